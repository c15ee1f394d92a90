"""Render targets (framebuffers) and readback into numpy arrays with row 0 at the top.

Attachments of the single-sample target, matching the fragment outputs of glsl/mesh:
  0: RGBA8 colour, 1: R32F linear depth (0 = nothing hit), 2: R32I object id + 1 (0 = none).
Ids are stored shifted by one because moderngl clears integer attachments through the float
path: the bit pattern of 0.0 is integer 0, so "clear to 0" is the only exact integer clear.

With MSAA a multisampled colour target is drawn and resolved into attachment 0; depth and ids
come from a single-sample pass into attachments 1 and 2 (never blended, sampled at pixel
centres, exactly as without MSAA).

Offscreen targets are drawn upside down (``FLIP_Y``: clip-space y negated, front faces
clockwise), so that GL's bottom-up rows read back as an image with row 0 at the top, straight
into the numpy array with no flipping copy.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..errors import InputError
from .context import max_image_size

MSAA_CHOICES = (0, 2, 4, 8)
# Clip-space y flip applied to offscreen renders (see the module docstring).
FLIP_Y = np.diag([1.0, -1.0, 1.0, 1.0])


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

    def _read(self, fbo, attachment: int, components: int, dtype) -> np.ndarray:
        shape = (self.height, self.width) + ((components,) if components > 1 else ())
        out = np.empty(shape, dtype=dtype)
        # Rows were drawn flipped (FLIP_Y), so GL's first row is the image's top row.
        fbo.read_into(out, components=components, attachment=attachment,
                      dtype=np.dtype(dtype).str[1:].replace("u1", "f1"))
        return out

    def read_color(self) -> np.ndarray:
        """(H, W, 4) uint8, row 0 at the top."""
        return self._read(self.color_only, 0, 4, np.uint8)

    def read_depth(self) -> np.ndarray:
        """(H, W) float32 linear depth, 0 where nothing was hit, row 0 at the top."""
        return self._read(self.full, 1, 1, np.float32)

    def read_ids(self) -> np.ndarray:
        """(H, W) int32 object ids, -1 for background, row 0 at the top."""
        ids = self._read(self.full, 2, 1, np.int32)
        ids -= 1
        return ids

    def release(self) -> None:
        for obj in reversed(self._own):
            obj.release()
        self._own.clear()


def check_size(ctx: moderngl.Context, width, height) -> None:
    limit = max_image_size(ctx)
    for name, v in (("width", width), ("height", height)):
        if not isinstance(v, (int, np.integer)) or isinstance(v, bool):
            raise InputError(f"image {name} must be an integer, got {v!r}")
        if not 1 <= v <= limit:
            raise InputError(f"image {name} must be between 1 and {limit} on this GL "
                             f"({ctx.info['GL_RENDERER']}), got {v}")
