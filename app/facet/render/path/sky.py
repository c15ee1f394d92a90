"""The path tracer's sky as a light (GL textures of facet.render.path.env_sampling's
distribution): the environment's luminance distribution (cdf, pdf) and the radiance it was
made from, made once per environment.

Light reaching surfaces from the sky is read from that radiance, texel for texel as the
distribution has it: the cube map's filtered texels spread a small sun into neighbours the
distribution gives little density, and each such sample was a firefly. The eye sees the
same radiance filtered between texel centres (the cube map held a different amount of a
small sun's light).
"""

from __future__ import annotations

import weakref

import numpy as np

from .env_sampling import distribution


class SkyLight:
    """The textures of one environment at a time (``textures``)."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._entry = None  # (weakref to the environment, its textures or None)

    def textures(self, environment):
        """(cdf, pdf, radiance, (W, H)) of ``environment``'s latitude-longitude grid; None
        without one, for a sky of one colour (sampled by the cosine about the surface:
        glsl/trace/sky.glsl sample_sky), or a sky that holds no light."""
        equirect = getattr(environment, "equirect", None)
        if equirect is None or environment.uniform_color is not None:
            self.release()
            return None
        entry = self._entry
        if entry is None or entry[0]() is not environment:
            self.release()
            made = distribution(equirect)
            textures = None
            if made is not None:
                cdf, pdf = made
                radiance = np.ascontiguousarray(equirect[..., :3], np.float32)
                textures = [self._texture(array) for array in (cdf, pdf, radiance)]
                # (seen by the eye filtered between texel centres, round the u seam;
                # surfaces' light fetches its texels: glsl/trace/sky.glsl)
                textures[2].filter = (self.ctx.LINEAR, self.ctx.LINEAR)
                textures[2].repeat_y = False
                textures.append((pdf.shape[1], pdf.shape[0]))
            self._entry = (weakref.ref(environment), textures)
        return self._entry[1]

    def _texture(self, array: np.ndarray):
        tex = self.ctx.texture((array.shape[1], array.shape[0]),
                               1 if array.ndim == 2 else 3, array.tobytes(), dtype="f4")
        tex.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
        return tex

    def release(self) -> None:
        if self._entry is not None and self._entry[1] is not None:
            for tex in self._entry[1][:3]:
                tex.release()
        self._entry = None
