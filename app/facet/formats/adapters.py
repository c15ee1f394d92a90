"""The geometry users already hold, as facet's (no GL): trimesh's Trimesh (with its
visuals: vertex colours, texture coordinates and image, Phong or PBR material), Scene (its
graph's transforms) and PointCloud. ``Scene.add`` and ``Mesh.from_trimesh`` take them;
anything else with ``vertices`` and ``faces`` arrays (Open3D's and PyVista's meshes through
numpy: ``facet.Mesh(np.asarray(m.vertices), np.asarray(m.triangles))``) goes through
``facet.Mesh`` itself.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError


def is_trimesh(value) -> bool:
    return type(value).__module__.split(".")[0] == "trimesh"


def trimesh_parts(value, mesh_class) -> list[tuple[str, Any, np.ndarray]]:
    """[(name, Mesh or Points, 4x4 part -> world)] of a trimesh Trimesh, Scene or
    PointCloud; ``mesh_class``: facet.scene.mesh.Mesh (given, so that this module and
    that one do not import each other)."""
    import trimesh

    if isinstance(value, trimesh.Scene):
        parts = []
        for node in value.graph.nodes_geometry:
            matrix, name = value.graph[node]
            parts.append((str(node), trimesh_geometry(value.geometry[name], mesh_class,
                                                      str(name)),
                          np.asarray(matrix, dtype=np.float64)))
        if not parts:
            raise InputError("the trimesh Scene holds no geometry")
        return parts
    return [(getattr(value, "metadata", {}).get("name", "") or type(value).__name__,
             trimesh_geometry(value, mesh_class), np.eye(4))]


def trimesh_geometry(tm, mesh_class, name: str = "trimesh"):
    """A facet Mesh (``mesh_class``) or Points of one trimesh geometry."""
    import trimesh

    from ..scene.points import Points

    if isinstance(tm, trimesh.PointCloud):
        colors = getattr(tm, "colors", None)
        colors = None if colors is None or len(colors) != len(tm.vertices) else \
            np.asarray(colors, dtype=np.uint8)
        return Points(np.asarray(tm.vertices), colors, name=name)
    if not isinstance(tm, trimesh.Trimesh):
        raise InputError(f"facet takes trimesh's Trimesh, Scene and PointCloud, got "
                         f"{type(tm).__name__}")
    visual = getattr(tm, "visual", None)
    uv = getattr(visual, "uv", None)
    uv = None if uv is None or len(uv) != len(tm.vertices) else np.asarray(uv)
    colors = None
    if getattr(visual, "kind", None) == "vertex":
        colors = np.asarray(visual.vertex_colors, dtype=np.uint8)
        if len(colors) != len(tm.vertices):
            colors = None
    elif getattr(visual, "kind", None) == "face" and len(tm.faces):
        return _face_colored(tm, mesh_class, name, trimesh_material(visual))
    normals = tm._cache.cache.get("vertex_normals") if hasattr(tm, "_cache") else None
    return mesh_class(np.asarray(tm.vertices), np.asarray(tm.faces), normals, uv, name=name,
                      colors=colors, material=trimesh_material(visual))


FACE_CREASE = 30.0  # degrees: a face colour's corner keeps the smooth normal within this


def _face_colored(tm, mesh_class, name: str, material):
    """A mesh with a colour per face (trimesh's face_colors): each face gets corners of its
    own with its colour; a corner keeps the vertex's smooth normal unless it turns more than
    FACE_CREASE from the face's (a box stays flat, a sphere smooth)."""
    faces = np.asarray(tm.faces)
    corners = faces.reshape(-1)
    colors = np.repeat(np.asarray(tm.visual.face_colors, dtype=np.uint8), 3, axis=0)
    v = np.asarray(tm.vertices, dtype=np.float64)
    cross = np.cross(v[faces[:, 1]] - v[faces[:, 0]], v[faces[:, 2]] - v[faces[:, 0]])
    summed = np.zeros_like(v)  # area-weighted vertex normals (trimesh's need scipy)
    np.add.at(summed, faces, cross[:, None, :])
    summed /= np.maximum(np.linalg.norm(summed, axis=1, keepdims=True), 1e-30)
    smooth = summed[faces]  # (F, 3, 3)
    flat = (cross / np.maximum(np.linalg.norm(cross, axis=1, keepdims=True), 1e-30))[:, None]
    keep = np.einsum("fcj,fkj->fc", smooth, flat) > np.cos(np.radians(FACE_CREASE))
    normals = np.where(keep[..., None], smooth, flat).reshape(-1, 3)
    uv = getattr(tm.visual, "uv", None)
    return mesh_class(np.asarray(tm.vertices)[corners], np.arange(len(corners)).reshape(-1, 3),
                      normals, None if uv is None else np.asarray(uv)[corners], name=name,
                      colors=colors, material=material)


def trimesh_material(visual):
    """A facet material of a trimesh visual's material (PBRMaterial: metallic-roughness
    with its base colour image; SimpleMaterial: Phong with its image), else None."""
    import trimesh

    material = getattr(visual, "material", None)
    if isinstance(material, trimesh.visual.material.PBRMaterial):
        from ..scene.pbr import PbrMaterial, TextureSlot
        from ..scene.texture import Texture

        factor = material.baseColorFactor
        base = np.ones(4) if factor is None else np.asarray(factor, dtype=np.float64)
        if base.max() > 1.0:  # trimesh keeps uint8 factors
            base = base / 255.0
        image = material.baseColorTexture
        return PbrMaterial(
            base_color=np.clip(base, 0, 1),
            metallic=float(np.clip(material.metallicFactor if material.metallicFactor
                                   is not None else 1.0, 0, 1)),
            roughness=float(np.clip(material.roughnessFactor if material.roughnessFactor
                                    is not None else 1.0, 0, 1)),
            double_sided=bool(material.doubleSided),
            base_color_texture=None if image is None else TextureSlot(
                Texture.from_pil(image, "baseColorTexture")),
            name=material.name or "")
    if isinstance(material, trimesh.visual.material.SimpleMaterial):
        from types import SimpleNamespace

        from .trimesh_files import material_from_trimesh  # (OBJ's MTL mapping: one place)

        found = material_from_trimesh(SimpleNamespace(visual=visual))
        image = getattr(material, "image", None)
        if found is None and image is not None:  # an image and no MTL colours: as given
            from ..scene.material import Material
            from ..scene.texture import Texture

            found = Material(color=(1.0, 1.0, 1.0), texture=Texture.from_pil(image, "image"))
        return found
    return None
