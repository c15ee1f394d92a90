"""The path tracer as an engine (facet.render.engine): colour from glsl/trace/path.frag
over its ray scene (facet.render.rays, the Whitted tracer's sibling): light that bounces
between surfaces, by the glTF metallic-roughness model (lib/pbr.glsl, the rasterizer's),
with its emitters (facet.render.path.emitters), area lights as emitting rectangles
(facet.render.path.area_lights) and the sky as a light (facet.render.path.sky).

One path per pixel and supersample; a sum of samples (msaa:N or spp=N: N paths per pixel).
The random stream of a path is a hash of its pixel and sample index, so a picture is the
same on every run. Its colour is linear radiance: float colour as it is, 8-bit colour
sRGB-encoded (as the rasterizer's metallic-roughness model writes it), in either colour
mode. ``max_depth`` is the most bounces after the eye ray (8 when not given:
facet.render.capabilities).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...geometry.sampling import MAX_SAMPLES
from ...gl.shaders import mat_bytes
from ...scene.light import AreaLight
from ...srgb import srgb_to_linear
from ..antialias import accumulation
from ..engine import Engine, grid_or_jittered
from ..material_record import TEXELS
from ..materials import as_pbr
from ..rays import pack
from ..rays.scene import RayScene, ray_scene_lines
from ..sequence import MAX_MOSAIC
from .area_lights import AreaEmitters, strip_area_points
from .emitters import emitted_luminance, pack_emitters
from .sky import SkyLight

STRATEGIES = {"mis": 0, "light": 1, "bsdf": 2}  # STRATEGY_* in glsl/trace/path.frag


class PathEngine(Engine):
    """The path tracer of one renderer (module docstring). ``strategy``: how emitters and
    the environment are found, "mis" (light and BSDF sampling, power heuristic), "light"
    or "bsdf" alone (the same picture, noisier: for tests of the estimator)."""

    name = "path"
    radiance = True
    adaptive = True
    mosaic = True
    # A fragment runs up to 8 paths one after the other, starting the next where the last
    # ended (glsl/trace/path.frag): llvmpipe's SIMD lanes idled while the longest path
    # of their 8 went on (256 x 256: 8 rather than 4 paths, the Cornell box and the glass
    # scene 4-8% faster; 16 little more, and a draw twice as long).
    per_fragment = 8
    strategy = "mis"

    def __init__(self, ctx, cache):
        super().__init__(ctx, cache)
        self.rays = RayScene(ctx, cache)
        self.sky = SkyLight(ctx)
        self._areas = AreaEmitters()
        self._lit_by = None  # the frame's scene, whose area lights are rectangles here
        self._sample = 0  # the supersample being drawn (sample_state)
        self._own_positions = False  # each pixel's own sample positions (prepare)
        self._emitter_count = 0
        self._emitter_pdf = np.zeros(0)
        self._emitters_key = None

    def sampling(self, opts, scene, camera, preview: bool):
        """Always a sum: msaa:N is N paths per pixel (none: one through the centre)."""
        if preview:
            return grid_or_jittered(1)
        aa = accumulation(opts.aa, scene, camera, opts.shadows)
        aa = aa if aa is not None else grid_or_jittered(opts.aa.msaa or 1)
        if (opts.noise is not None or opts.time_limit is not None) and \
                opts.aa.kind != "ssaa":  # no spp given: as many paths as they allow
            aa = replace(aa, samples=MAX_SAMPLES, pattern="jittered")
        return aa

    def prepare(self, scene, state, opts=None, aa=None):
        """The ray scene's upload, with the area lights' rectangles. With the jittered
        pattern each pixel places its paths by its own stratified points (path.frag): the
        samples' shared offsets are left out of their cameras."""
        self._own_positions = aa is not None and aa.pattern == "jittered"
        self._lit_by = scene
        scene = self._areas.with_rectangles(scene)
        self.rays.prepare(scene, state, _layer_requests(scene))
        return state

    def sample_state(self, scene, scene_k, state, opts, k: int, plain: bool):
        """Sample k's stream; the points that stand in for area lights elsewhere go (their
        rectangles emit instead)."""
        self._sample = k
        self._lit_by = scene
        if any(isinstance(x, AreaLight) for x in scene.lights):
            return state.with_(lights=strip_area_points(scene, scene_k, state.lights))
        return state

    def _with_rectangles(self, scene):
        if self._lit_by is not None:
            rectangles = self._areas.objects(self._lit_by)
            if rectangles:
                return scene.view(objects=scene.objects + rectangles)
        return scene

    def draw_mosaic(self, scene, states, first: int, opts, surf, background,
                    per_fragment: int = 1) -> None:
        """Samples ``first``, ``first + 1``, ... (one state each, differing only in camera
        and shift) at once into the bound mosaic target: ``per_fragment`` of them in each
        part, the parts one above the other."""
        self._sample = first
        self.draw_sample(scene, states[0], opts, surf, background, mosaic=states,
                         per_fragment=per_fragment)

    def draw_sample(self, scene, state, opts, surf, background, mosaic=None,
                    per_fragment: int = 1) -> None:
        """One sample, or with ``mosaic`` (states) several: ``per_fragment`` in each part
        of the stack. One program draws both (a picture's first call compiles what its
        later ones use: a mosaic variant cost its first stacked draw about 0.1 s on
        llvmpipe)."""
        states = mosaic or [state]
        own = self._own_positions and state.jitter is not None  # (else the centre, or the
        if own:                                                  # pattern's offsets)
            states = [s.with_(jitter=None) for s in states]
        views = [s.view_projection() for s in states]
        inverse = b"".join(mat_bytes(np.linalg.inv(v)) for v in views)
        inverse += bytes(64 * (MAX_MOSAIC - len(states)))  # (the array's unused part)
        scene = self._with_rectangles(scene)
        if not state.srgb:  # a display value here; the output is encoded (Engine.radiance)
            background = (*srgb_to_linear(np.asarray(background[:3])), background[3])
            # So are the generated sky's and 8-bit images' values (the rasterizer shows
            # them as given): their radiance is what they show once encoded.
            if state.environment is not None:
                state = replace(state, environment=state.environment.decoded())
        sky = self.sky.textures(state.environment)
        program = self.rays.program("path", state, False, extra=_light_defines(scene, state) +
                                    _material_defines(scene) + (
            ("SKY_DISTRIBUTION",) if sky is not None else ()) + (
            ("ADAPTIVE",) if self.active is not None else ()) + (("MOSAIC", MAX_MOSAIC),))
        textures = {"u_emitters": "emitters"}  # a scene texture (RayScene.draw_colour)
        if self.active is not None:
            textures["u_active"] = self.active
        if sky is not None:
            textures.update(u_sky_cdf=sky[0], u_sky_pdf=sky[1], u_sky_radiance=sky[2])
        self.rays.draw_colour(
            scene, state, program, textures, self._emitter_rows, views,
            u_background=background, u_max_depth=int(opts.max_depth),
            u_sample=self._sample, u_flip_y=int(state.flip_y), u_seed=int(opts.seed),
            u_strategy=STRATEGIES[self.strategy],
            u_inv_view_projections=inverse, u_count=len(states),
            u_per_fragment=per_fragment, u_own_positions=int(own),
            u_emitter_count=lambda: self._emitter_count,  # (counted while binding)
            u_sky_size=sky[3] if sky is not None else (1, 1))

    def draw_exact(self, scene, state, aux, albedo: bool = False) -> None:
        """The exact channels; ``albedo``: the first hit's albedo into colour too (the
        denoiser's guide)."""
        self.rays.draw_exact(scene, state, aux, _material_defines(scene) +
                             (("ALBEDO",) if albedo else ()), self._emitter_rows)

    def _emitter_rows(self, rows, ordered) -> None:
        """The emitters' table (facet.render.path.emitters) uploaded when it changed, and
        each instance row's density factor."""
        key = tuple((i, id(o.mesh), o.shape and (o.shape.kind, o.shape.params),
                     np.asarray(o.transform).tobytes(),
                     tuple(as_pbr(o.material).emissive * as_pbr(o.material).emissive_strength))
                    for i, o in enumerate(ordered))  # (shapes too: they emit as meshes do)
        if key != self._emitters_key or "emitters" not in self.rays.textures:
            tris = {id(o.mesh): self.rays.meshes[o.mesh].tris for o in ordered
                    if o.shape is None}
            table, pdf = pack_emitters(ordered, lambda o: as_pbr(o.material), tris,
                                       self.rays.first_tri)
            self.rays.upload("emitters", table)
            self._emitter_count = len(table) if pdf.any() else 0
            self._emitter_pdf = pdf
            self._emitters_key = key
        rows[:, pack.MATERIAL_ROW + TEXELS["flags"], 0] = self._emitter_pdf

    def more_lines(self, opts, scene) -> list[str]:
        lines = ray_scene_lines(scene, "the path tracer")
        volumes = any(as_pbr(o.material).transmission > 0 and as_pbr(o.material).thickness > 0
                      and not pack.open_volume(o) for o in scene.objects)
        if volumes and any(not isinstance(x, AreaLight) for x in scene.lights):
            lines.append("the path tracer lights what lies behind glass volumes by emitting "
                         "surfaces and the sky only: point, spot and directional light "
                         "refracted through glass (caustics) is not found by paths from the "
                         "eye")
        if scene.ambient_declared and scene.ambient.any() and scene.environment is None and \
                not np.allclose(scene.background[:3], scene.ambient):
            lines.append("the path tracer lights by the ambient light as a constant sky; eye "
                         "rays that escape show the background colour, not that sky")
        areas = [x for x in scene.lights if isinstance(x, AreaLight)]
        if any(not np.array_equal(x.attenuation, (0.0, 0.0, 1.0)) for x in areas):
            lines.append("the path tracer's area lights are emitting rectangles: they fall "
                         "off with the inverse square of the distance (their attenuation "
                         "is ignored)")
        return lines

    def release(self) -> None:
        self.sky.release()
        self.rays.release()


