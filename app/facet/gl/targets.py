"""Render targets (framebuffers) and readback into numpy arrays with row 0 at the top.

Attachment 0 is always the RGBA8 colour. The auxiliary channels a render asks for follow at
locations 1, 2, ... in the order of ``AUX_CHANNELS`` (the fragment shader gets the same
locations as defines, ``OUT_DEPTH`` etc.; see ``aux_locations``). They are allocated on first
use and never blended:

  depth     R32F   linear depth along the camera axis, 0 = nothing hit
  ids       R32I   object id + 1, 0 = nothing
  normals   RGBA32F  world-space unit normal (xyz), 0 = nothing
  position  RGBA32F  world-space position (xyz), 0 = nothing
  uv        RG32F  texture coordinates, 0 = nothing

Ids are stored shifted by one because moderngl clears integer attachments through the float
path: the bit pattern of 0.0 is integer 0, so "clear to 0" is the only exact integer clear.

With MSAA a multisampled colour target is drawn and resolved into attachment 0; the auxiliary
channels come from a single-sample pass (sampled at pixel centres, exactly as without MSAA).

Offscreen targets are drawn upside down (``FLIP_Y``: clip-space y negated, front faces
clockwise), so that GL's bottom-up rows read back as an image with row 0 at the top, straight
into the numpy array with no flipping copy.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..errors import InputError
from .context import max_image_size

# Auxiliary channel -> (components, GL dtype, numpy dtype); order fixes attachment locations.
AUX_CHANNELS = {
    "depth": (1, "f4", np.float32),
    "ids": (1, "i4", np.int32),
    "normals": (4, "f4", np.float32),
    "position": (4, "f4", np.float32),
    "uv": (2, "f4", np.float32),
}


# Colour target formats: RGBA8 (uint8 readback) or RGBA32F (float32 readback, for 16-bit
# output and dithering from the unrounded shading values).
COLOR_DTYPES = {"f1": np.uint8, "f4": np.float32}


def aux_locations(channels) -> dict[str, int]:
    """Fragment output location of each requested auxiliary channel (1, 2, ... in order)."""
    wanted = [c for c in AUX_CHANNELS if c in channels]
    return {c: i + 1 for i, c in enumerate(wanted)}


MSAA_CHOICES = (0, 2, 4, 8)
# Clip-space y flip applied to offscreen renders (see the module docstring).
FLIP_Y = np.diag([1.0, -1.0, 1.0, 1.0])


class Targets:
    """All framebuffers for one image size and sample count."""

    def __init__(self, ctx: moderngl.Context, width: int, height: int, msaa: int = 0,
                 color_dtype: str = "f1"):
        check_size(ctx, width, height)
        if msaa not in MSAA_CHOICES:
            raise InputError(f"msaa must be one of {MSAA_CHOICES}, got {msaa!r}")
        if msaa > ctx.max_samples:
            raise InputError(f"msaa={msaa} is more than this GL supports "
                             f"(max {ctx.max_samples} samples on {ctx.info['GL_RENDERER']})")
        if color_dtype not in COLOR_DTYPES:
            raise InputError(f"color_dtype must be one of {tuple(COLOR_DTYPES)}, got "
                             f"{color_dtype!r}")
        self.ctx, self.width, self.height, self.msaa = ctx, width, height, msaa
        self.color_dtype = color_dtype
        size = (width, height)
        self.color = ctx.renderbuffer(size, 4, dtype=color_dtype)
        self.zbuffer = ctx.depth_renderbuffer(size)
        self.color_only = ctx.framebuffer([self.color], self.zbuffer)
        self._own = [self.color, self.zbuffer, self.color_only]
        self._aux: dict[str, tuple[moderngl.Renderbuffer, moderngl.Framebuffer]] = {}
        self._targets: dict[tuple[str, ...], moderngl.Framebuffer] = {}
        self.multisample = None
        if msaa:
            self.ms_color = ctx.renderbuffer(size, 4, samples=msaa, dtype=color_dtype)
            self.ms_z = ctx.depth_renderbuffer(size, samples=msaa)
            self.multisample = ctx.framebuffer([self.ms_color], self.ms_z)
            self._own += [self.ms_color, self.ms_z, self.multisample]

    def _channel(self, name: str) -> tuple[moderngl.Renderbuffer, moderngl.Framebuffer]:
        """The buffer of an auxiliary channel and a framebuffer to clear it alone."""
        if name not in self._aux:
            components, dtype, _ = AUX_CHANNELS[name]
            rb = self.ctx.renderbuffer((self.width, self.height), components, dtype=dtype)
            self._aux[name] = (rb, self.ctx.framebuffer([rb]))
        return self._aux[name]

    def begin_aux(self, channels, background) -> moderngl.Framebuffer:
        """Clear colour and the requested auxiliary channels (to 0) and bind a target with
        them at the locations of ``aux_locations``."""
        key = tuple(aux_locations(channels))
        for name in key:
            self._channel(name)[1].clear(0.0, 0.0, 0.0, 0.0)
        if key not in self._targets:
            self._targets[key] = self.ctx.framebuffer(
                [self.color, *(self._channel(n)[0] for n in key)], self.zbuffer)
        self.begin_color(background)
        self._targets[key].use()
        return self._targets[key]

    def begin_color(self, background) -> moderngl.Framebuffer:
        """Clear and bind the colour-only single-sample target."""
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
        """(H, W, 4) uint8 (or float32 for a float colour target), row 0 at the top."""
        return self._read(self.color_only, 4, self.color_dtype, COLOR_DTYPES[self.color_dtype])

    def read_aux(self, name: str) -> np.ndarray:
        """(H, W) or (H, W, k) array of an auxiliary channel drawn by the last ``begin_aux``
        (ids shifted back: -1 = background)."""
        components, dtype, np_dtype = AUX_CHANNELS[name]
        out = self._read(self._channel(name)[1], components, dtype, np_dtype)
        if name == "ids":
            out -= 1
        return out

    def _read(self, fbo, components: int, dtype: str, np_dtype) -> np.ndarray:
        shape = (self.height, self.width) + ((components,) if components > 1 else ())
        out = np.empty(shape, dtype=np_dtype)
        # Rows were drawn flipped (FLIP_Y), so GL's first row is the image's top row.
        fbo.read_into(out, components=components, attachment=0, dtype=dtype)
        return out

    def release(self) -> None:
        for fbo in self._targets.values():
            fbo.release()
        for rb, fbo in self._aux.values():
            fbo.release()
            rb.release()
        for obj in reversed(self._own):
            obj.release()
        self._own.clear()
        self._aux.clear()
        self._targets.clear()


def check_size(ctx: moderngl.Context, width, height) -> None:
    limit = max_image_size(ctx)
    for name, v in (("width", width), ("height", height)):
        if not isinstance(v, (int, np.integer)) or isinstance(v, bool):
            raise InputError(f"image {name} must be an integer, got {v!r}")
        if not 1 <= v <= limit:
            raise InputError(f"image {name} must be between 1 and {limit} on this GL "
                             f"({ctx.info['GL_RENDERER']}), got {v}")
