"""The one loader of mesh files: path -> parts (each its own mesh, material and node
transform) and named cameras, used by every front (CLI, viewer, scene files, ``Mesh.load``,
``facet.load``). Returns plain arrays so that it needs nothing from facet.scene.mesh.

* glTF / GLB: facet.formats.gltf (pygltflib + numpy): per-primitive parts with PbrMaterial,
  both uv sets, tangents, vertex colours, node transforms, cameras.
* OBJ, STL, PLY, OFF: trimesh. An OBJ keeps one part per material (MTL: C = Kd, k_d = 1,
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
import re
import warnings
from pathlib import Path

import numpy as np

from ..errors import FacetError, FacetWarning, MeshError
from ..scene.material import Material
from ..scene.normals import DEFAULT_CREASE, crease_normals, face_normals
from ..scene.texture import Texture

# Extensions we accept (lower case, no dot) and the trimesh file_type for each.
FORMATS = {"obj": "obj", "stl": "stl", "ply": "ply", "off": "off", "glb": "glb",
           "gltf": "gltf", "xyz": "xyz", "pts": "pts", "pcd": "pcd"}
POINT_FORMATS = (".xyz", ".pts", ".pcd")  # point clouds facet reads itself
PER_VERTEX = ("positions", "normals", "uvs", "uvs1", "tangents", "colors")
FACE_SAMPLE = 4096  # triangles looked at first for one with area (_finish)


def _check_path(path) -> Path:
    from ..guard import regular_file

    p = regular_file(path, "mesh file", MeshError, missing="file")
    ext = p.suffix.lower().lstrip(".")
    if ext not in FORMATS:
        known = ", ".join(f".{e}" for e in FORMATS)
        raise MeshError(f"{p}: unknown mesh format '{p.suffix or '(none)'}'; use one of {known}")
    if not os.access(p, os.R_OK):
        raise MeshError(f"{p}: permission denied")
    if p.stat().st_size == 0:
        raise MeshError(f"{p}: the file is empty")
    return p


def load_file(path, crease: float = DEFAULT_CREASE) -> tuple[list, dict, list, object]:
    """``(parts, cameras, lights, rig)`` of a mesh file: parts as (name, ``Mesh`` keyword
    arguments, 4x4 node -> file transform), a part's arguments shared by every node that
    uses the same mesh; cameras as {name: Camera}, lights and the Rig of its animations,
    skins and morph targets (glTF only; facet.scene.animation; None when nothing moves)."""
    p = _check_path(path)
    crease = _check_crease(crease)

    def finish(arrays: dict, where: str) -> dict:
        return _finish(arrays, p, where, crease)

    if p.suffix.lower() in (".gltf", ".glb"):
        from .gltf import read_gltf

        return read_gltf(p, finish)
    if p.suffix.lower() in POINT_FORMATS:
        from .point_files import read_pcd, read_text_points

        read = read_pcd if p.suffix.lower() == ".pcd" else read_text_points
        return [(p.stem, finish(read(p), ""), np.eye(4))], {}, [], None
    return _trimesh_parts(p, finish), {}, [], None


def _check_crease(crease) -> float:
    from ..errors import InputError

    if not (isinstance(crease, (int, float)) and 0 <= crease <= 180):
        raise InputError(f"crease angle must be in [0, 180] degrees (180: fully smooth), got "
                         f"{crease!r}")
    return float(crease)


def _finish(arrays: dict, p: Path, where: str, crease: float) -> dict:
    """Checked ``Mesh`` arguments: finite positions, faces in range, some triangle with
    area, normals split at creases when the file has none. Points and lines (``kind``):
    finite positions within float32's reach."""
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


# -- trimesh formats ------------------------------------------------------------------------
def _read(p: Path):
    """trimesh's object for a checked path (a Trimesh, a Scene, or something else)."""
    import trimesh  # imported here: commands that load no mesh do not pay for it

    resolver = None
    if p.suffix.lower() == ".obj":
        _check_obj_indices(p)
        resolver = _guarded_resolver(p)
    try:
        loaded = trimesh.load(str(p), file_type=FORMATS[p.suffix.lower().lstrip(".")],
                              process=False, resolver=resolver)
    except FacetError:
        raise
    except Exception as exc:  # trimesh raises many types for bad files; report them as one
        if isinstance(exc, (UnicodeError, ImportError)):  # trimesh guessing at encodings
            detail = "not text in a known encoding: a binary file, or UTF-16?"
        else:
            detail = str(exc).strip().splitlines()[0] if str(exc).strip() else \
                type(exc).__name__
        raise MeshError(f"{p}: cannot read the file as {p.suffix.lower()} ({detail}); "
                        "is it truncated or in another format?") from None
    if getattr(resolver, "fatal", None):  # trimesh swallows what its resolver raises
        raise resolver.fatal[0]
    for name, problem in dict.fromkeys(getattr(resolver, "refused", ())):
        kind = "material library" if name.lower().endswith(".mtl") else "texture" if \
            Path(name).suffix.lower() in IMAGE_SUFFIXES else "file"
        warnings.warn(f"{p.name}: {kind} {name!r} {problem}; loaded without it", FacetWarning,
                      stacklevel=3)
    return loaded


