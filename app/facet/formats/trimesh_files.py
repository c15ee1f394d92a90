"""OBJ, STL, PLY and OFF files through trimesh (its loaders under facet's guarded resolver:
an OBJ's MTL and images only through facet.guard), as the loaders' raw part arrays; the
checks trimesh leaves out (OBJ's index 0, PLY's counts) and PLY triangle strips."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np

from ..errors import FacetError, FacetWarning, MeshError
from ..guard import read_bytes
from ..scene.material import Material
from ..scene.texture import Texture

# Extensions we accept (lower case, no dot) and the trimesh file_type for each.
FORMATS = {"obj": "obj", "stl": "stl", "ply": "ply", "off": "off", "glb": "glb",
           "gltf": "gltf", "xyz": "xyz", "pts": "pts", "pcd": "pcd", "dae": "dae"}
COLLADA_MISSING = ("reading COLLADA (.dae) needs pycollada: pip install "
                   "'facet-render[urdf]'")


def _guarded_resolver(p: Path):
    """A trimesh resolver that opens only regular files inside the model's folder (and
    the confinement folder, facet.guard), for whatever the model names (material
    libraries, textures: trimesh finds ``mtllib`` even in a comment). A missing one is
    listed in ``refused`` (the model loads without it, with one warning each); one that
    is not a regular file, outside the confinement folder or beyond a budget is a
    MeshError kept in ``fatal`` (raised once trimesh returns)."""
    import trimesh

    from ..guard import read_bytes

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
                return read_bytes(path, f"file {p.name} names", MeshError)
            except MeshError as exc:
                self.fatal.append(exc)
                raise FileNotFoundError(name) from None

    resolver = Guarded(str(p))
    resolver.refused, resolver.fatal = [], []
    return resolver


IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tga", ".tif", ".tiff", ".gif", ".webp")


# A face line with an index that is exactly 0 (OBJ counts from 1; negative counts back).
_OBJ_ZERO_INDEX = re.compile(rb"^[ \t]*f[ \t][^\n]*?(?<![\w.+-])0+(?=[/ \t\r\n]|$)", re.M)


def _check_obj_indices(p: Path, data: bytes) -> None:
    """An OBJ face index 0 is invalid (indices count from 1); trimesh would read it as the
    last vertex. One pass of a regular expression over the file's bytes ``data``."""
    m = _OBJ_ZERO_INDEX.search(data)
    if m is not None:
        line = data.count(b"\n", 0, m.start()) + 1
        raise MeshError(f"{p}:{line}: a face refers to vertex 0, but OBJ counts vertices "
                        "from 1 (or back from -1); fix the file's face indices")


def trimesh_file_parts(p: Path, finish) -> list:
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
                   "uvs": uv, "name": p.name, "material": material_from_trimesh(tm),
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


def material_from_trimesh(tm) -> Material | None:
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


# -- trimesh formats ------------------------------------------------------------------------
def _read(p: Path):
    """trimesh's object for a checked path (a Trimesh, a Scene, or something else)."""
    import io

    import trimesh  # imported here: commands that load no mesh do not pay for it

    data = read_bytes(p, "mesh file", MeshError)  # once, through the guard
    resolver = None
    if p.suffix.lower() == ".obj":
        _check_obj_indices(p, data)
        resolver = _guarded_resolver(p)
    if p.suffix.lower() == ".dae":  # XML: no DTD or entities (they could name any file)
        if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
            raise MeshError(f"{p}: declares a DTD or entities; a COLLADA file needs neither, "
                            "and facet does not expand them")
        try:
            import collada  # noqa: F401
        except ImportError:
            raise MeshError(f"{p}: {COLLADA_MISSING}") from None
        resolver = _guarded_resolver(p)  # (its textures)
    try:
        loaded = trimesh.load(io.BytesIO(data), file_type=FORMATS[p.suffix.lower().lstrip(".")],
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
