"""The rasterizer as an engine (facet.render.engine): forward shading with shadow maps,
order-independent transparency, planar mirrors and the wireframe overlay. One picture (with
MSAA when asked: opaque objects with their mirrors and environment, the overlay, then
transparent ones by OIT over the resolved colour), or one supersample of a sum; the exact
channels from the opaque objects in a single-sample pass, drawn when first read.
"""

from __future__ import annotations

from ...gl.targets import aux_locations, clear_frame
from ..antialias import has_area_lights, point_lights_for
from ..engine import Engine
from .forward import ForwardPass
from .overlay import wireframe_overlay
from .shadow import ShadowMaps
from .splats import SplatPass, scene_splats
from .transparency import Transparency, split_transparent


class RasterEngine(Engine):
    name = "raster"
    deferred_exact = True  # most callers read colour only (facet.render.frame)

    def __init__(self, ctx, cache):
        super().__init__(ctx, cache)
        self.forward = ForwardPass(ctx, cache)
        self._shadows = None  # the shadow atlas, made on first use
        self._splats = None  # the Gaussian splats' pass, made on first use

    @property
    def splats(self) -> SplatPass:
        if self._splats is None:
            self._splats = SplatPass(self.ctx)
        return self._splats

    @property
    def shadows(self) -> ShadowMaps:
        if self._shadows is None:
            self._shadows = ShadowMaps(self.ctx, self.cache)
        return self._shadows

    def draws_together(self, scene) -> bool:
        # Users' shaders write colour only: the exact channels get their own pass then.
        return not any(o.material.shader is not None for o in scene.objects)

    def prepare(self, scene, state, opts, aa):
        """The shadow maps, once per frame (per sample for area lights, sample_state)."""
        if opts.shadows and not (aa is not None and has_area_lights(scene)):
            return state.with_(shadows=self.shadows.draw(point_lights_for(scene), opts.pcf))
        return state

    def draw_picture(self, scene, state, opts, surf, clear, dtype, together, direct):
        """One picture (straight into the window ``direct`` when nothing needs compositing
        or finishing; ``together``: the exact channels drawn alongside). Returns the
        framebuffer holding it."""
        t = surf.targets
        opaque, transparent = split_transparent(scene)
        if opts.aa.msaa:
            target = t.multisample(opts.aa.msaa, dtype)
        elif direct is not None and transparent is None:
            target = direct
            target.viewport = (0, 0, *opts.size)
        else:
            target = t.color(dtype)
        if together:  # the same colour texture, with the exact channels' attachments
            target = t.aux(together, dtype)
        target.use()
        clear_frame(target, clear, exact=bool(together))
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        self.forward.draw(opaque, state, aux=together)
        if opts.wireframe:
            wireframe_overlay(self.forward, scene, state)
        splats = bool(scene_splats(scene))
        if together and splats:  # their depth and ids where they cover the opaque scene's
            self.splats.draw_exact(scene, state, target, aux_locations(together))
        if transparent is None and direct is not None and not splats:
            return target  # shown as it is (a multisampled one resolves as it is copied)
        zbuffer = target.depth_attachment if opts.aa.msaa else t.zbuffer
        result = t.resolve(target, dtype) if opts.aa.msaa else t.color(dtype)
        if transparent is not None:
            # Layers tested against the opaque depth (multisampled with MSAA: anti-aliased
            # edges), composited over the resolved opaque colour.
            oit = _oit(surf).begin(zbuffer)
            self.forward.draw(transparent, state, oit=True)
            _oit(surf).end(oit, result)
        if splats:  # over everything, tested against the opaque depth (MSAA's resolved)
            self.splats.draw(scene, state, t.zbuffer, result)
        return result

    def sample_state(self, scene, scene_k, state, opts, k: int, plain: bool):
        """Area lights: the maps follow the lights' points of sample ``k`` (``scene_k``)."""
        if opts.shadows and has_area_lights(scene) and not plain:
            return state.with_(shadows=self.shadows.draw(scene_k, opts.pcf, k))
        return state

    def draw_sample(self, scene, state, opts, surf, background) -> None:
        acc = surf.accumulator
        opaque, transparent = split_transparent(scene)
        self.forward.draw(opaque, state)
        if opts.wireframe:
            wireframe_overlay(self.forward, scene, state)
        if transparent is not None:
            oit = _oit(surf).begin(acc.sample_depth)
            self.forward.draw(transparent, state, oit=True)
            _oit(surf).end(oit, acc.sample)
        if scene_splats(scene):
            self.splats.draw(scene, state, acc.sample_depth, acc.sample)

    def exact_scene(self, scene):
        return split_transparent(scene)[0]  # the nearest opaque surface, as the tracer's

    def draw_exact(self, scene, state, aux) -> None:
        self.forward.draw(scene, state.with_(shading="unlit", shadows=None, environment=None),
                          aux=aux, colour_pass=False)
        if scene_splats(scene):  # (the bound target: facet.render.sequence's exact one)
            self.splats.draw_exact(scene, state, self.ctx.fbo, aux_locations(aux))

    def more_lines(self, opts, scene) -> list[str]:
        lines = []
        if opts.shadows and any(o.mesh.kind != "mesh" for o in scene.objects):
            lines.append("points and lines cast no shadow maps in the rasterizer (the "
                         "tracers' spheres and capsules cast shadows)")
        clouds = scene_splats(scene)
        if "ids" in opts.outputs and len(clouds) > 1:
            lines.append(f"ids of {len(clouds)} splat clouds: where clouds overlap in a "
                         "pixel, its id is the mean of theirs weighted by their opacity "
                         "there (one cloud's pixels are exact)")
        surface = [c for c in ("normals", "position", "uv") if c in opts.outputs]
        if clouds and surface:
            lines.append(f"Gaussian splats have no {', '.join(surface)}: those channels show "
                         "the meshes only (depth, ids and alpha include the splats)")
        if clouds and opts.wireframe:
            lines.append("the wireframe overlay draws meshes' edges; Gaussian splats have "
                         "none")
        if clouds and opts.shadows:
            lines.append("Gaussian splats cast no shadows and take no light: they carry "
                         "their own colours")
        return lines

    def user_programs(self):
        return self.forward.user  # (facet.render.raster.user_shaders)

    def release(self) -> None:
        if self._shadows is not None:
            self._shadows.release()
        if self._splats is not None:
            self._splats.release()
        self.forward.release()


def _oit(surf) -> Transparency:
    """The order-independent transparency sums of the surfaces' size (made once a size)."""
    return surf.part("oit", Transparency)
