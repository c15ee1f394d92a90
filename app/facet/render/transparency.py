"""Order-independent transparency: weighted blended OIT (McGuire and Bavoil 2013).

Why this method: it needs one geometry pass whatever the depth complexity, no sorting and
no per-pixel lists, so it costs the same for intersecting and overlapping objects, and it
runs on GL 3.3 and llvmpipe. Depth peeling would be exact but costs one pass per layer.

The price is an approximation: where layers overlap, their colours are blended by a
depth-weighted mean instead of strictly front to back. Coverage (how much of the opaque
scene shows through) is exact: prod(1 - a_i). The stated error is therefore the difference
between ``oit_two_layers`` (what the method computes, which the render must match) and
``over_two_layers`` (the exact result): for two layers it is bounded by |C1 - C2| times
a1 a2 (a1 + a2 - a1 a2) / (a1 + a2), at most |C1 - C2| / 8 for opacities of 1/2.

Transparent objects (material opacity < 1) are drawn after the opaque scene, tested
against its depth without writing depth; they do not appear in depth, ids or the other
exact channels, which describe the nearest opaque surface.
"""

from __future__ import annotations

import numpy as np

from ..gl.glsl_source import glsl_root
from ..gl.shaders import compile_program

WEIGHT_SCALE, WEIGHT_MIN = 3000.0, 0.01  # w = max(WEIGHT_MIN, WEIGHT_SCALE (1 - z)^3)


def weight(z_window: float) -> float:
    """The shader's depth weight for window-space depth z in [0, 1]."""
    return max(WEIGHT_MIN, WEIGHT_SCALE * (1.0 - z_window) ** 3)


def oit_two_layers(c1, a1, w1, c2, a2, w2, background) -> np.ndarray:
    """What weighted blended OIT gives for two layers over ``background`` (module doc)."""
    c1, c2, bg = (np.asarray(v, dtype=np.float64) for v in (c1, c2, background))
    mean = (w1 * a1 * c1 + w2 * a2 * c2) / (w1 * a1 + w2 * a2)
    reveal = (1 - a1) * (1 - a2)
    return mean * (1 - reveal) + bg * reveal


def over_two_layers(c1, a1, c2, a2, background) -> np.ndarray:
    """Exact front-to-back "over" compositing of layer 1 (front) over layer 2 over bg."""
    c1, c2, bg = (np.asarray(v, dtype=np.float64) for v in (c1, c2, background))
    return a1 * c1 + (1 - a1) * (a2 * c2 + (1 - a2) * bg)


class Transparency:
    """The OIT targets of one image size and the composite pass."""

    def __init__(self, ctx, width: int, height: int):
        self.ctx = ctx
        size = (width, height)
        self.accum = ctx.texture(size, 4, dtype="f4")
        self.reveal = ctx.texture(size, 1, dtype="f4")
        self.clear_fbo = ctx.framebuffer([self.accum, self.reveal])
        self._targets: dict[int, object] = {}  # zbuffer glo -> OIT framebuffer using it
        root = glsl_root()
        self.composite = compile_program(ctx, root / "shadertoy" / "fullscreen.vert",
                                         root / "post" / "oit_composite.frag")
        self.vao = ctx.vertex_array(self.composite.gl, [])

    def begin(self, zbuffer):
        """Clear the sums and bind them with the opaque scene's depth (test only)."""
        self.clear_fbo.clear(0.0, 0.0, 0.0, 0.0)
        key = zbuffer.glo
        if key not in self._targets:
            self._targets[key] = self.ctx.framebuffer([self.accum, self.reveal], zbuffer)
        fbo = self._targets[key]
        fbo.use()
        ctx = self.ctx
        ctx.enable(ctx.DEPTH_TEST | ctx.BLEND)
        ctx.blend_func = ctx.ONE, ctx.ONE
        fbo.depth_mask = False
        return fbo

    def end(self, fbo, target) -> None:
        """Composite the transparent layers over the opaque colour in ``target``."""
        ctx = self.ctx
        fbo.depth_mask = True
        target.use()
        ctx.disable(ctx.DEPTH_TEST)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = ctx.SRC_ALPHA, ctx.ONE_MINUS_SRC_ALPHA
        self.accum.use(location=0)
        self.reveal.use(location=1)
        self.composite.set("u_accum", 0)
        self.composite.set("u_reveal", 1)
        self.vao.render(vertices=3)
        ctx.disable(ctx.BLEND)
        ctx.enable(ctx.DEPTH_TEST)

    def release(self) -> None:
        for fbo in self._targets.values():
            fbo.release()
        for obj in (self.vao, self.clear_fbo, self.accum, self.reveal):
            obj.release()
        self.composite.release()