def _layer_requests(scene) -> list:
    """Every image of the materials' slots but occlusion (the path tracer traces occlusion),
    a Phong material's as the slot of its metallic-roughness mapping."""
    out = []
    for obj in scene.objects:
        m = as_pbr(obj.material)
        out += [(slot.texture, pack.slot_mode(name, slot)) for name, slot in m.slots.items()
                if name != "occlusion"]
    return out


def _light_defines(scene, state) -> tuple:
    """The kinds of light a frame lacks, as defines that leave their sampling out of the
    program (code no lane takes still costs llvmpipe time: facet.render.rays.scene
    scene_defines): NO_DELTA_LIGHTS (no point, spot or directional light), NO_EMITTERS
    (nothing in the emitters' table: facet.render.path.emitters)."""
    emits = any(emitted_luminance(as_pbr(o.material)) > 0.0 and
                (o.shape is not None or o.mesh.kind == "mesh") for o in scene.objects)
    return (() if state.lights else ("NO_DELTA_LIGHTS",)) + (() if emits else ("NO_EMITTERS",))


def _material_defines(scene) -> tuple:
    """The material's own slots (PBR_SLOTS); HAS_ALPHA when some are not opaque or let
    light through unbent (thin-walled glass: shadow rays pass it); NO_SLOT_IMAGES,
    NO_TRANSMISSION, NO_CLEARCOAT, NO_SHEEN, NO_IRIDESCENCE, NO_ANISOTROPY,
    NO_DIFFUSE_TRANSMISSION and NO_DISPERSION where no material has them (their lobes'
    code would cost llvmpipe time unused: facet.render.rays.scene scene_defines)."""
    pbrs = [as_pbr(o.material) for o in scene.objects]
    alpha = any(m.alpha_mode != "OPAQUE" or (m.transmission > 0 and m.thickness == 0)
                for m in pbrs) or any(pack.open_volume(o) for o in scene.objects)
    images = () if _layer_requests(scene) else ("NO_SLOT_IMAGES",)
    absent = (("NO_TRANSMISSION", any(m.transmission > 0 for m in pbrs)),
              ("NO_CLEARCOAT", any(m.clearcoat > 0 for m in pbrs)),
              ("NO_SHEEN", any(np.any(np.asarray(m.sheen_color) > 0) for m in pbrs)),
              ("NO_IRIDESCENCE", any(m.iridescence > 0 for m in pbrs)),
              ("NO_ANISOTROPY", any(m.anisotropy > 0 for m in pbrs)),
              ("NO_DIFFUSE_TRANSMISSION", any(m.diffuse_transmission > 0 for m in pbrs)),
              ("NO_DISPERSION", any(m.dispersion > 0 and m.transmission > 0 for m in pbrs)))
    return ("PBR_SLOTS", "PBR_SHADING", "PATH_TRACER") + (("HAS_ALPHA",) if alpha else ()) + \
        images + tuple(name for name, used in absent if not used)
