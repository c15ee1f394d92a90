"""The one loader of mesh files: path -> parts (each its own mesh, material and node
transform) and named cameras, used by every front (CLI, viewer, scene files, ``Mesh.load``,
``facet.load``). Returns plain arrays so that it needs nothing from facet.scene.mesh.

* glTF / GLB: facet.formats.gltf (pygltflib + numpy): per-primitive parts with PbrMaterial,
  both uv sets, tangents, vertex colours, node transforms, cameras.
* OpenUSD (.usd, .usda, .usdc, .usdz): facet.formats.usd (pxr, the ``usd`` extra): the
  composed stage's meshes, gprims (exact shapes), points, curves, materials, lights and
  cameras.
* URDF robots (.urdf): facet.formats.urdf (yourdfpy, the ``urdf`` extra): each link's
  visual (or collision) geometry placed by the joint configuration.
* OBJ, STL, PLY, OFF, COLLADA (.dae, with pycollada: the ``urdf`` extra): trimesh. An
  OBJ keeps one part per material (MTL: C = Kd, k_d = 1,
  k_s = mean(Ks), n = Ns, k_a = 1, map_Kd the texture); a missing .mtl or texture loads
  without it and says so in one warning line. PLY faces stored as triangle strips load.

Normals: a file's own normals are used as they are. Without them, vertices are split at
edges sharper than the crease angle (facet.scene.normals; default 60 degrees, 180 = all
smooth), so a cube is a cube and a sphere stays smooth. Per-vertex colours (PLY, OBJ's
``v x y z r g b``, glTF COLOR_0) become ``colors``. Every failure (missing file, a
directory, an unknown extension, a parse error, no faces, only degenerate triangles,
NaN/inf vertices) is one ``MeshError`` naming the file and what to do.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError, MeshError
from ..scene.mesh import Mesh
from ..scene.normals import DEFAULT_CREASE, crease_normals, face_normals
from ..scene.points import Lines, Points
from .trimesh_files import FORMATS, trimesh_file_parts
from .usd_stage import USD_SUFFIXES

if TYPE_CHECKING:
    from ..scene.animation import Rig

POINT_FORMATS = (".xyz", ".pts", ".pcd")  # point clouds facet reads itself
PER_VERTEX = ("positions", "normals", "uvs", "uvs1", "tangents", "colors")
FACE_SAMPLE = 4096  # triangles looked at first for one with area (_finish)


def _check_path(path) -> Path:
    from ..guard import regular_file

    p = regular_file(path, "mesh file", MeshError, missing="file")
    ext = p.suffix.lower().lstrip(".")
    if ext not in FORMATS and f".{ext}" not in USD_SUFFIXES and ext != "urdf":
        known = ", ".join([*(f".{e}" for e in FORMATS), *USD_SUFFIXES, ".urdf"])
        raise MeshError(f"{p}: unknown mesh format '{p.suffix or '(none)'}'; use one of {known}")
    if not os.access(p, os.R_OK):
        raise MeshError(f"{p}: permission denied")
    if p.stat().st_size == 0:
        raise MeshError(f"{p}: the file is empty")
    return p


def load_file(path, crease: float = DEFAULT_CREASE, usd=None,
              urdf: dict | None = None) -> tuple[list, dict, list, object]:
    """``(parts, cameras, lights, rig)`` of a mesh file: parts as (name, ``Mesh`` keyword
    arguments, 4x4 node -> file transform), a part's arguments shared by every node that
    uses the same mesh; cameras as {name: Camera}, lights and the Rig of its animations,
    skins and morph targets (glTF only; facet.scene.animation; None when nothing moves).
    ``usd``: facet.formats.usd.UsdOptions for a stage (variants, payloads, purposes,
    time); a stage's lights may hold its dome as an Environment. ``urdf``: a robot's
    ``joints``, ``package_path`` and ``collision`` (facet.formats.urdf)."""
    p = _check_path(path)
    crease = _check_crease(crease)

    def finish(arrays: dict, where: str) -> dict:
        return _finish(arrays, p, where, crease)

    if p.suffix.lower() in (".gltf", ".glb"):
        from .gltf import read_gltf

        return read_gltf(p, finish)
    if p.suffix.lower() in USD_SUFFIXES:
        from .usd import read_usd

        return read_usd(p, finish, usd)
    if p.suffix.lower() == ".urdf":
        from .urdf import read_urdf

        return read_urdf(p, load_file, crease, **(urdf or {}))
    if p.suffix.lower() in POINT_FORMATS:
        from .point_files import read_pcd, read_text_points

        read = read_pcd if p.suffix.lower() == ".pcd" else read_text_points
        return [(p.stem, finish(read(p), ""), np.eye(4))], {}, [], None
    return trimesh_file_parts(p, finish), {}, [], None


def _check_crease(crease) -> float:
    from ..errors import InputError

    if not (isinstance(crease, (int, float)) and 0 <= crease <= 180):
        raise InputError(f"crease angle must be in [0, 180] degrees (180: fully smooth), got "
                         f"{crease!r}")
    return float(crease)


def _finish(arrays: dict, p: Path, where: str, crease: float) -> dict:
    """Checked ``Mesh`` arguments: finite positions, faces in range, some triangle with
    area, normals split at creases when the file has none. Points and lines (``kind``):
    finite positions within float32's reach. A reader's own ``crease`` (a USD mesh's
    subdivision scheme decides its normals) comes before the loader's."""
    crease = float(arrays.pop("crease", crease))
    vertices = np.asarray(arrays["positions"])
    if vertices.dtype not in (np.float32, np.float64):
        vertices = vertices.astype(np.float64)
    if arrays.get("kind") in ("points", "lines"):
        return _finish_sprites(arrays, vertices, p, where)
    faces = np.asarray(arrays["faces"]).reshape(-1, 3)
    if faces.dtype.kind not in "iu":
        faces = faces.astype(np.int64)
    at = f"{p}: {where}: " if where else f"{p}: "
    if len(faces) == 0:
        raise MeshError(f"{at}the mesh has 0 faces; nothing to render")
    if not np.isfinite(vertices).all():
        bad = int((~np.isfinite(vertices).all(axis=1)).sum())
        raise MeshError(f"{at}{bad} vertices are NaN or infinite; fix or remove them")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise MeshError(f"{at}faces refer to vertices that do not exist; the file is corrupt")
    from ..scene.normals import MAX_COORDINATE

    reach = max(-float(vertices.min()), float(vertices.max()))
    huge = np.abs(vertices).max(axis=1) > MAX_COORDINATE if reach > MAX_COORDINATE else None
    if huge is not None:  # before any arithmetic on them: squares would overflow
        raise MeshError(f"{at}{int(huge.sum())} vertices lie beyond {MAX_COORDINATE:g} "
                        f"(the first is vertex {int(np.argmax(huge))}); GPU arithmetic is "
                        "float32 and squares of such coordinates overflow: scale the model "
                        "down")
    normals = arrays.get("normals")
    if normals is not None and (len(normals) != len(vertices) or
                                not np.all(np.einsum("ij,ij->i", normals, normals) > 0)):
        normals = None  # missing or broken normals in the file: compute them
    # Some triangle must have area: the first few thousand usually show one (all of them
    # are computed only when they do not, or when the normals are computed anyway).
    face_n = area2 = None
    if normals is not None:
        _, some = face_normals(vertices, faces[:FACE_SAMPLE])
        if not np.any(some > 0):
            face_n, area2 = face_normals(vertices, faces)
    else:
        face_n, area2 = face_normals(vertices, faces)
    if area2 is not None and not np.any(area2 > 0):
        raise MeshError(f"{at}all {len(faces)} triangles have zero area (degenerate); "
                        "nothing to render")
    out = dict(arrays, positions=vertices.astype(np.float32, copy=False), faces=faces,
               path=str(p), checked=True)
    if normals is None:
        vertices, faces = vertices.astype(np.float64), faces.astype(np.int64)
        extra = [np.asarray(out[k], dtype=np.float64).reshape(len(vertices), -1)
                 for k in ("uvs", "uvs1", "colors", "tangents") if out.get(k) is not None]
        found: dict = {}
        source, new_faces, out["normals"] = crease_normals(
            vertices, faces, crease, np.hstack(extra) if extra else None, face_n, found)
        if "closed" in found and not np.any(area2 <= 0):
            out["closed"] = found["closed"]  # learnt on the way: Mesh.closed need not sort
        for key in PER_VERTEX:
            if key != "normals" and out.get(key) is not None:
                out[key] = np.asarray(out[key])[source]
        if out.get("deform") is not None:  # skin and morph data follow their vertices
            out["deform"] = out["deform"].remapped(source)
        if out.get("scalars"):
            out["scalars"] = {k: v[source] for k, v in out["scalars"].items()}
        out["faces"] = new_faces
    return out