def _guarded_resolver(p: Path):
    """A trimesh resolver that opens only regular files inside the model's folder (and
    the confinement folder, facet.guard), for whatever the model names (material
    libraries, textures: trimesh finds ``mtllib`` even in a comment). A missing one is
    listed in ``refused`` (the model loads without it, with one warning each); one that
    is not a regular file, outside the confinement folder or beyond a budget is a
    MeshError kept in ``fatal`` (raised once trimesh returns)."""
    import trimesh

    from ..guard import regular_file

    class Guarded(trimesh.resolvers.FilePathResolver):
        refused: list = []
        fatal: list = []

        def get(self, name: str) -> bytes:
            shown = name.strip()
            try:
                path = self.absolute(shown)
            except ValueError:
                self.refused.append((shown, f"outside {self.parent}"))
                raise FileNotFoundError(name) from None
            if not path.exists() and not path.is_symlink():
                self.refused.append((shown, f"not found in {path.parent}"))
                raise FileNotFoundError(name)
            try:
                return regular_file(path, f"file {p.name} names", MeshError).read_bytes()
            except MeshError as exc:
                self.fatal.append(exc)
                raise FileNotFoundError(name) from None

    resolver = Guarded(str(p))
    resolver.refused, resolver.fatal = [], []
    return resolver


IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tga", ".tif", ".tiff", ".gif", ".webp")

# A face line with an index that is exactly 0 (OBJ counts from 1; negative counts back).
_OBJ_ZERO_INDEX = re.compile(rb"^[ \t]*f[ \t][^\n]*?(?<![\w.+-])0+(?=[/ \t\r\n]|$)", re.M)


def _check_obj_indices(p: Path) -> None:
    """An OBJ face index 0 is invalid (indices count from 1); trimesh would read it as the
    last vertex. One pass of a regular expression over the file's bytes."""
    data = p.read_bytes()
    m = _OBJ_ZERO_INDEX.search(data)
    if m is not None:
        line = data.count(b"\n", 0, m.start()) + 1
        raise MeshError(f"{p}:{line}: a face refers to vertex 0, but OBJ counts vertices "
                        "from 1 (or back from -1); fix the file's face indices")


def _trimesh_parts(p: Path, finish) -> list:
    import trimesh

    loaded = _read(p)
    if p.suffix.lower() == ".ply":
        _check_ply_counts(p, loaded)
    lines = None
    if p.suffix.lower() == ".obj":  # trimesh leaves OBJ polylines out
        from .point_files import obj_lines

        lines = obj_lines(p)
        if lines is not None:
            lines = (f"{p.stem}-lines", finish(lines, "lines"), np.eye(4))
            if not isinstance(loaded, (trimesh.Trimesh, trimesh.Scene)) or (
                    isinstance(loaded, trimesh.Scene) and not loaded.geometry):
                return [lines]  # lines only
    parts = _trimesh_scene_parts(p, loaded, finish)
    return parts + ([lines] if lines is not None else [])


def _trimesh_scene_parts(p: Path, loaded, finish) -> list:
    import trimesh

    if not isinstance(loaded, trimesh.Scene):
        return [(p.stem, _to_mesh(loaded, p, finish), np.eye(4))]
    if not loaded.geometry:
        raise MeshError(f"{p}: cannot read the file: no geometry found; is it truncated or "
                        "in another format?")
    meshes: dict[str, dict] = {}
    parts = []
    for node in loaded.graph.nodes_geometry:
        matrix, geom_name = loaded.graph[node]
        if geom_name not in meshes:
            meshes[geom_name] = _to_mesh(loaded.geometry[geom_name], p, finish, str(geom_name))
        parts.append((str(node), meshes[geom_name], np.asarray(matrix, dtype=np.float64)))
    return parts


