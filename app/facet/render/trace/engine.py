"""The Whitted ray tracer as an engine (facet.render.engine) on the GPU: one supersample of
traced colour (glsl/trace/trace.frag) or the exact channels (glsl/trace/primary.frag) as
full-screen passes over its ray scene (facet.render.rays), on any GL 3.3 context (llvmpipe
and the viewer's window included). Its colour is always a sum of samples (msaa:N becomes N
rays per pixel); what it does not honour is its row of facet.render.capabilities.
"""

from __future__ import annotations

from ...options.render import parse_aa
from ...options.values import DISTRIBUTED_AA
from ...scene.pbr import PbrMaterial
from ..antialias import accumulation
from ..engine import Engine, grid_or_jittered
from ..materials import as_pbr
from ..rays import pack
from ..rays.scene import RayScene, ray_scene_lines
from ..state import FrameState

# Below this roughness a glTF material reflects the scene (glsl/trace/shade.glsl's).
TRACED_ROUGHNESS = 0.6


class TraceEngine(Engine):
    """The Whitted tracer of one renderer: its ray scene and the draws."""

    name = "trace"

    def __init__(self, ctx, cache):
        super().__init__(ctx, cache)
        self.rays = RayScene(ctx, cache)

    def sampling(self, opts, scene, camera, preview: bool):
        """Always a sum: msaa:N is N rays per pixel (none: one through the centre), glossy
        reflections a sum over tilts; a window's moving view one ray through each pixel's
        centre."""
        if preview:
            return parse_aa("ssaa:grid:1")
        aa = accumulation(opts.aa, scene, camera, opts.shadows)
        if aa is None and glossy_reflections(scene, opts.shading):
            aa = parse_aa(DISTRIBUTED_AA)  # the reflections' tilts are a sum over samples
        return aa if aa is not None else grid_or_jittered(opts.aa.msaa or 1)

    def prepare(self, scene, state: FrameState, opts=None, aa=None) -> FrameState:
        """Geometry and textures for this scene (uploaded only when they changed)."""
        self.rays.prepare(scene, state, _layer_requests(scene, _pbr_shading(state)))
        return state

    def draw_sample(self, scene, state, opts, surf, background) -> None:
        """Trace one supersample (``state``'s camera, jitter, lights, gloss tilt) into the
        bound target: premultiplied colour and coverage."""
        # Reflection, refraction and transparency need the ray stack; without them a
        # simpler program runs (glsl/trace/trace.frag, SECONDARY).
        secondary = any(o.material.reflectivity > 0 or o.material.opacity < 1 or
                        getattr(o.material, "alpha_mode", "") in ("MASK", "BLEND") or
                        getattr(o.material, "transmission", 0.0) > 0 or
                        getattr(o.material, "roughness", 1.0) < TRACED_ROUGHNESS or
                        getattr(o.material, "clearcoat", 0.0) > 0
                        for o in scene.objects)
        program = self.rays.program("trace", state, opts.shadows, secondary=secondary,
                                    extra=_material_defines(scene, state))
        self.rays.draw_colour(scene, state, program, u_background=background,
                              u_max_depth=int(opts.max_depth),
                              u_gloss_jitter=state.gloss_jitter)

    def draw_exact(self, scene, state: FrameState, aux) -> None:
        self.rays.draw_exact(scene, state, aux, _material_defines(scene, state))

    def more_lines(self, opts, scene) -> list[str]:
        lines = ray_scene_lines(scene, "the ray tracer")
        if opts.environment is not None and opts.shading in ("auto", "pbr") and any(
                isinstance(o.material, PbrMaterial) for o in scene.objects):
            lines.append("the ray tracer lights metallic-roughness materials by the ambient "
                         "term, not by the environment (the rasterizer and the path tracer "
                         "do)")
        return lines

    def release(self) -> None:
        self.rays.release()


def glossy_reflections(scene, shading: str) -> bool:
    """Whether a glTF material traces a blurred reflection of the scene
    (glsl/trace/trace.frag: roughness below TRACED_ROUGHNESS, above 0)."""
    return shading in ("auto", "pbr") and any(
        isinstance(o.material, PbrMaterial) and not o.material.unlit and (
            0 < o.material.roughness < TRACED_ROUGHNESS or
            (o.material.clearcoat > 0 and 0 < o.material.clearcoat_roughness <
             TRACED_ROUGHNESS)) for o in scene.objects)


def _layer_requests(scene, pbr_shading: bool) -> list:
    """(texture, mode) for each image the tracer samples (modes: facet.render.rays.pack):
    a Phong material's image as given, a metallic-roughness material's slots (colour
    decoded to linear, data as stored) when it is shaded by that model (``pbr_shading``),
    else its base colour image as its Phong stand-in's, and as its slot too where its
    coverage cuts or blends it."""
    out = []
    for obj in scene.objects:
        m = obj.material
        if isinstance(m, PbrMaterial) and pbr_shading:
            out += [(slot.texture, pack.slot_mode(name, slot)) for name, slot in m.slots.items()]
            continue
        if m.texture is not None:
            out.append((m.texture, pack.AS_GIVEN))
        slot = getattr(m, "base_color_texture", None)
        if slot is not None and m.alpha_mode != "OPAQUE":  # its coverage: cut-outs
            out.append((slot.texture, pack.slot_mode("base_color", slot)))
    return out


def _material_defines(scene, state) -> tuple:
    """Defines of how materials are read: PBR_SLOTS when some are metallic-roughness (their
    records' slots: cut-outs and coverage in every shading model, as the rasterizer cuts
    them), PBR_SHADING when they are shaded by that model (glsl/trace/shade.glsl's
    shade_pbr; shading "auto" or "pbr"; by their Phong stand-ins otherwise); NO_IRIDESCENCE,
    NO_ANISOTROPY and NO_DIFFUSE_TRANSMISSION where no material has a thin film, an
    anisotropic lobe or diffuse transmission (their code left out: llvmpipe runs a branch no
    pixel takes)."""
    if not any(isinstance(o.material, PbrMaterial) for o in scene.objects):
        return ()
    # shadow rays through BLEND coverage, MASK cut-outs and glass, texel by texel
    alpha = any(as_pbr(o.material).alpha_mode != "OPAQUE" or as_pbr(o.material).transmission > 0
                for o in scene.objects)
    film = any(as_pbr(o.material).iridescence > 0 for o in scene.objects)
    stretched = any(as_pbr(o.material).anisotropy > 0 for o in scene.objects)
    through = any(as_pbr(o.material).diffuse_transmission > 0 for o in scene.objects)
    return ("PBR_SLOTS",) + (("PBR_SHADING",) if _pbr_shading(state) else ()) + \
        (("ALPHA_SHADOWS",) if alpha else ()) + (() if film else ("NO_IRIDESCENCE",)) + \
        (() if stretched else ("NO_ANISOTROPY",)) + \
        (() if through else ("NO_DIFFUSE_TRANSMISSION",))


def _pbr_shading(state) -> bool:
    """Whether metallic-roughness materials are shaded by their model (else by their
    Phong stand-ins, as the rasterizer's phong model draws them)."""
    return state.shading in ("auto", "pbr")