def _finish_sprites(arrays: dict, vertices: np.ndarray, p: Path, where: str) -> dict:
    from ..scene.normals import MAX_COORDINATE

    at = f"{p}: {where}: " if where else f"{p}: "
    if len(vertices) == 0:
        raise MeshError(f"{at}holds no points; nothing to render")
    keep = np.isfinite(vertices).all(axis=1)
    if not keep.all():
        raise MeshError(f"{at}{int((~keep).sum())} points are NaN or infinite; fix or remove "
                        "them")
    huge = np.abs(vertices).max(axis=1) > MAX_COORDINATE
    if huge.any():
        raise MeshError(f"{at}{int(huge.sum())} points lie beyond {MAX_COORDINATE:g}; GPU "
                        "arithmetic is float32: scale the model down")
    return dict(arrays, positions=vertices.astype(np.float32), path=str(p))


def read_parts(path, crease: float | None = None, usd=None,
               urdf: dict | None = None) -> tuple[list, dict, list, Rig | None]:
    """The parts of a mesh file as scene objects, its cameras, its lights (glTF's
    KHR_lights_punctual) and its rig: ([(name, Mesh | Points | Lines, (4, 4) part -> file)],
    {name: Camera}, [lights], facet.scene.animation.Rig or None when nothing in it moves,
    whose part ``i`` is ``parts[i]`` at rest). A glTF keeps its nodes and primitives (a mesh
    used by several nodes is made once), an OBJ one part per material, other formats one
    part. What ``Mesh.load`` and ``Mesh.load_parts`` read (facet.scene.readers)."""
    raw, cameras, lights, rig = load_file(path, DEFAULT_CREASE if crease is None else crease,
                                          usd, urdf)
    made: dict[int, object] = {}
    parts = []
    for name, data, matrix in raw:
        if id(data) not in made:
            made[id(data)] = _part(data)
        parts.append((name, made[id(data)], matrix))
    return parts, cameras, lights, rig


