"""Anti-aliasing modes: ``none``, ``msaa:N`` and supersampling by accumulation,
``ssaa:PATTERN:N`` (also written ``PATTERN:N``), with the sample patterns of
``facet.geometry.sampling``.

Supersampling renders the scene N times with the projection shifted by sub-pixel offsets
(in clip space, so every pixel moves by the same fraction of itself), adds each float image
into an accumulation target on the GPU and divides by N once at the end. Only colour is
supersampled: depth, ids and the other channels come from the unshifted pass at pixel
centres, so labels stay exact.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry.sampling import MAX_SAMPLES, PATTERNS, pattern
from ..gl.glsl_source import glsl_root
from ..gl.shaders import compile_program


@dataclass(frozen=True)
class AntiAliasing:
    kind: str  # "none", "msaa", "ssaa"
    samples: int = 1
    pattern: str = ""

    def __str__(self) -> str:
        return {"none": "none", "msaa": f"msaa:{self.samples}"}.get(
            self.kind, f"ssaa:{self.pattern}:{self.samples}")


def parse_aa(text: str) -> AntiAliasing:
    """``none``, ``msaa:4``, ``ssaa:jittered:16`` or ``jittered:16``."""
    parts = str(text).strip().lower().split(":")
    try:
        if parts == ["none"]:
            return AntiAliasing("none")
        if parts[0] == "msaa" and len(parts) == 2:
            n = int(parts[1])
            if n not in (0, 2, 4, 8):
                raise InputError(f"aa {text!r}: msaa takes 2, 4 or 8 samples")
            return AntiAliasing("msaa", n) if n else AntiAliasing("none")
        if parts[0] == "ssaa":
            parts = parts[1:]
        if len(parts) == 2 and parts[0] in PATTERNS:
            n = int(parts[1])
            if n < 1:
                raise InputError(f"aa {text!r}: the sample count must be >= 1")
            if n > MAX_SAMPLES:
                warnings.warn(f"aa {text!r}: {n} samples capped to {MAX_SAMPLES}",
                              stacklevel=2)
                n = MAX_SAMPLES
            pattern(parts[0], n)  # validates (a grid needs a square number)
            return AntiAliasing("ssaa", n, parts[0])
    except InputError:
        raise
    except ValueError:  # int() of something that is not a number
        pass
    raise InputError(f"aa {text!r}: expected none, msaa:N or ssaa:PATTERN:N with PATTERN one "
                     f"of {', '.join(PATTERNS)} (e.g. ssaa:jittered:16)")


def jitter_matrix(dx: float, dy: float, width: int, height: int) -> np.ndarray:
    """Clip-space shift that moves the image by (dx, dy) pixels (x right, y down): applied
    after the projection, x' = x + s w, so after the divide every point moves by s in NDC,
    for perspective and parallel projections alike."""
    m = np.eye(4)
    m[0, 3], m[1, 3] = 2.0 * dx / width, -2.0 * dy / height
    return m


class Accumulator:
    """The float sample and accumulation targets of one renderer, made on first use."""

    def __init__(self, ctx, width: int, height: int):
        self.ctx = ctx
        size = (width, height)
        self.sample_tex = ctx.texture(size, 4, dtype="f4")
        self.sample_depth = ctx.depth_renderbuffer(size)
        self.sample = ctx.framebuffer([self.sample_tex], self.sample_depth)
        self.accum_tex = ctx.texture(size, 4, dtype="f4")
        self.accum = ctx.framebuffer([self.accum_tex])
        root = glsl_root()
        self.program = compile_program(ctx, root / "shadertoy" / "fullscreen.vert",
                                       root / "post" / "accumulate.frag")
        self.vao = ctx.vertex_array(self.program.gl, [])
        self.resolve_program = compile_program(ctx, root / "shadertoy" / "fullscreen.vert",
                                               root / "post" / "resolve.frag")
        self.resolve_vao = ctx.vertex_array(self.resolve_program.gl, [])

    def show(self, framebuffer, samples: int) -> None:
        """Draw the mean of ``samples`` accumulated samples into ``framebuffer``."""
        ctx = self.ctx
        framebuffer.use()
        self.accum_tex.use(location=0)
        self.resolve_program.set("u_accum", 0)
        self.resolve_program.set("u_scale", 1.0 / samples)
        ctx.disable(ctx.DEPTH_TEST | ctx.BLEND)
        self.resolve_vao.render(vertices=3)
        ctx.enable(ctx.DEPTH_TEST)

    def begin_sample(self, background) -> None:
        self.sample.use()
        self.sample.clear(*background, depth=1.0)

    def add_sample(self) -> None:
        """accum += sample (additive blending of a full-screen pass)."""
        ctx = self.ctx
        self.accum.use()
        self.sample_tex.use(location=0)
        self.program.set("u_sample", 0)
        ctx.disable(ctx.DEPTH_TEST)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = ctx.ONE, ctx.ONE
        self.vao.render(vertices=3)
        ctx.disable(ctx.BLEND)
        ctx.enable(ctx.DEPTH_TEST)

    def result(self, samples: int) -> np.ndarray:
        """The mean of the samples, (H, W, 4) float32, row 0 at the top (drawn flipped)."""
        w, h = self.accum_tex.size
        out = np.empty((h, w, 4), np.float32)
        self.accum.read_into(out, components=4, dtype="f4")
        out /= samples
        return out

    def release(self) -> None:
        for obj in (self.vao, self.resolve_vao, self.accum, self.accum_tex, self.sample,
                    self.sample_depth, self.sample_tex):
            obj.release()
        self.program.release()
        self.resolve_program.release()


LENS_SEED, TIME_SEED, AREA_SEED, GLOSS_SEED = 1, 2, 3, 4  # the pixel pattern's seed is 0


def gloss_jitter(k: int, n: int) -> tuple[float, float]:
    """Sample ``k``'s tilt of glossy reflections (a jittered pattern, own seed)."""
    u, v = pattern("jittered", n, GLOSS_SEED)[k]
    return float(u), float(v)


