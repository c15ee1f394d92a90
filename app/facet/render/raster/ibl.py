"""Image-based lighting for the physically based model (glsl/lib/pbr.glsl's pbr_ambient),
computed on the GPU once and kept: the split-sum table (once per renderer) and, per
environment, its irradiance and its GGX-prefiltered radiance as octahedral maps
(glsl/lib/sampling.glsl); the prefiltered map's mip level k holds roughness k / (levels - 1),
so one trilinear lookup blends between roughnesses.

Each map is drawn with a full-screen pass into a float target, read back and written into
its level (moderngl attaches no cube faces or mip levels to framebuffers); a few hundred
kilobytes, once per environment.
"""

from __future__ import annotations

import weakref

import numpy as np

from ...gl.fullscreen import FullScreenPass

LUT_SIZE = 64
PREFILTER_SIZE = (256, 256)  # level 0 of the prefiltered map: roughness 0
PREFILTER_LEVELS = 6  # roughness 0, 0.2, ..., 1 at 256^2 ... 8^2
PREFILTER_SAMPLES = 256
IRRADIANCE_SIZE = (32, 32)


def _half(data: bytes) -> bytes:
    """float32 texels as float16: the maps are sampled per fragment, and half floats (11
    significant bits, plenty for light) filter faster on a CPU rasteriser."""
    return np.frombuffer(data, np.float32).astype(np.float16).tobytes()


class ImageLighting:
    """The table and the per-environment maps of one context (released with it)."""

    def __init__(self, ctx, cache):
        self.ctx, self.cache = ctx, cache
        self._passes: dict[str, FullScreenPass] = {}
        self._lut = None
        self._maps: dict[int, tuple[weakref.ref, tuple]] = {}

    def _pass(self, name: str) -> FullScreenPass:
        if name not in self._passes:
            self._passes[name] = FullScreenPass(self.ctx, f"ibl/{name}.frag")
        return self._passes[name]

    def _draw(self, name: str, size, textures=None, **uniforms) -> bytes:
        """RGBA float32 bytes of one full-screen pass at ``size``."""
        ctx = self.ctx
        target = ctx.texture(size, 4, dtype="f4")
        fbo = ctx.framebuffer([target])
        bound = ctx.fbo
        try:
            fbo.use()
            ctx.disable(ctx.DEPTH_TEST | ctx.BLEND | ctx.CULL_FACE)
            self._pass(name).draw(textures, u_size=(float(size[0]), float(size[1])),
                                  **uniforms)
            return fbo.read(components=4, dtype="f4")
        finally:
            bound.use()
            ctx.enable(ctx.DEPTH_TEST)
            fbo.release()
            target.release()

    def lut(self):
        """The split-sum table (A, B, C) over (N.V, roughness), LUT_SIZE^2, bilinear."""
        if self._lut is None:
            data = self._draw("lut", (LUT_SIZE, LUT_SIZE))
            self._lut = self.ctx.texture((LUT_SIZE, LUT_SIZE), 4, _half(data), dtype="f2")
            self._lut.filter = (self.ctx.LINEAR, self.ctx.LINEAR)
            self._lut.repeat_x = self._lut.repeat_y = False
        return self._lut

    def maps(self, environment) -> tuple:
        """(irradiance, prefiltered radiance) of ``environment`` (made once, kept while the
        environment lives)."""
        entry = self._maps.get(id(environment))
        if entry is not None and entry[0]() is environment:
            return entry[1]
        if entry is not None:
            for tex in entry[1]:
                tex.release()
        cube = self.cache.cube(environment)
        source = {"u_source": cube}
        # Irradiance: its cosine lobe spans the sphere; a mip of about 16 texels suffices.
        lod = max(float(np.log2(environment.size / 16.0)), 0.0)
        irradiance = self.ctx.texture(IRRADIANCE_SIZE, 4, _half(self._draw(
            "irradiance", IRRADIANCE_SIZE, source, u_lod=lod)), dtype="f2")
        irradiance.filter = (self.ctx.LINEAR, self.ctx.LINEAR)
        prefiltered = self.ctx.texture(PREFILTER_SIZE, 4, dtype="f2")
        prefiltered.build_mipmaps(0, PREFILTER_LEVELS - 1)
        for level in range(PREFILTER_LEVELS):
            size = (PREFILTER_SIZE[0] >> level, PREFILTER_SIZE[1] >> level)
            data = self._draw("prefilter", size, source,
                              u_roughness=level / (PREFILTER_LEVELS - 1),
                              u_source_size=float(environment.size),
                              u_samples=PREFILTER_SAMPLES)
            prefiltered.write(_half(data), level=level)
        prefiltered.filter = (self.ctx.LINEAR_MIPMAP_LINEAR, self.ctx.LINEAR)
        for tex in (irradiance, prefiltered):
            tex.repeat_x = tex.repeat_y = False
        maps = (irradiance, prefiltered)
        self._maps[id(environment)] = (weakref.ref(environment), maps)
        return maps

    def release(self) -> None:
        for p in self._passes.values():
            p.release()
        self._passes.clear()
        if self._lut is not None:
            self._lut.release()
            self._lut = None
        for _, maps in self._maps.values():
            for tex in maps:
                tex.release()
        self._maps.clear()