def _part(data: dict):
    """A Mesh (or Points, Lines) from ``load_file``'s arguments; a bad array names the
    file."""
    args = dict(data)
    path = args.pop("path")
    args.pop("deform", None)  # the rig's (facet.scene.animation)
    kind = args.pop("kind", "mesh")
    if kind == "shape":  # an exact shape (facet.scene.shapes; a capsule is a mesh)
        return _shape(args, path)
    try:
        if kind != "mesh":  # a point cloud or lines (facet.scene.points)
            return (Points if kind == "points" else Lines)(**args)
        return Mesh(**args)
    except InputError as exc:
        raise MeshError(f"{path}: {exc}") from None


def _shape(args: dict, path: str):
    """A facet shape (or a capsule's mesh) of a reader's ``shape`` and ``params``."""
    from ..scene import primitives as P
    from ..scene import shapes as S

    kind, params, material = args["shape"], tuple(args["params"]), args.get("material")
    try:
        if kind == "capsule":
            mesh = P.capsule(*params)
            mesh.material = material
            return mesh
        shape = {"box": lambda x, y, z: S.Box((x, y, z)), "sphere": S.Sphere,
                 "cylinder": S.Cylinder, "cone": S.Cone,
                 "plane": lambda w, d: S.Plane((w, d))}[kind](*params)
    except InputError as exc:
        raise MeshError(f"{path}: {args.get('name', kind)}: {exc}") from None
    shape.material = material
    return shape
