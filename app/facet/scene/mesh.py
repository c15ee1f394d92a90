"""Triangle meshes as numpy arrays (object space), independent of any GL state.

A ``Mesh`` holds ``positions`` (N, 3) float32, ``normals`` (N, 3) float32 (unit length),
``uvs`` (N, 2) float32 or None, and ``faces`` (F, 3) uint32 indices, counter-clockwise seen
from outside. Arrays are read-only after construction so a renderer can cache their upload by
object identity.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


def smooth_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals, (N, 3) float32.

    Each face adds its unnormalised cross product (|cross| = 2 x area) to its three vertices,
    summed with ``np.bincount`` (no Python loop over vertices; the sums run in float64).
    Vertices used by no face, or whose normals cancel, get +z.
    """
    p = np.asarray(positions, dtype=np.float32)
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    face_n = np.cross(b - a, c - a)
    n = np.zeros((len(p), 3))
    for corner in range(3):
        for k in range(3):
            n[:, k] += np.bincount(faces[:, corner], face_n[:, k], minlength=len(p))
    length = np.linalg.norm(n, axis=1)
    ok = length > 0
    n[ok] /= length[ok, None]
    n[~ok] = (0.0, 0.0, 1.0)
    return n.astype(np.float32)


class Mesh:
    """An indexed triangle mesh in object space.

    Parameters
    ----------
    positions : (N, 3) array of finite floats
    faces : (F, 3) integer indices into positions, F >= 1
    normals : (N, 3) optional; computed (area-weighted, smooth) when omitted
    uvs : (N, 2) optional texture coordinates
    colors : (N, 3|4) optional per-vertex colours, floats in [0, 1] (or uint8 0..255)
    name : label used in messages
    material : the ``Material`` the file defined, if any (``Scene.add`` uses it by default)
    """

    def __init__(self, positions, faces, normals=None, uvs=None, *, name: str = "mesh",
                 material=None, colors=None):
        self.name = name
        pos = np.asarray(positions, dtype=np.float32)
        if pos.ndim != 2 or pos.shape[1] != 3:
            raise InputError(f"{name}: positions must have shape (N, 3), got {pos.shape}")
        fac = np.asarray(faces)
        if fac.ndim != 2 or fac.shape[1] != 3:
            raise InputError(f"{name}: faces must have shape (F, 3), got {fac.shape}")
        if len(fac) == 0:
            raise InputError(f"{name}: the mesh has no faces")
        if not np.issubdtype(fac.dtype, np.integer):
            raise InputError(f"{name}: faces must be integer indices, got {fac.dtype}")
        if fac.min() < 0 or fac.max() >= len(pos):
            raise InputError(f"{name}: face indices must be in [0, {len(pos) - 1}], "
                             f"got [{fac.min()}, {fac.max()}]")
        bad = ~np.isfinite(pos).all(axis=1)
        if bad.any():
            raise InputError(f"{name}: {int(bad.sum())} vertices are NaN or infinite "
                             f"(first at index {int(np.argmax(bad))})")
        fac = fac.astype(np.uint32)
        if normals is None:
            nrm = smooth_normals(pos, fac)
        else:
            nrm = np.asarray(normals, dtype=np.float32)
            if nrm.shape != pos.shape:
                raise InputError(f"{name}: normals must match positions {pos.shape}, "
                                 f"got {nrm.shape}")
            length = np.linalg.norm(nrm, axis=1, keepdims=True)
            if not np.all(np.isfinite(length)) or np.any(length == 0):
                nrm = smooth_normals(pos, fac)  # broken normals in the file: recompute
            else:
                nrm = nrm / length
        uv = None
        if uvs is not None:
            uv = np.asarray(uvs, dtype=np.float32)
            if uv.shape != (len(pos), 2):
                raise InputError(f"{name}: uvs must have shape ({len(pos)}, 2), got {uv.shape}")
        col = None
        if colors is not None:
            col = np.asarray(colors)
            if col.dtype == np.uint8:
                col = col / 255.0
            col = col.astype(np.float32)
            if col.ndim != 2 or col.shape[0] != len(pos) or col.shape[1] not in (3, 4):
                raise InputError(f"{name}: colors must have shape ({len(pos)}, 3|4), got "
                                 f"{col.shape}")
            if not np.all(np.isfinite(col)) or col.min() < 0 or col.max() > 1:
                raise InputError(f"{name}: vertex colours must be in [0, 1]")
            if col.shape[1] == 3:
                col = np.hstack([col, np.ones((len(col), 1), np.float32)])
        self.colors = None if col is None else _readonly(col)
        self.positions = _readonly(pos)
        self.faces = _readonly(fac)
        self.normals = _readonly(nrm.astype(np.float32))
        self.uvs = None if uv is None else _readonly(uv)
        self.material = material

    @classmethod
    def load(cls, path, *, flat: bool = False) -> Mesh:
        """Read a mesh file (OBJ, STL, PLY, OFF, GLB/glTF, ...) through trimesh.

        A file with several parts is merged into one mesh, each part placed by its node
        transform. ``flat=True`` gives faceted normals (see ``flat_shaded``). Raises
        ``facet.MeshError`` naming the file when it cannot be read.
        """
        from .loading import load_mesh

        mesh = cls._from_file(load_mesh(path))
        return mesh.flat_shaded() if flat else mesh

    @classmethod
    def load_parts(cls, path) -> list[tuple[str, Mesh, np.ndarray]]:
        """The parts of a mesh file as (node name, mesh, 4x4 node -> file transform): a
        glTF keeps its nodes (a mesh used by several nodes is made once), other formats
        give one part with the identity."""
        from .loading import load_parts

        made: dict[int, Mesh] = {}
        parts = []
        for name, data, matrix in load_parts(path):
            if id(data) not in made:
                made[id(data)] = cls._from_file(data)
            parts.append((name, made[id(data)], matrix))
        return parts

    @classmethod
    def _from_file(cls, data: dict) -> Mesh:
        """A Mesh from facet.scene.loading's arguments; a bad array names the file."""
        from ..errors import MeshError

        args = dict(data)
        path = args.pop("path")
        try:
            return cls(**args)
        except InputError as exc:
            raise MeshError(f"{path}: {exc}") from None

    @property
    def vertex_count(self) -> int:
        return len(self.positions)

    @property
    def face_count(self) -> int:
        return len(self.faces)

    @property
    def bounds(self) -> np.ndarray:
        """Axis-aligned bounds of the vertices, (2, 3) float64: min, max."""
        return np.stack([self.positions.min(axis=0),
                         self.positions.max(axis=0)]).astype(np.float64)

    def flat_shaded(self) -> Mesh:
        """A copy with one vertex per face corner and the face's geometric normal on each."""
        tri = self.positions[self.faces].astype(np.float64)  # (F, 3, 3)
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        length = np.linalg.norm(n, axis=1, keepdims=True)
        n = np.where(length > 0, n / np.where(length > 0, length, 1), (0.0, 0.0, 1.0))
        faces = np.arange(3 * self.face_count, dtype=np.uint32).reshape(-1, 3)
        uvs = None if self.uvs is None else self.uvs[self.faces].reshape(-1, 2)
        colors = None if self.colors is None else self.colors[self.faces].reshape(-1, 4)
        return Mesh(tri.reshape(-1, 3), faces, np.repeat(n, 3, axis=0), uvs,
                    name=self.name, material=self.material, colors=colors)

    def __repr__(self) -> str:
        return f"Mesh({self.name!r}, vertices={self.vertex_count}, faces={self.face_count})"
