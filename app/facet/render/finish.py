"""Colour finishing: the last pass of every render, offscreen or in a window.

It turns what the passes drew (linear light, premultiplied by coverage, perhaps a sum of N
supersamples) into what is returned or shown: the mean of the samples, straight alpha over a
transparent background (what PNG means: an edge keeps its object's colour and its coverage
goes into alpha; pixels nothing covers keep the background's colour), and the sRGB encoding
in the colour-managed mode (facet.image.colorspace states both modes). When none of these
applies the pass is skipped: the picture is read or shown as drawn.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..gl.fullscreen import FullScreenPass


@dataclass(frozen=True)
class Finish:
    """What finishing does to one render's colour."""

    scale: float = 1.0  # 1 / samples accumulated
    srgb: bool = False
    empty: tuple[float, float, float] | None = None  # unpremultiply; empty pixels' colour
    clamp: bool = True  # colour to [0, 1]; False: radiance kept (float output of radiance)

    @property
    def needed(self) -> bool:
        return self.scale != 1.0 or self.srgb or self.empty is not None


def finish_for(background, srgb: bool, samples: int = 1, clamp: bool = True) -> Finish:
    """The finishing of a render over ``background`` (straight RGBA, linear; alpha < 1:
    transparent) that summed ``samples`` pictures; ``clamp`` False keeps colour above 1
    (linear radiance into float output)."""
    bg = np.asarray(background, dtype=np.float64)
    empty = tuple(float(c) for c in bg[:3]) if bg[3] < 1.0 else None
    return Finish(1.0 / samples, srgb, empty, clamp)


class Finisher:
    """The finishing pass (glsl/post/finish.frag) of one context."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.pass_ = FullScreenPass(ctx, "post/finish.frag")

    def draw(self, source, target, finish: Finish) -> None:
        """Finish ``source`` (a float texture) into the framebuffer ``target``."""
        ctx = self.ctx
        target.use()
        ctx.disable(ctx.DEPTH_TEST | ctx.BLEND)
        self.pass_.draw({"u_source": source}, u_scale=float(finish.scale),
                        u_unpremultiply=finish.empty is not None,
                        u_empty=finish.empty or (0.0, 0.0, 0.0), u_encode_srgb=finish.srgb,
                        u_clamp=finish.clamp)
        ctx.enable(ctx.DEPTH_TEST)

    def release(self) -> None:
        self.pass_.release()
