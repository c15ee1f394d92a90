"""Triangle meshes as numpy arrays (object space), independent of any GL state.

A ``Mesh`` holds ``positions`` (N, 3) float32, ``normals`` (N, 3) float32 (unit length),
``uvs`` (N, 2) float32 or None (OpenGL's convention: v = 0 is the image's bottom row), an
optional second set ``uvs1``, optional ``tangents`` (N, 4) (xyz and handedness, as glTF),
optional ``colors`` (N, 4) (sRGB-encoded, as displayed), and ``faces`` (F, 3) uint32
indices, counter-clockwise seen from outside. Arrays are read-only after construction so a
renderer can cache their upload by object identity.
"""

from __future__ import annotations

import warnings
from typing import Annotated

import numpy as np

from ..boundary import Array, ArrayLike, Crease, FilePath, checked
from ..errors import FacetWarning, InputError
from ..geometry import transforms as T
from .normals import (
    MAX_COORDINATE,  # beyond it float32 squares overflow
    closed_surface,
    smooth_normals,
    weld_key,
)
from .readers import reader  # facet.formats reads the files


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


class Mesh:
    """An indexed triangle mesh in object space (``kind`` "mesh"; facet.scene.points holds
    the others).

    Parameters
    ----------
    positions : (N, 3) array of finite floats
    faces : (F, 3) integer indices into positions, F >= 1
    normals : (N, 3) optional; computed (area-weighted, smooth) when omitted
    uvs : (N, 2) optional texture coordinates
    colors : (N, 3|4) optional per-vertex colours, floats in [0, 1] (or uint8 0..255)
    uvs1 : (N, 2) optional second texture coordinate set (glTF TEXCOORD_1)
    tangents : (N, 4) optional tangent frames (computed from the uvs when a normal map
        needs them and they are absent; facet.scene.normals.tangents)
    closed : whether the surface is closed and consistently wound, when the caller knows
        (a loader that sorted the edges); else found out when first asked
    name : label used in messages
    material : the ``Material`` the file defined, if any (``Scene.add`` uses it by default)
    variants : {variant name: Material}, the file's material variants
        (KHR_materials_variants; the ``variant`` render option picks one)
    scalars : {name: (N,) floats} per-vertex scalars (a PLY's own properties)
    """

    kind = "mesh"

    @checked
    def __init__(self, positions: Annotated[ArrayLike, Array("N,3")],
                 faces: Annotated[ArrayLike, Array("F,3", finite=False)],
                 normals: Annotated[ArrayLike | None, Array("N,3", finite=False)] = None,
                 uvs: Annotated[ArrayLike | None, Array("N,2")] = None, *,
                 name: str = "mesh", material=None,
                 colors: Annotated[ArrayLike | None, Array("N,3", "N,4")] = None,
                 uvs1: Annotated[ArrayLike | None, Array("N,2")] = None,
                 tangents: Annotated[ArrayLike | None, Array("N,4")] = None,
                 closed: bool | None = None, variants: dict | None = None,
                 checked: bool = False, scalars: dict | None = None):
        self.name = name
        self.variants = variants
        # {name: (N,) float32} per-vertex scalars a file carried (PLY properties), for
        # colormaps (``colored_by``)
        self.scalars = scalars or {}
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
        if not checked:  # (``checked``: facet.formats.loading checked these already)
            self._check(pos, fac, name)
        fac = fac.astype(np.uint32, copy=False)
        if normals is None:
            nrm = smooth_normals(pos, fac)
        else:
            nrm = np.asarray(normals, dtype=np.float32)
            if nrm.shape != pos.shape:
                raise InputError(f"{name}: normals must match positions {pos.shape}, "
                                 f"got {nrm.shape}")
            length = np.sqrt(np.einsum("ij,ij->i", nrm, nrm))[:, None]
            if not np.all(np.isfinite(length)) or np.any(length == 0):
                nrm = smooth_normals(pos, fac)  # broken normals in the file: recompute
            else:
                nrm = nrm / length
        uv, uv1 = (self._per_vertex(v, 2, key, name, len(pos))
                   for v, key in ((uvs, "uvs"), (uvs1, "uvs1")))
        tan = self._per_vertex(tangents, 4, "tangents", name, len(pos))
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
        self.uvs1 = None if uv1 is None else _readonly(uv1)
        self._tangents = None if tan is None else _readonly(tan)
        self.material = material
        self._closed = closed  # None: found out when first asked (``closed``)

    @staticmethod
    def _check(pos: np.ndarray, fac: np.ndarray, name: str) -> None:
        """Faces in range; positions finite and within float32's reach."""
        if fac.min() < 0 or fac.max() >= len(pos):
            raise InputError(f"{name}: face indices must be in [0, {len(pos) - 1}] (rows of "
                             f"positions), got [{fac.min()}, {fac.max()}]")
        bad = ~np.isfinite(pos).all(axis=1)
        if bad.any():
            raise InputError(f"{name}: {int(bad.sum())} vertices are NaN or infinite "
                             f"(first at index {int(np.argmax(bad))})")
        huge = np.abs(pos).max(axis=1) > MAX_COORDINATE
        if huge.any():
            raise InputError(f"{name}: {int(huge.sum())} vertices lie beyond "
                             f"{MAX_COORDINATE:g} (first at index {int(np.argmax(huge))}); "
                             "GPU arithmetic is float32 and squares of such coordinates "
                             "overflow: scale the model down")

    @staticmethod
    def _per_vertex(values, width: int, key: str, name: str, n: int):
        if values is None:
            return None
        v = np.asarray(values, dtype=np.float32)
        if v.shape != (n, width):
            raise InputError(f"{name}: {key} must have shape ({n}, {width}), got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise InputError(f"{name}: {key} must be finite")
        return v

    @property
    def tangents(self) -> np.ndarray | None:
        """(N, 4) float32 tangent frames: the mesh's own, else computed from ``uvs`` once
        (None without uvs)."""
        if self._tangents is None and self.uvs is not None:
            from .normals import tangents

            self._tangents = _readonly(tangents(self.positions, self.normals, self.uvs,
                                                self.faces))
        return self._tangents

    @classmethod
    @checked
    def load(cls, path: FilePath, *, flat: bool = False, crease: Crease = None) -> Mesh:
        """Read a mesh file (OBJ, STL, PLY, OFF, glTF/GLB) as one mesh.

        A file of several parts is merged, each placed by its node transform, with the first
        part's material (a warning says so when the parts' materials differ: ``facet.open_scene``
        or ``Mesh.load_parts`` keep them apart). Skinned and morphed parts stand in their rest
        pose with default weights.

        Parameters
        ----------
        path : str or Path
            The file.
        flat : bool
            Faceted normals (see ``flat_shaded``).
        crease : float, optional
            Where a file has no normals, split them at edges sharper than this many degrees
            (default facet.scene.normals.DEFAULT_CREASE).

        Returns
        -------
        Mesh
            The mesh, with the file's material as ``material``.

        Raises
        ------
        facet.MeshError
            When the file cannot be read (the message names it).
        """
        parts, _, _, rig = reader("mesh file")(path, crease)
        if rig is not None:  # skins and default morph weights applied, nothing playing
            placed, _ = rig.posed_meshes([m for _, m, _ in parts], 0.0, rig.NO_CLIPS)
            parts = [(n, m if isinstance(m, Mesh) or m.kind != "mesh" else Mesh(
                m.positions, m.faces, m.normals, m.uvs, name=m.name, material=m.material,
                colors=m.colors, uvs1=m.uvs1, tangents=m._tangents, variants=m.variants),
                x) for (n, _, _), (m, x) in zip(parts, placed, strict=True)]
        # (an exact shape has parameters and makes its own mesh: facet.scene.shapes)
        parts = [(n, _tessellated(m) if hasattr(m, "params") else m, x) for n, m, x in parts]
        meshes = [part for part in parts if part[1].kind == "mesh"]
        if not meshes:
            from ..errors import MeshError

            raise MeshError(f"{path}: holds {parts[0][1].kind}, not triangles; open it with "
                            "facet.load (a scene that draws them) or facet.Points")
        if len(meshes) < len(parts):
            warnings.warn(f"{path}: Mesh.load keeps the triangles and leaves out its points "
                          "and lines (facet.load keeps them)", FacetWarning, stacklevel=2)
            parts = meshes
        mesh = parts[0][1] if len(parts) == 1 and np.array_equal(parts[0][2], np.eye(4)) \
            else merge_parts(parts, str(path))
        return mesh.flat_shaded() if flat else mesh

    @checked
    def colored_by(self, values: Annotated[ArrayLike, Array("N")], colormap: str = "viridis",
                   limits: Annotated[ArrayLike | None, Array("2")] = None) -> Mesh:
        """A copy coloured by per-vertex scalars through a colormap.

        Its material turns white (its other properties kept), so the colours show as the
        colormap gives them.

        Parameters
        ----------
        values : (N,) float
            One value per vertex (NaN shows grey).
        colormap : str
            A colormap name (facet.scene.colormap: matplotlib's when installed; viridis,
            coolwarm and gray built in).
        limits : (float, float), optional
            The values mapped to the colormap's ends (default: the values' range).

        Returns
        -------
        Mesh
            The coloured copy.
        """
        from dataclasses import replace

        from .colormap import colors_for, scalars
        from .material import Material
        from .pbr import PbrMaterial

        v = scalars(values, f"{self.name}: colored_by values")
        if len(v) != self.vertex_count:
            raise InputError(f"{self.name}: values: {len(v)} scalars for {self.vertex_count} "
                             "vertices")
        return Mesh(self.positions, self.faces, self.normals, self.uvs, name=self.name,
                    material=Material(color=np.ones(3)) if self.material is None else
                    replace(self.material, base_color=np.array(
                        [1.0, 1.0, 1.0, self.material.base_color[3]]), base_color_texture=None)
                    if isinstance(self.material, PbrMaterial) else
                    replace(self.material, color=np.ones(3), texture=None),
                    colors=colors_for(v, colormap, limits), uvs1=self.uvs1,
                    tangents=self._tangents, closed=self._closed, checked=True,
                    scalars=self.scalars)

    @classmethod
    def from_trimesh(cls, tm) -> Mesh:
        """A Mesh of a trimesh geometry: its vertices, faces, normals (when it has them),
        texture coordinates, vertex or face colours and material (facet.formats.adapters).

        Parameters
        ----------
        tm : trimesh.Trimesh or trimesh.Scene
            The geometry; a Scene's parts are merged, each placed by its graph (``Scene.add``
            keeps them apart).

        Returns
        -------
        Mesh
            The mesh.
        """
        parts = [(n, m, x) for n, m, x in reader("trimesh")(tm, cls) if m.kind == "mesh"]
        if not parts:
            raise InputError(f"{type(tm).__name__} holds no triangles (a point cloud: "
                             "Scene.add or facet.Points take it)")
        if len(parts) == 1 and np.array_equal(parts[0][2], np.eye(4)):
            return parts[0][1]
        return merge_parts(parts, type(tm).__name__)

    @classmethod
    @checked
    def load_parts(cls, path: FilePath, *, crease: Crease = None) -> list[tuple[str, Mesh,
                                                                             np.ndarray]]:
        """The parts of a mesh file, each with its own material: a glTF keeps its nodes and
        primitives (a mesh used by several nodes is made once), an OBJ one part per material,
        other formats one part.

        Parameters
        ----------
        path : str or Path
            The file.
        crease : float, optional
            Where a file has no normals, split them at edges sharper than this many degrees
            (default facet.scene.normals.DEFAULT_CREASE).

        Returns
        -------
        list of (str, Mesh | Points | Lines, (4, 4) float64 ndarray)
            Each part's name, geometry (with its own material) and part -> file transform.
        """
        return reader("mesh file")(path, crease)[0]

    @property
    def vertex_count(self) -> int:
        return len(self.positions)

    @property
    def face_count(self) -> int:
        return len(self.faces)

    @property
    def bounds(self) -> np.ndarray:
        """Axis-aligned bounds of the vertices, (2, 3) float64: min, max (computed once:
        the arrays are read-only)."""
        if getattr(self, "_bounds", None) is None:
            b = np.stack([self.positions.min(axis=0), self.positions.max(axis=0)])
            self._bounds = b.astype(np.float64)
            self._bounds.setflags(write=False)
        return self._bounds

    @property
    def closed(self) -> bool:
        """Whether the surface is closed and consistently wound: every edge is shared by
        exactly two triangles that run along it in opposite directions (degenerate
        triangles aside). Vertices at the same position count as one, so texture seams do
        not open it. Then no back face can be seen from outside (facet.render.raster.culling).
        Computed once."""
        if getattr(self, "_closed", None) is None:
            faces = self.faces.astype(np.int64)
            closed = closed_surface(faces, len(self.positions))
            if not closed:  # perhaps only split at seams: weld positions and retry
                closed = closed_surface(weld_key(self.positions)[faces], len(self.positions))
            self._closed = closed
        return bool(self._closed)

    def flat_shaded(self) -> Mesh:
        """A copy with one vertex per face corner and each face's geometric normal.

        Returns
        -------
        Mesh
            The faceted copy (colours, uvs and scalars follow their corners).
        """
        tri = self.positions[self.faces].astype(np.float64)  # (F, 3, 3)
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        length = np.linalg.norm(n, axis=1, keepdims=True)
        n = np.where(length > 0, n / np.where(length > 0, length, 1), (0.0, 0.0, 1.0))
        faces = np.arange(3 * self.face_count, dtype=np.uint32).reshape(-1, 3)
        uvs = None if self.uvs is None else self.uvs[self.faces].reshape(-1, 2)
        colors = None if self.colors is None else self.colors[self.faces].reshape(-1, 4)
        uvs1 = None if self.uvs1 is None else self.uvs1[self.faces].reshape(-1, 2)
        corners = self.faces.reshape(-1)
        return Mesh(tri.reshape(-1, 3), faces, np.repeat(n, 3, axis=0), uvs,
                    name=self.name, material=self.material, colors=colors, uvs1=uvs1,
                    variants=self.variants,
                    scalars={k: v[corners] for k, v in self.scalars.items()})

    def __repr__(self) -> str:
        return f"Mesh({self.name!r}, vertices={self.vertex_count}, faces={self.face_count})"


def _tessellated(shape) -> Mesh:
    """A file's exact shape (facet.scene.shapes: a USD gprim, a URDF box) as its own mesh,
    with the shape's material."""
    t = shape.mesh()
    return Mesh(t.positions, t.faces, t.normals, t.uvs, name=shape.kind,
                material=shape.material)


def merge_parts(parts, label: str):
    """One ``Mesh`` of ``parts`` [(name, mesh, 4x4 part -> file)], with the first part's
    material; warns when the parts' materials differ."""
    meshes = [m for _, m, _ in parts]
    materials = {id(m.material) for m in meshes}
    if len(materials) > 1:
        warnings.warn(f"{label}: Mesh.load merges {len(parts)} parts with {len(materials)} "
                      "materials into one mesh with the first material; facet.open_scene "
                      "or Mesh.load_parts keeps them apart", FacetWarning, stacklevel=3)
    positions, normals, faces, offset = [], [], [], 0
    for _, mesh, matrix in parts:
        positions.append(T.transform_points(matrix, mesh.positions))
        n = mesh.normals @ T.normal_matrix(matrix).T
        normals.append(n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30))
        flip = np.linalg.det(matrix[:3, :3]) < 0  # a mirroring node turns the winding
        f = mesh.faces[:, ::-1] if flip else mesh.faces
        faces.append(f.astype(np.int64) + offset)
        offset += mesh.vertex_count

    def joined(key: str, fill=None):
        arrays = [getattr(m, key) for m in meshes]
        if all(a is None for a in arrays) or (fill is None and any(a is None for a in arrays)):
            return None
        return np.concatenate([np.tile(fill, (m.vertex_count, 1)) if a is None else a
                               for a, m in zip(arrays, meshes, strict=True)])

    return Mesh(np.concatenate(positions), np.concatenate(faces), np.concatenate(normals),
                joined("uvs"), name=meshes[0].name, material=meshes[0].material,
                colors=joined("colors", np.ones(4, np.float32)), uvs1=joined("uvs1"))
