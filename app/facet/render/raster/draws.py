"""The forward pass's draws, chosen from a table keyed by (geometry kind, material model)
instead of branches (``DRAWERS``): a mesh by a Phong model, by the metallic-roughness model,
or by a user's own shader; points and lines by their sprite programs. Each draw gets the
pass's shared state (``FramePass``, made once per pass by facet.render.raster.forward) and
one item: an object, or a batch of objects sharing mesh and material (drawn instanced).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ...geometry import transforms as T
from ...gl.bindings import unit
from ..materials import as_pbr, model_for, slot_defines
from ..state import FrameState
from .culling import det3
from .ibl import PREFILTER_LEVELS
from .skinning import gpu_pose
from .slots import phong_record, set_pbr_material
from .sprites import set_sprite_uniforms, sprite_variant, uses_edl
from .transmission import transmits
from .variant import LIT, Variant, grey_terms, light_products


@dataclass
class FramePass:
    """What every draw of one forward pass shares."""

    state: FrameState
    base: Variant  # the pass's variant, each object's made from it
    view_projection: np.ndarray
    eye: tuple  # the eye, or a parallel projection's direction to the viewer
    ambient: np.ndarray  # I_a, linear
    intensities: np.ndarray  # (lights, 3) I_i
    aux: tuple[str, ...]  # the exact channels drawn alongside
    oit: bool  # the transparent pass
    colour_pass: bool
    reflections: dict  # id(mirror object) -> its reflection's texture
    behind: object  # the picture transmission refracts, or None
    mirrored_view: bool  # the front faces' winding turned round
    ready: set = field(default_factory=set)  # programs whose frame uniforms are set
    # id(material) -> (material, its pbr record): made once a pass for the objects that
    # share it (a stage's thousands of prims, a few materials)
    records: dict = field(default_factory=dict)

    @property
    def environment(self):
        return self.state.environment


def material_model(obj, fp: FramePass) -> str:
    """``obj``'s key in DRAWERS' second place: "user" (its own shader, for colour),
    "pbr" or "phong" (the Phong family: phong, blinn, flat, gouraud, unlit, normals)."""
    if obj.material.shader is not None and not fp.aux:
        return "user"
    return "pbr" if model_for(fp.state.shading, obj.material) == "pbr" else "phong"


def draw_phong(fwd, fp: FramePass, item, obj) -> None:
    """A mesh by a Phong model (glsl/mesh/phong.frag): its material record, its image, its
    mirror's reflection or the environment it reflects."""
    m, state = obj.material, fp.state
    model = model_for(state.shading, m)
    mirror = id(obj) in fp.reflections
    reflects = (fp.environment is not None and m.reflectivity > 0 and fp.colour_pass
                and not mirror)
    exact_only = bool(fp.aux) and not fp.colour_pass
    grey = not exact_only and model in LIT and \
        grey_terms(light_products(m, state, fp.ambient, fp.intensities))
    prog = fwd.program(fwd.phong_variant(
        fp.base, model, m.texture is not None, mirror, reflects, obj.mesh.colors is not None,
        getattr(m, "alpha_mode", "") == "MASK", exact_only, grey, isinstance(item, list),
        *gpu_pose(obj.mesh)))
    fwd.frame_uniforms(prog, fp, False)
    _phong_material(fwd, fp, prog, item, obj, True)
    if mirror:
        fp.reflections[id(obj)].use(location=unit("u_mirror"))
    elif reflects:
        fwd.cache.cube(fp.environment).use(location=unit("u_environment"))
        prog.set("u_gloss_jitter", tuple(float(v) for v in state.gloss_jitter))
    fwd.render(prog, item, fp)


def draw_user(fwd, fp: FramePass, item, obj) -> None:
    """A mesh by its user's shader (facet.render.raster.user_shaders), given the matrices,
    ``u_color`` and the material record (lib/lights.glsl's shade_scene reads it), each
    where the shader declares it."""
    prog = fwd.user.program(obj.material.shader, fp.base.defines())
    fwd.frame_uniforms(prog, fp, True)
    _phong_material(fwd, fp, prog, item, obj, False)
    fwd.render(prog, item, fp)