def _to_mesh(tm, p: Path, finish, where: str = "") -> dict:
    """``Mesh`` arguments from one trimesh geometry."""
    import trimesh

    if not isinstance(tm, trimesh.Trimesh):
        faces = _ply_strips(tm)
        if faces is None and isinstance(tm, trimesh.PointCloud) and \
                p.suffix.lower() == ".ply":  # a scanner's point cloud
            from .point_files import ply_points

            return finish(ply_points(tm, p), where)
        if faces is None:
            kind = "points" if "Point" in type(tm).__name__ else "lines or curves"
            raise MeshError(f"{p}: the file has 0 faces (it holds only {kind}); nothing to "
                            "render")
        colors = getattr(tm, "colors", None)
        colors = None if colors is None or len(colors) != len(tm.vertices) else \
            np.asarray(colors, dtype=np.uint8)
        return finish({"positions": np.asarray(tm.vertices), "faces": faces,
                       "name": p.name, "colors": colors}, where)
    # Normals the file itself carried (OBJ vn, PLY nx/ny/nz) sit in trimesh's cache.
    normals = tm._cache.cache.get("vertex_normals") if hasattr(tm, "_cache") else None
    vertices = np.asarray(tm.vertices)
    uv = getattr(tm.visual, "uv", None)
    if uv is not None and len(uv) != len(vertices):
        uv = None
    colors = None  # per-vertex colours: PLY red/green/blue, OBJ "v x y z r g b"
    if getattr(tm.visual, "kind", None) == "vertex":
        colors = np.asarray(tm.visual.vertex_colors, dtype=np.uint8)
        if len(colors) != len(vertices):
            colors = None
    scalars = None
    if p.suffix.lower() == ".ply":  # per-vertex scalar properties, for colormaps
        from .point_files import ply_scalars

        scalars = ply_scalars(tm, len(vertices)) or None
    return finish({"positions": vertices, "faces": np.asarray(tm.faces), "normals": normals,
                   "scalars": scalars,
                   "uvs": uv, "name": p.name, "material": _material_from_trimesh(tm),
                   "colors": colors}, where)


def _check_ply_counts(p: Path, tm) -> None:
    """A PLY whose header promises more elements than the file holds is truncated (trimesh
    reads what is there and says nothing)."""
    raw = (getattr(tm, "metadata", None) or {}).get("_ply_raw") or {}
    for name, element in raw.items():
        data = element.get("data")
        if isinstance(data, dict):
            found = min((len(v) for v in data.values()), default=0)
        elif hasattr(data, "__len__"):
            found = len(data)
        else:
            continue
        if found < element.get("length", 0):
            raise MeshError(f"{p}: the header promises {element['length']:,} {name} "
                            f"elements but the file holds {found:,}; is it truncated?")


def _ply_strips(tm) -> np.ndarray | None:
    """(F, 3) triangles of a PLY's ``tristrips`` element (index -1 restarts a strip),
    which trimesh leaves out; None when there is none."""
    raw = (getattr(tm, "metadata", None) or {}).get("_ply_raw") or {}
    data = raw.get("tristrips", {}).get("data")
    # ASCII: {name: lists}; binary: a structured array whose field holds (count, list).
    if isinstance(data, dict):
        lists = next(iter(data.values()), None)
    elif isinstance(data, np.ndarray) and data.dtype.names:
        lists = data[data.dtype.names[0]]
        if lists.dtype.names:  # (count, indices) pairs: the indices
            lists = lists[lists.dtype.names[-1]]
    else:
        lists = None
    if lists is None or len(lists) == 0:
        return None
    rows = [np.append(np.asarray(s, dtype=np.int64).reshape(-1), -1) for s in lists]
    seq = np.concatenate(rows)
    k = np.arange(len(seq) - 2)
    # Triangle k takes seq[k:k+3]; every other one in a run is wound the other way round.
    start = np.maximum.accumulate(np.where(seq < 0, np.arange(len(seq)), -1)) + 1
    valid = (seq[k] >= 0) & (seq[k + 1] >= 0) & (seq[k + 2] >= 0)
    odd = (k - start[k]) % 2 == 1
    tri = np.stack([np.where(odd, seq[k + 1], seq[k]), np.where(odd, seq[k], seq[k + 1]),
                    seq[k + 2]], axis=1)[valid]
    # Strips repeat an index to turn or to join runs: those triangles are empty.
    keep = (tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2])
    return tri[keep]


def _material_from_trimesh(tm) -> Material | None:
    """The Phong material an OBJ's MTL defined, or None (mapping: module doc)."""
    mat = getattr(getattr(tm, "visual", None), "material", None)
    kwargs = getattr(mat, "kwargs", None) or {}
    if "kd" not in kwargs:  # trimesh invents defaults otherwise
        return None
    ks = np.clip(np.mean(kwargs.get("ks", [0.0])), 0.0, 1.0)
    ns = float(kwargs.get("ns", 32.0))
    image = getattr(mat, "image", None)  # map_Kd
    return Material(color=np.clip(np.asarray(kwargs["kd"], dtype=float)[:3], 0, 1),
                    ka=1.0, kd=1.0, ks=float(ks), shininess=max(ns, 0.0),
                    name=getattr(mat, "name", "") or "",
                    texture=None if image is None else Texture.from_pil(image, "map_Kd"))
