"""Reading mesh files through trimesh into ``facet.scene.Mesh``, with clear errors.

Every failure (missing file, a directory, an unknown extension, a parse error, no faces,
NaN/inf vertices) becomes one ``MeshError`` that names the file and says what to do.

Materials found in the file map to Phong (``facet.scene.Material``):

* OBJ/MTL: C = Kd, k_d = 1, k_s = mean(Ks), n = Ns, k_a = 1; map_Kd becomes the texture.
* glTF/GLB (metallic-roughness): C = baseColorFactor.rgb, k_d = 1,
  k_s = 0.5 (1 - roughness), n = 2 / alpha^2 - 2 with alpha = max(roughness^2, 0.05)
  (the Blinn-Phong exponent that matches a GGX lobe of that roughness), clamped to [1, 512];
  baseColorTexture becomes the texture.

Per-vertex colours (PLY, OBJ's "v x y z r g b" extension, glTF COLOR_0) become
``Mesh.colors``.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import FacetError, MeshError
from .material import Material
from .texture import Texture

# Extensions we accept (lower case, no dot) and the trimesh file_type for each.
FORMATS = {"obj": "obj", "stl": "stl", "ply": "ply", "off": "off", "glb": "glb",
           "gltf": "gltf"}


def _check_path(path) -> Path:
    p = Path(path)
    if not p.exists():
        raise MeshError(f"{p}: no such file")
    if p.is_dir():
        raise MeshError(f"{p}: is a directory, expected a mesh file")
    ext = p.suffix.lower().lstrip(".")
    if ext not in FORMATS:
        known = ", ".join(f".{e}" for e in FORMATS)
        raise MeshError(f"{p}: unknown mesh format '{p.suffix or '(none)'}'; use one of {known}")
    if not os.access(p, os.R_OK):
        raise MeshError(f"{p}: permission denied")
    if p.stat().st_size == 0:
        raise MeshError(f"{p}: the file is empty")
    return p


def _material_from_trimesh(tm) -> Material | None:
    """The Phong material a trimesh geometry's file defined, or None (mapping: module doc)."""
    mat = getattr(getattr(tm, "visual", None), "material", None)
    if mat is None:
        return None
    kwargs = getattr(mat, "kwargs", None) or {}
    if "kd" in kwargs:  # an MTL file's own values (trimesh invents defaults otherwise)
        ks = np.clip(np.mean(kwargs.get("ks", [0.0])), 0.0, 1.0)
        ns = float(kwargs.get("ns", 32.0))
        image = getattr(mat, "image", None)  # map_Kd
        return Material(color=np.clip(np.asarray(kwargs["kd"], dtype=float)[:3], 0, 1),
                        ka=1.0, kd=1.0, ks=float(ks), shininess=max(ns, 0.0),
                        name=getattr(mat, "name", "") or "",
                        texture=None if image is None else Texture.from_pil(image, "map_Kd"))
    if hasattr(mat, "baseColorFactor"):  # glTF metallic-roughness (factor default: white)
        base = mat.baseColorFactor
        base = np.ones(3) if base is None else np.asarray(base, dtype=float)[:3]
        if base.max() > 1.0:  # trimesh stores uint8 colours
            base = base / 255.0
        rough = getattr(mat, "roughnessFactor", None)
        rough = 1.0 if rough is None else float(np.clip(rough, 0.0, 1.0))
        alpha = max(rough * rough, 0.05)
        shininess = float(np.clip(2.0 / alpha**2 - 2.0, 1.0, 512.0))
        image = getattr(mat, "baseColorTexture", None)
        return Material(color=np.clip(base, 0, 1), ka=1.0, kd=1.0, ks=0.5 * (1.0 - rough),
                        shininess=shininess, name=getattr(mat, "name", "") or "",
                        texture=None if image is None else
                        Texture.from_pil(image, "baseColorTexture"))
    return None


def _read(p: Path):
    """trimesh's object for a checked path (a Trimesh, a Scene, or something else)."""
    import trimesh  # imported here: commands that load no mesh do not pay for it

    try:
        return trimesh.load(str(p), file_type=FORMATS[p.suffix.lower().lstrip(".")],
                            process=False)
    except FacetError:
        raise
    except Exception as exc:  # trimesh raises many types for bad files; report them as one
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise MeshError(f"{p}: cannot read the file as {p.suffix.lower()} ({detail}); "
                        "is it truncated or in another format?") from None