def _phong_material(fwd, fp: FramePass, prog, item, obj, strict: bool) -> None:
    """One object's (or batch's) placement, its material record (glsl/mesh/record.glsl:
    C, the Phong terms, opacity, reflectivity, cut-outs) and its image."""
    m = obj.material
    if not isinstance(item, list):
        prog.set("u_model", obj.transform, strict)
        prog.set("u_mvp", fp.view_projection @ obj.transform, strict)
        prog.set("u_normal_matrix", T.normal_matrix.unchecked(obj.transform), strict)
        prog.set("u_object_id", obj.id + 1, strict)  # 0: "nothing" in the id target
    record = phong_record(m, fp.state)
    prog.set_array("u_material", record, strict=False)
    if not strict:  # a user's shader: C as a uniform of its own (facet.scene.shader)
        prog.set("u_color", tuple(record[0, :3].tolist()), strict=False)
    if m.texture is not None:
        fwd.cache.texture(m.texture, fp.state.srgb).use(location=unit("u_texture"))


def draw_pbr(fwd, fp: FramePass, item, obj) -> None:
    """A mesh by the metallic-roughness model (glsl/mesh/pbr.frag): its material record
    and slots, image-based light, and the picture behind it when it transmits
    (facet.render.raster.transmission)."""
    m, mesh, env = as_pbr(obj.material), obj.mesh, fp.environment
    behind = fp.behind if fp.behind is not None and transmits(m) else None
    skin, morph = gpu_pose(mesh)
    prog = fwd.program(replace(
        fp.base, shading="pbr", slots=slot_defines(m), vertex_colors=mesh.colors is not None,
        uv1=mesh.uvs1 is not None,
        # (a deformed pose's tangents are its rest mesh's, moved on the GPU)
        tangents=m.normal_mapped and (mesh.rest if skin or morph else mesh).tangents
        is not None, alpha_mask=m.alpha_mode == "MASK",
        environment=env is not None and fp.colour_pass, transmission=behind is not None,
        instanced=isinstance(item, list), skin=skin, morph=morph))
    fwd.frame_uniforms(prog, fp, False)
    if not isinstance(item, list):
        prog.set("u_model", obj.transform)
        prog.set("u_mvp", fp.view_projection @ obj.transform)
        prog.set("u_normal_matrix", T.normal_matrix.unchecked(obj.transform))
        prog.set("u_handedness", -1.0 if det3(obj.transform) < 0 else 1.0, strict=False)
        prog.set("u_object_id", obj.id + 1)
    bound = set_pbr_material(prog, m, fwd.cache, fwd.samplers, fp.records)
    if fp.colour_pass:
        fwd.ibl.lut().use(location=unit("u_ibl_lut"))
        if env is not None:
            irradiance, prefiltered = fwd.ibl.maps(env)
            irradiance.use(location=unit("u_irradiance"))
            prefiltered.use(location=unit("u_prefiltered"))
            prog.set("u_prefiltered_levels", float(PREFILTER_LEVELS), strict=False)
    if behind is not None:
        behind.use(location=unit("u_behind"))
        prog.set("u_behind_width", float(behind.width))
        prog.set("u_view_projection", fp.view_projection)
    fwd.render(prog, item, fp)
    for at in bound:  # sampler objects outlive the draw otherwise
        fwd.ctx.clear_samplers(at, at + 1)


def draw_sprites(fwd, fp: FramePass, item, obj) -> None:
    """Points or lines (facet.render.raster.sprites): quads per point or segment, an unlit
    cloud shaded by eye-dome lighting from its own depth pass first."""
    state = fp.state
    variant = sprite_variant(fp.base, obj, state.shading, bool(fp.aux) and not fp.colour_pass)
    buffers = fwd.cache.buffers(obj.mesh)
    fwd.cull(False)

    def program(v):
        prog = fwd.program(v)
        fwd.frame_uniforms(prog, fp, False)
        set_sprite_uniforms(prog, obj, state, fp.view_projection)
        return prog

    if uses_edl(obj, variant):  # its depth first, read around each fragment after
        depth = replace(variant, aux=(), oit=False, edl_depth=True, shadow_slots=None,
                        light_kinds=())
        shade = fwd.edl.draw_shade(state.width, state.height,
                                   lambda: buffers.draw_sprites(fwd.ctx, program(depth).gl))
        prog = program(replace(variant, edl=True))
        shade.use(location=unit("u_edl_shade"))
        buffers.draw_sprites(fwd.ctx, prog.gl)
        return
    buffers.draw_sprites(fwd.ctx, program(variant).gl)


MODELS = ("phong", "pbr", "user")
DRAWERS = {("mesh", "phong"): draw_phong, ("mesh", "pbr"): draw_pbr,
           ("mesh", "user"): draw_user,
           **{(kind, model): draw_sprites for kind in ("points", "lines") for model in MODELS}}
