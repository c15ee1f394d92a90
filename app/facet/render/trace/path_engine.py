"""The path tracer as an engine (facet.render.engine): the ray tracer's scene upload, its
hierarchy and its exact channels (facet.render.trace.engine), with colour from
glsl/trace/path.frag: light that bounces between surfaces, by the glTF metallic-roughness
model (lib/pbr.glsl, the rasterizer's), instead of the Whitted tracer's ambient term.

One path per pixel and supersample; a sum of samples like the tracer's (msaa:N or spp=N:
N paths per pixel). The random stream of a path is a hash of its pixel and sample index,
so a picture is the same on every run. Its colour is linear radiance: float colour as it
is, 8-bit colour sRGB-encoded (as the rasterizer's metallic-roughness model writes it), in
either colour mode. ``max_depth`` is the most bounces after the eye
ray; left at facet's default (the Whitted tracer's 5) the path tracer takes
``DEFAULT_BOUNCES``.
"""

from __future__ import annotations

import weakref
from dataclasses import replace

import numpy as np

from ...scene.light import AreaLight
from ...scene.option_values import DEFAULT_BOUNCES, DEFAULT_MAX_DEPTH
from ...scene.options import RenderOptions
from ...scene.pbr import PbrMaterial
from ...srgb import srgb_to_linear
from ..materials import as_pbr, feature_lines
from . import pack
from .area_lights import AreaEmitters, strip_area_points
from .emitters import pack_emitters
from .engine import TraceEngine
from .env_sampling import distribution
from .sprites import sprite_lines

STRATEGIES = {"mis": 0, "light": 1, "bsdf": 2}  # STRATEGY_* in glsl/trace/path.frag


