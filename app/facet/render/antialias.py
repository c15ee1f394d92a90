"""Supersampling by accumulation and the distributed effects that ride on it.

The scene is drawn once per sample of a pattern (``facet.options.render.AntiAliasing``,
``ssaa:PATTERN:N``) with the projection shifted by sub-pixel offsets (in clip space, so every
pixel moves by the same fraction of itself); each float image is added into an accumulation
target on the GPU and the sum is divided by N once, when the colour is finished. Only colour
is supersampled: depth, ids and the other channels come from the unshifted pass at pixel
centres, so labels stay exact.

Each sample also looks through another point of the lens (depth of field), at another
shutter time (motion blur), lights from another point of each area light (soft shadows) and
tilts glossy reflections another way (``distributed_sample``), from patterns decorrelated
from the pixel jitter.
"""

from __future__ import annotations

import numpy as np

from ..geometry.lens import check_lens, concentric_disk, interpolate_transform, lens_camera
from ..geometry.sampling import pattern
from ..gl.fullscreen import FullScreenPass
from ..options.render import DISTRIBUTED_AA, AntiAliasing, parse_aa
from ..scene.light import AreaLight


def jitter_matrix(dx: float, dy: float, width: int, height: int) -> np.ndarray:
    """Clip-space shift that moves the image by (dx, dy) pixels (x right, y down): applied
    after the projection, x' = x + s w, so after the divide every point moves by s in NDC,
    for perspective and parallel projections alike."""
    m = np.eye(4)
    m[0, 3], m[1, 3] = 2.0 * dx / width, -2.0 * dy / height
    return m


class Accumulator:
    """The float sample and accumulation targets of one image size."""

    def __init__(self, ctx, width: int, height: int):
        self.ctx = ctx
        size = (width, height)
        self.sample_tex = ctx.texture(size, 4, dtype="f4")
        self.sample_depth = ctx.depth_renderbuffer(size)
        self.sample = ctx.framebuffer([self.sample_tex], self.sample_depth)
        self.accum_tex = ctx.texture(size, 4, dtype="f4")
        self.accum = ctx.framebuffer([self.accum_tex])
        self.add = FullScreenPass(ctx, "post/accumulate.frag")
        self._mosaics: dict[int, tuple] = {}  # parts -> (texture, framebuffer)

    def clear(self) -> None:
        self.accum.clear(0.0, 0.0, 0.0, 0.0)

    def begin_sample(self, background) -> None:
        self.sample.use()
        self.sample.clear(*background, depth=1.0)

    def mosaic(self, parts: int):
        """The framebuffer of ``parts`` samples stacked one above the other (made once)."""
        if parts not in self._mosaics:
            w, h = self.accum_tex.size
            tex = self.ctx.texture((w, h * parts), 4, dtype="f4")
            # With a depth buffer as the sample's has: llvmpipe compiles a program anew
            # for each framebuffer layout it draws into (seconds, for the path tracer's).
            depth = self.ctx.depth_renderbuffer((w, h * parts))
            self._mosaics[parts] = (tex, self.ctx.framebuffer([tex], depth), depth)
        return self._mosaics[parts][1]

    def add_sample(self, parts: int = 0) -> None:
        """accum += sample, or the sum of a mosaic's ``parts`` samples (additive blending of
        a full-screen pass)."""
        ctx = self.ctx
        self.accum.use()
        ctx.disable(ctx.DEPTH_TEST)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = ctx.ONE, ctx.ONE
        source = self._mosaics[parts][0] if parts else self.sample_tex
        self.add.draw({"u_sample": source}, u_slices=max(parts, 1),
                      u_slice_height=self.accum_tex.size[1])
        ctx.disable(ctx.BLEND)
        ctx.enable(ctx.DEPTH_TEST)

    def release(self) -> None:
        for obj in (self.accum, self.accum_tex, self.sample, self.sample_depth,
                    self.sample_tex, *(x for made in self._mosaics.values() for x in made)):
            obj.release()
        self.add.release()


LENS_SEED, TIME_SEED, AREA_SEED, GLOSS_SEED = 1, 2, 3, 4  # the pixel pattern's seed is 0


def gloss_jitter(k: int, n: int) -> tuple[float, float]:
    """Sample ``k``'s tilt of glossy reflections (a jittered pattern, own seed)."""
    u, v = pattern("jittered", n, GLOSS_SEED)[k]
    return float(u), float(v)


def has_area_lights(scene) -> bool:
    return any(isinstance(light, AreaLight) for light in scene.lights)


def accumulation(aa: AntiAliasing, scene, camera, shadows: bool) -> AntiAliasing | None:
    """The supersampling colour needs: ``aa`` when it supersamples, else
    ``DISTRIBUTED_AA`` when the scene has a distributed effect, else None."""
    if aa.supersampled:
        return aa
    return parse_aa(DISTRIBUTED_AA) if needs_accumulation(scene, camera, shadows) else None


def needs_accumulation(scene, camera, shadows: bool) -> bool:
    """Depth of field, motion blur, area-light penumbrae and glossy environment reflection
    are sums over samples: a render with any of them supersamples (headless and viewer)."""
    return bool(check_lens(camera)
                or getattr(scene, "moving", None) is not None
                or any(o.transform_end is not None for o in scene.objects)
                or (shadows and has_area_lights(scene))
                or (scene.environment is not None
                    and any(o.material.gloss > 0 and o.material.reflectivity > 0
                            for o in scene.objects)))


def point_lights_for(scene, k: int | None = None, n: int = 1):
    """The scene with each area light replaced by a point light: at sample ``k`` of a
    jittered pattern over its rectangle, or at its centre (``k`` None)."""
    if not has_area_lights(scene):
        return scene
    uv = pattern("jittered", n, AREA_SEED)[k] if k is not None else (0.0, 0.0)
    return scene.view(lights=[x.point_light(*uv) if isinstance(x, AreaLight) else x
                              for x in scene.lights])


def distributed_sample(camera, scene, k: int, mode: AntiAliasing):
    """Sample ``k``'s camera (a lens point, for depth of field) and scene (objects at a
    shutter time, for motion blur), from patterns decorrelated from the pixel jitter; the
    inputs themselves when neither effect is on."""
    n = mode.samples
    scene = point_lights_for(scene, k, n)
    if camera.aperture > 0:
        disk = concentric_disk(pattern("jittered", n, LENS_SEED))
        lx, ly = disk[k] * camera.aperture / 2.0
        camera = lens_camera(camera, lx, ly)
    moving = getattr(scene, "moving", None) is not None
    if moving or any(o.transform_end is not None for o in scene.objects):
        from dataclasses import replace

        # Stratified shutter times, shuffled so they do not follow the pixel offsets.
        order = np.random.default_rng(TIME_SEED).permutation(n)
        t = (order[k] + 0.5) / n
        if moving:  # the animation at this time of the shutter (facet.scene.staging)
            from ..scene.staging import at_shutter

            scene = at_shutter(scene, t)
        scene = scene.view(objects=[
            o if o.transform_end is None else
            replace(o, transform=interpolate_transform(o.transform, o.transform_end, t),
                    transform_end=None)
            for o in scene.objects])
    return camera, scene
