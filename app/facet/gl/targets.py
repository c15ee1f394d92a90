"""Render targets (framebuffers) and readback into numpy arrays with row 0 at the top.

Attachments of the single-sample target, matching the fragment outputs of glsl/mesh:
  0: RGBA8 colour, 1: R32F linear depth (0 = nothing hit), 2: R32I object id + 1 (0 = none).
Ids are stored shifted by one because moderngl clears integer attachments through the float
path: the bit pattern of 0.0 is integer 0, so "clear to 0" is the only exact integer clear.

With MSAA a multisampled colour target is drawn and resolved into attachment 0; depth and ids
come from a single-sample pass into attachments 1 and 2 (never blended, sampled at pixel
centres, exactly as without MSAA).
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..errors import InputError
from .context import max_image_size

MSAA_CHOICES = (0, 2, 4, 8)


class Targets:
    """All framebuffers for one image size and sample count."""

    def __init__(self, ctx: moderngl.Context, width: int, height: int, msaa: int = 0):
        check_size(ctx, width, height)
        if msaa not in MSAA_CHOICES:
            raise InputError(f"msaa must be one of {MSAA_CHOICES}, got {msaa!r}")
        if msaa > ctx.max_samples:
            raise InputError(f"msaa={msaa} is more than this GL supports "
                             f"(max {ctx.max_samples} samples on {ctx.info['GL_RENDERER']})")
        self.ctx, self.width, self.height, self.msaa = ctx, width, height, msaa
        size = (width, height)
        self.color = ctx.renderbuffer(size, 4)
        self.depth_linear = ctx.renderbuffer(size, 1, dtype="f4")
        self.ids = ctx.renderbuffer(size, 1, dtype="i4")
        self.zbuffer = ctx.depth_renderbuffer(size)
        self._own = [self.color, self.depth_linear, self.ids, self.zbuffer]
        # Full target (colour + depth + ids), a colour-only view and an aux-only view for
        # clearing depth/ids to 0 separately from the background colour.
        self.full = ctx.framebuffer([self.color, self.depth_linear, self.ids], self.zbuffer)
        self.color_only = ctx.framebuffer([self.color], self.zbuffer)
        self.aux_clear = ctx.framebuffer([self.depth_linear, self.ids])
        self._own += [self.full, self.color_only, self.aux_clear]
        self.multisample = None
        if msaa:
            self.ms_color = ctx.renderbuffer(size, 4, samples=msaa)
            self.ms_z = ctx.depth_renderbuffer(size, samples=msaa)
            self.multisample = ctx.framebuffer([self.ms_color], self.ms_z)
            self._own += [self.ms_color, self.ms_z, self.multisample]

    def begin_full(self, background) -> moderngl.Framebuffer:
        """Clear every attachment and bind the single-sample target."""
        self.aux_clear.clear(0.0, 0.0, 0.0, 0.0)
        self.begin_color(background)
        self.full.use()
        return self.full

    def begin_color(self, background) -> moderngl.Framebuffer:
        """Clear and bind the colour-only single-sample target (depth and ids untouched)."""
        self.color_only.use()
        self.color_only.clear(*background, depth=1.0)
        return self.color_only

    def begin_multisample(self, background) -> moderngl.Framebuffer:
        self.multisample.use()
        self.multisample.clear(*background, depth=1.0)
        return self.multisample

    def resolve(self) -> None:
        """Average the samples of the multisampled colour into attachment 0."""
        self.ctx.copy_framebuffer(self.color_only, self.multisample)

    def read_color(self) -> np.ndarray:
        """(H, W, 4) uint8, row 0 at the top."""
        data = self.color_only.read(components=4, attachment=0, dtype="f1")
        return _flip(np.frombuffer(data, np.uint8).reshape(self.height, self.width, 4))

    def read_depth(self) -> np.ndarray:
        """(H, W) float32 linear depth, 0 where nothing was hit, row 0 at the top."""
        data = self.full.read(components=1, attachment=1, dtype="f4")
        return _flip(np.frombuffer(data, np.float32).reshape(self.height, self.width))

    def read_ids(self) -> np.ndarray:
        """(H, W) int32 object ids, -1 for background, row 0 at the top."""
        data = self.full.read(components=1, attachment=2, dtype="i4")
        ids = np.frombuffer(data, np.int32).reshape(self.height, self.width)
        return _flip(ids) - 1

    def release(self) -> None:
        for obj in reversed(self._own):
            obj.release()
        self._own.clear()


def _flip(a: np.ndarray) -> np.ndarray:
    """GL rows run bottom-up; images run top-down."""
    return np.ascontiguousarray(a[::-1])


def check_size(ctx: moderngl.Context, width, height) -> None:
    limit = max_image_size(ctx)
    for name, v in (("width", width), ("height", height)):
        if not isinstance(v, (int, np.integer)) or isinstance(v, bool):
            raise InputError(f"image {name} must be an integer, got {v!r}")
        if not 1 <= v <= limit:
            raise InputError(f"image {name} must be between 1 and {limit} on this GL "
                             f"({ctx.info['GL_RENDERER']}), got {v}")