class PathEngine(TraceEngine):
    """The path tracer of one renderer (module docstring). ``strategy``: how emitters and
    the environment are found, "mis" (light and BSDF sampling, power heuristic), "light"
    or "bsdf" alone (the same picture, noisier: for tests of the estimator)."""

    name = "path"
    radiance = True
    strategy = "mis"
    _sample = 0  # the supersample being drawn (sample_state)
    _emitter_count = 0
    _emitters_key = None
    _sky_entry = None  # (weakref to the environment, its textures or None)

    def __init__(self, ctx, cache):
        super().__init__(ctx, cache)
        self._areas = AreaEmitters()
        self._lit_by = None  # the frame's scene, whose area lights are rectangles here

    def prepare(self, scene, state, opts=None, aa=None):
        """The tracer's upload, with the area lights' rectangles (area_lights)."""
        self._lit_by = scene
        return super().prepare(self._areas.with_rectangles(scene), state, opts, aa)

    def sample_state(self, scene, scene_k, state, opts, k: int, plain: bool):
        """Sample k's stream; the points that stand in for area lights elsewhere go (their
        rectangles emit instead)."""
        self._sample = k
        self._lit_by = scene
        if any(isinstance(x, AreaLight) for x in scene.lights):
            return state.with_(lights=strip_area_points(scene, scene_k, state.lights))
        return state

    def draw_sample(self, scene, state, opts, surf, background) -> None:
        if self._lit_by is not None:
            rectangles = self._areas.objects(self._lit_by)
            if rectangles:
                scene = scene.view(objects=scene.objects + rectangles)
        bounces = DEFAULT_BOUNCES if opts.max_depth == DEFAULT_MAX_DEPTH else opts.max_depth
        if not state.srgb:  # a display value here; the output is encoded (Engine.radiance)
            background = (*srgb_to_linear(np.asarray(background[:3])), background[3])
            # So are the generated sky's and 8-bit images' values (the rasterizer shows
            # them as given): their radiance is what they show once encoded.
            if state.environment is not None:
                state = replace(state, environment=state.environment.decoded())
        sky = self._sky(state.environment)
        program = self._program("path", state, False, extra=self._material_defines(scene) + (
            ("SKY_DISTRIBUTION",) if sky is not None else ()))
        self.draw_colour(scene, state, program, u_background=background,
                         u_max_depth=int(bounces), u_sample=self._sample,
                         u_flip_y=int(state.flip_y),
                         u_seed=int(opts.seed),
                         u_strategy=STRATEGIES[self.strategy],
                         u_emitter_count=self._emitter_count,
                         u_sky_size=sky[3] if sky is not None else (1, 1))

    # -- what differs from the tracer's upload ---------------------------------------------
    def _material_defines(self, scene, state=None) -> tuple:
        """The material's own slots (PBR_SLOTS); HAS_ALPHA when some are not opaque."""
        alpha = any(as_pbr(o.material).alpha_mode != "OPAQUE" for o in scene.objects)
        return ("PBR_SLOTS", "PATH_TRACER") + (("HAS_ALPHA",) if alpha else ())

    def _tangents(self, obj) -> bool:
        return as_pbr(obj.material).normal_mapped

    def _layer_requests(self, scene, pbr_shading: bool = True) -> list:
        """Every image of the materials' slots (facet.render.trace.pack.PATH_SLOTS), a
        Phong material's as the slot of its metallic-roughness mapping: all linear."""
        out = []
        for obj in scene.objects:
            m = as_pbr(obj.material)
            out += [(slot.texture, pack.slot_mode(name, slot)) for name, slot in m.slots.items()
                    if name in pack.PATH_SLOTS]
        return out

    def _more_textures(self) -> dict:
        out = {"u_emitters": self._textures["emitters"]}
        if self._sky_entry is not None and self._sky_entry[1] is not None:
            cdf, pdf, radiance, _ = self._sky_entry[1]
            out.update(u_sky_cdf=cdf, u_sky_pdf=pdf, u_sky_radiance=radiance)
        return out

    def _sky(self, environment):
        """The environment's luminance distribution as textures (cdf, pdf, the radiance
        it was made from, (W, H)), made once per environment
        (facet.render.trace.env_sampling); None without one. Light reaching surfaces from
        the sky is read from that radiance, texel for texel as the distribution has it: the
        cube map's filtered texels spread a small sun into neighbours the distribution
        gives little density, and each such sample was a firefly."""
        equirect = getattr(environment, "equirect", None)
        if equirect is None:
            self._release_sky()
            return None
        entry = self._sky_entry
        if entry is None or entry[0]() is not environment:
            self._release_sky()
            made = distribution(equirect)
            textures = None
            if made is not None:
                cdf, pdf = made
                textures = []
                radiance = np.ascontiguousarray(equirect[..., :3], np.float32)
                for array in (cdf, pdf, radiance):
                    tex = self.ctx.texture((array.shape[1], array.shape[0]),
                                           1 if array.ndim == 2 else 3,
                                           array.tobytes(), dtype="f4")
                    tex.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
                    textures.append(tex)
                textures.append((pdf.shape[1], pdf.shape[0]))
            self._sky_entry = (weakref.ref(environment), textures)
        return self._sky_entry[1]

    def _release_sky(self) -> None:
        if self._sky_entry is not None and self._sky_entry[1] is not None:
            for tex in self._sky_entry[1][:3]:
                tex.release()
        self._sky_entry = None

    def release(self) -> None:
        self._release_sky()
        super().release()

    def _more_rows(self, rows, ordered) -> None:
        """The emitters' table (facet.render.trace.emitters) and their densities."""
        key = tuple((i, id(o.mesh), np.asarray(o.transform).tobytes(),
                     tuple(as_pbr(o.material).emissive * as_pbr(o.material).emissive_strength))
                    for i, o in enumerate(ordered) if o.shape is None)
        if key != self._emitters_key or "emitters" not in self._textures:
            tris = {id(o.mesh): self._meshes[o.mesh].tris for o in ordered
                    if o.shape is None}
            table, pdf = pack_emitters(ordered, lambda o: as_pbr(o.material), tris,
                                       self._first_tri)
            self._upload("emitters", table)
            self._emitter_count = len(table) if pdf.any() else 0
            self._emitter_pdf = pdf
            self._emitters_key = key
        rows[:, pack.MATERIAL_ROW + 7, 0] = self._emitter_pdf

    def unsupported(self, opts, scene) -> list[str]:
        """What the path tracer does not draw as asked (each a warning line)."""
        lines = []
        if opts.wireframe:
            lines.append("the path tracer draws no wireframe overlay")
        if opts.shading not in ("auto", "pbr", "phong"):
            lines.append(f"the path tracer shades by the metallic-roughness model, not "
                         f"shading = {opts.shading}")
        if opts.cull == "on":
            lines.append("the path tracer culls no back faces for cull = on (only "
                         "single-sided glTF materials lose theirs)")
        if not opts.shadows_on:
            lines.append("the path tracer always traces shadows (shadows = off ignored)")
        if opts.pcf != RenderOptions.pcf:  # given: the default filters nothing here
            lines.append("pcf filters shadow maps; the path tracer's shadow rays are exact")
        areas = [x for x in scene.lights if isinstance(x, AreaLight)]
        if any(not np.array_equal(x.attenuation, (0.0, 0.0, 1.0)) for x in areas):
            lines.append("the path tracer's area lights are emitting rectangles: they fall "
                         "off with the inverse square of the distance (their attenuation "
                         "is ignored)")
        return lines + sprite_lines(scene, "the path tracer") + feature_lines(scene, _dropped,
                                                                      "the path tracer")


def _dropped(m) -> list[str]:
    """The material features of ``m`` the path tracer does not draw."""
    out = []
    if m.shader is not None:
        out.append("users' mesh shaders")
    if not isinstance(m, PbrMaterial):
        if m.reflectivity > 0:
            out.append("Phong reflectivity (mirrors: traced as the metallic-roughness "
                       "mapping of the Phong terms)")
        if m.ior > 0:
            out.append("Phong ior (refraction: traced as a transparent surface that does "
                       "not bend light)")
        return out
    return out