def load_mesh(path) -> dict:
    """Read ``path`` as one mesh's ``Mesh`` keyword arguments (a scene graph is baked into
    one world-space mesh); raises ``MeshError`` naming the file on any failure. This module
    returns plain arrays so that it needs nothing from facet.scene.mesh (which calls it)."""
    import trimesh

    p = _check_path(path)
    loaded = _read(p)
    if isinstance(loaded, trimesh.Scene):
        if not loaded.geometry:
            raise MeshError(f"{p}: cannot read the file: no geometry found; is it truncated or "
                            "in another format?")
        material = None
        for geom in loaded.geometry.values():
            material = material or _material_from_trimesh(geom)
        # Bake every node's transform into its geometry (scene graph -> one world mesh).
        tm = loaded.to_geometry() if hasattr(loaded, "to_geometry") else \
            loaded.dump(concatenate=True)
        return _to_mesh(tm, p, material)
    return _to_mesh(loaded, p, _material_from_trimesh(loaded))


def load_parts(path) -> list[tuple[str, dict, np.ndarray]]:
    """The parts of a mesh file as (node name, mesh arguments, 4x4 node -> file transform).

    glTF/GLB keep their node hierarchy: one part per node that holds geometry, with the
    node's world transform from the file's scene graph; a mesh used by several nodes is
    converted once. Other formats give one part with the identity.
    """
    import trimesh

    p = _check_path(path)
    loaded = _read(p)
    if not isinstance(loaded, trimesh.Scene):
        return [(p.stem, _to_mesh(loaded, p, _material_from_trimesh(loaded)), np.eye(4))]
    if not loaded.geometry:
        raise MeshError(f"{p}: cannot read the file: no geometry found; is it truncated or "
                        "in another format?")
    meshes: dict[str, dict] = {}
    parts = []
    for node in loaded.graph.nodes_geometry:
        matrix, geom_name = loaded.graph[node]
        if geom_name not in meshes:
            geom = loaded.geometry[geom_name]
            meshes[geom_name] = _to_mesh(geom, p, _material_from_trimesh(geom))
        parts.append((str(node), meshes[geom_name], np.asarray(matrix, dtype=np.float64)))
    return parts


def _to_mesh(tm, p: Path, material) -> dict:
    """``Mesh`` arguments from one trimesh geometry, with the checks every file gets."""
    import trimesh

    if not isinstance(tm, trimesh.Trimesh):
        kind = "points" if "Point" in type(tm).__name__ else "lines or curves"
        raise MeshError(f"{p}: the file has 0 faces (it holds only {kind}); nothing to render")
    vertices = np.asarray(tm.vertices)
    faces = np.asarray(tm.faces)
    if len(faces) == 0:
        raise MeshError(f"{p}: the mesh has 0 faces; nothing to render")
    if not np.isfinite(vertices).all():
        bad = int((~np.isfinite(vertices).all(axis=1)).sum())
        raise MeshError(f"{p}: {bad} vertices are NaN or infinite; fix or remove them")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise MeshError(f"{p}: faces refer to vertices that do not exist; the file is corrupt")
    # Normals the file itself carried (OBJ vn, PLY nx/ny/nz, glTF NORMAL) sit in trimesh's
    # cache; asking trimesh to compute them is slow without scipy, so we compute our own.
    normals = tm._cache.cache.get("vertex_normals") if hasattr(tm, "_cache") else None
    if normals is None:
        # Files without normals, STL above all, repeat vertices per face: weld them so the
        # smooth normals average over neighbours (texture seams stay split).
        tm.merge_vertices()
        vertices, faces = np.asarray(tm.vertices), np.asarray(tm.faces)
    uv = getattr(tm.visual, "uv", None)
    if uv is not None and len(uv) != len(vertices):
        uv = None
    colors = None  # per-vertex colours: PLY red/green/blue, OBJ "v x y z r g b", COLOR_0
    if getattr(tm.visual, "kind", None) == "vertex":
        colors = np.asarray(tm.visual.vertex_colors, dtype=np.uint8)
        if len(colors) != len(vertices):
            colors = None
    return {"positions": vertices, "faces": faces, "normals": normals, "uvs": uv,
            "name": p.name, "material": material, "colors": colors, "path": str(p)}
