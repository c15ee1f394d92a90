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

Transparent objects (``material.transparent``: opacity < 1, glTF alphaMode BLEND) are
drawn after the opaque scene, tested against its depth without writing depth; they do not
appear in depth, ids or the other exact channels, which describe the nearest opaque
surface.
"""

from __future__ import annotations

import numpy as np

from ...gl.fullscreen import FullScreenPass

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
        self.size = size
        self._multisample = None  # (samples, sums framebuffer), made for an MSAA depth
        # zbuffer glo -> (that zbuffer, the OIT framebuffer using it). The zbuffer object is
        # kept to tell a live buffer from a released one whose GL name was reused.
        self._targets: dict[int, tuple] = {}
        self.composite = FullScreenPass(ctx, "post/oit_composite.frag")

    def _sums(self, samples: int):
        """The framebuffer the layers are summed into: the textures themselves, or for a
        multisampled depth buffer multisampled sums (resolved into the textures by
        ``end``, so transparent edges are anti-aliased like opaque ones)."""
        if not samples:
            return self.clear_fbo
        if self._multisample is None or self._multisample[0] != samples:
            self._release_multisample()
            ctx = self.ctx
            bufs = [ctx.renderbuffer(self.size, 4, samples=samples, dtype="f4"),
                    ctx.renderbuffer(self.size, 1, samples=samples, dtype="f4")]
            self._multisample = (samples, ctx.framebuffer(bufs), bufs)
        return self._multisample[1]

    def begin(self, zbuffer):
        """Clear the sums and bind them with the opaque scene's depth (test only); the
        sums are multisampled when that depth buffer is."""
        sums = self._sums(zbuffer.samples)
        sums.clear(0.0, 0.0, 0.0, 0.0)
        key = zbuffer.glo
        if key in self._targets and self._targets[key][0] is not zbuffer:
            self._targets.pop(key)[1].release()
        if key not in self._targets:
            self._targets[key] = (zbuffer, self.ctx.framebuffer(sums.color_attachments,
                                                                zbuffer))
        fbo = self._targets[key][1]
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
        if self._multisample is not None and fbo.samples:
            # Average the samples' sums. The reveal sum is -log(transmittance), so a pixel
            # a layer half covers gets the geometric rather than the arithmetic mean of
            # its samples' transmittance (1 - a/2 vs sqrt(1 - a): 0.75 vs 0.71 at a = 1/2).
            ctx.copy_framebuffer(self.clear_fbo, self._multisample[1])
        target.use()
        ctx.disable(ctx.DEPTH_TEST)
        ctx.enable(ctx.BLEND)
        # "over" for colour and for coverage: alpha_out = a + alpha_dst (1 - a), so an
        # opaque background stays opaque and a transparent one gets the layers' coverage.
        ctx.blend_func = (ctx.SRC_ALPHA, ctx.ONE_MINUS_SRC_ALPHA, ctx.ONE,
                          ctx.ONE_MINUS_SRC_ALPHA)
        self.composite.draw({"u_accum": self.accum, "u_reveal": self.reveal})
        ctx.disable(ctx.BLEND)
        ctx.enable(ctx.DEPTH_TEST)

    def _release_multisample(self) -> None:
        if self._multisample is not None:
            self._multisample[1].release()
            for buf in self._multisample[2]:
                buf.release()
        self._multisample = None

    def release(self) -> None:
        for _, fbo in self._targets.values():
            fbo.release()
        self._targets.clear()
        self._release_multisample()
        for obj in (self.clear_fbo, self.accum, self.reveal):
            obj.release()
        self.composite.release()


def split_transparent(scene):
    """(opaque scene, transparent scene or None): views of ``scene`` by material opacity."""
    if not any(o.material.transparent for o in scene.objects):
        return scene, None
    return (scene.view(objects=[o for o in scene.objects if not o.material.transparent]),
            scene.view(objects=[o for o in scene.objects if o.material.transparent]))
