"""Points and lines in the forward pass (facet.scene.points): one instanced draw of a quad
per point or segment (glsl/mesh/sprite.vert), shaded by glsl/mesh/phong.frag like a mesh:
points with normals by the frame's lit model, the rest unlit in their colour. The exact
channels come out as a mesh's do (a point's depth and id exact at its centre)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...geometry import transforms as T
from ...scene.pbr import as_phong
from ..materials import model_for
from .slots import phong_record

LIT_SPRITES = ("phong", "blinn", "normals", "unlit")  # models a lit point keeps as they are


def sprite_variant(base, obj, shading: str, exact_only: bool):
    """The program variant of a points or lines object."""
    sprites = obj.mesh
    model = model_for(shading, obj.material)
    if sprites.kind == "lines" or sprites.normals is None:
        model = "normals" if model == "normals" else "unlit"
    elif model not in LIT_SPRITES:
        model = "phong"  # gouraud, flat and pbr become per-fragment Phong for points
    return replace(base, shading=model, sprite=sprites.kind, exact_only=exact_only,
                   vertex_colors=sprites.colors is not None, texture=False, mirror=False,
                   environment=False, alpha_mask=False, grey=False, instanced=False,
                   slots=(), uv1=False, tangents=False, transmission=False)


def uses_edl(obj, variant) -> bool:
    """Whether an unlit cloud's colour is shaded by eye-dome lighting (glsl/lib/edl.glsl):
    asked for (Points.edl), unlit, in a colour pass."""
    return (obj.mesh.kind == "points" and obj.mesh.edl and variant.shading == "unlit"
            and not variant.exact_only and not variant.oit)


def set_sprite_uniforms(prog, obj, state, view_projection) -> None:
    """Matrices, the material record (its Phong stand-in's: facet.scene.pbr.as_phong) and
    sizes of one points or lines object."""
    sprites = obj.mesh
    prog.set("u_model", obj.transform)
    prog.set("u_mvp", view_projection @ obj.transform)
    prog.set("u_normal_matrix", T.normal_matrix.unchecked(obj.transform), strict=False)
    prog.set("u_object_id", obj.id + 1, strict=False)
    prog.set_array("u_material", phong_record(as_phong(obj.material), state), strict=False)
    prog.set("u_viewport", (float(state.width), float(state.height)), strict=False)
    radius = getattr(sprites, "radius", None)
    pixels = sprites.width if sprites.kind == "lines" else (0.0 if radius else sprites.size)
    prog.set("u_sprite_pixels", float(pixels), strict=False)
    scale = (0.0, 0.0)
    if radius:  # the view-space radius through the projection's x and y scales
        projection = view_projection @ np.linalg.inv(state.camera.view)
        scale = (radius * abs(float(projection[0, 0])), radius * abs(float(projection[1, 1])))
    prog.set("u_sprite_clip", scale, strict=False)