def has_area_lights(scene) -> bool:
    from ..scene.light import AreaLight

    return any(isinstance(light, AreaLight) for light in scene.lights)


def needs_accumulation(scene, camera, shadows: bool) -> bool:
    """Depth of field, motion blur, area-light penumbrae and glossy environment reflection
    are sums over samples: a render with any of them supersamples (headless and viewer)."""
    from ..geometry.lens import check_lens

    return bool(check_lens(camera)
                or any(o.transform_end is not None for o in scene.objects)
                or (shadows and has_area_lights(scene))
                or (scene.environment is not None
                    and any(o.material.gloss > 0 and o.material.reflectivity > 0
                            for o in scene.objects)))


DISTRIBUTED_AA = "ssaa:jittered:16"  # the supersampling such a render gets unless aa says


def point_lights_for(scene, k: int | None = None, n: int = 1):
    """The scene with each area light replaced by a point light: at sample ``k`` of a
    jittered pattern over its rectangle, or at its centre (``k`` None)."""
    from ..scene.light import AreaLight

    if not has_area_lights(scene):
        return scene
    uv = pattern("jittered", n, AREA_SEED)[k] if k is not None else (0.0, 0.0)
    return scene.view(lights=[x.point_light(*uv) if isinstance(x, AreaLight) else x
                              for x in scene.lights])


def distributed_sample(camera, scene, k: int, mode: AntiAliasing):
    """Sample ``k``'s camera (a lens point, for depth of field) and scene (objects at a
    shutter time, for motion blur), from patterns decorrelated from the pixel jitter; the
    inputs themselves when neither effect is on."""
    from ..geometry.lens import concentric_disk, interpolate_transform, lens_camera

    n = mode.samples
    scene = point_lights_for(scene, k, n)
    if camera.aperture > 0:
        disk = concentric_disk(pattern("jittered", n, LENS_SEED))
        lx, ly = disk[k] * camera.aperture / 2.0
        camera = lens_camera(camera, lx, ly)
    if any(o.transform_end is not None for o in scene.objects):
        from ..scene.scene import SceneObject

        # Stratified shutter times, shuffled so they do not follow the pixel offsets.
        order = np.random.default_rng(TIME_SEED).permutation(n)
        t = (order[k] + 0.5) / n
        scene = scene.view(objects=[
            o if o.transform_end is None else
            SceneObject(o.id, o.mesh, o.material,
                        interpolate_transform(o.transform, o.transform_end, t), o.name)
            for o in scene.objects])
    return camera, scene
