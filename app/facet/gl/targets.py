"""Render targets (framebuffers) of one image size, and readback into numpy with row 0 on top.

A ``Targets`` makes what a render asks for on first use and keeps it for the next frame:

* ``color(dtype)``: single-sample colour (a texture, so later passes can read it) with the
  shared depth buffer; dtype ``f1`` (RGBA8, uint8 readback) or ``f4`` (RGBA32F, float32
  readback: 16-bit output, dithering, linear light before sRGB encoding).
* ``multisample(samples, dtype)``: multisampled colour and depth, resolved into
  ``color(dtype)``; one sample count at a time (a new count releases the old buffers).
* ``output(dtype)``: where the colour-finishing pass writes (facet.render.finish).
* the exact auxiliary channels, never blended, in attachments at locations 1, 2, ... after
  colour in the order of ``AUX_ATTACHMENTS`` (the fragment shader gets the same locations
  as defines, ``OUT_DEPTH_IDS`` etc.; see ``aux_locations``):

  depth_ids RG32UI   the bits of the float32 linear depth along the camera axis (0 =
                     nothing hit) and the object id + 1 (0 = nothing): the channels
                     ``depth`` and ``ids``, the default outputs, in one attachment
  normals   RGBA32F  world-space unit normal (xyz), 0 = nothing
  position  RGBA32F  world-space position (xyz), 0 = nothing
  uv        RG32F    texture coordinates, 0 = nothing

Depth and ids share an attachment because every attachment costs a software rasteriser
per fragment (llvmpipe, 1024x1024, 20k faces: one RG32UI adds 0.9 ms to a 6-7 ms frame,
R32F + R32I 2.3 ms); the pair is read back once and split. Ids are stored shifted by one
because moderngl clears integer attachments through the float path: the bit pattern of
0.0 is integer 0, so "clear to 0" is the only exact integer clear.

Offscreen targets are drawn upside down (``FLIP_Y``: clip-space y negated, front faces
clockwise), so that GL's bottom-up rows read back as an image with row 0 at the top, straight
into the numpy array with no flipping copy.
"""

from __future__ import annotations

import contextlib

import moderngl
import numpy as np

from ..errors import InputError
from ..options.render import MSAA_CHOICES, OUTPUTS
from .context import max_image_size

# Auxiliary attachment -> (components, GL dtype, numpy dtype); order fixes the locations.
AUX_ATTACHMENTS = {
    "depth_ids": (2, "u4", np.uint32),
    "normals": (4, "f4", np.float32),
    "position": (4, "f4", np.float32),
    "uv": (2, "f4", np.float32),
}
# Auxiliary channel -> the attachment it is read from.
AUX_CHANNELS = {"depth": "depth_ids", "ids": "depth_ids", "normals": "normals",
                "position": "position", "uv": "uv"}
assert set(AUX_CHANNELS) == set(OUTPUTS) - {"color", "spp"}

# Colour target formats and their readback dtypes.
COLOR_DTYPES = {"f1": np.uint8, "f4": np.float32}
# Clip-space y flip applied to offscreen renders (see the module docstring).
FLIP_Y = np.diag([1.0, -1.0, 1.0, 1.0])


def aux_locations(channels) -> dict[str, int]:
    """Fragment output location of each attachment the requested auxiliary channels need
    (1, 2, ... in order); ``channels`` may name attachments too."""
    needed = {AUX_CHANNELS.get(c, c) for c in channels}
    wanted = [a for a in AUX_ATTACHMENTS if a in needed]  # anything else: no attachment
    return {a: i + 1 for i, a in enumerate(wanted)}


@contextlib.contextmanager
def writing(fbo: moderngl.Framebuffer, *, colour: bool = True, exact: bool = True):
    """Within this block, draws and clears of ``fbo`` write its colour (the first
    attachment) only if ``colour``, and its exact channels' attachments only if ``exact``.
    GL leaves a draw buffer a shader does not write undefined, so colour-only passes (the
    sky, the wireframe overlay) mask the exact channels; the exact-channel pass computes no
    colour and masks it, so its clear clears the depth buffer alone (glClear honours the
    mask)."""
    mask = fbo.color_mask
    off = (False,) * 4
    fbo.color_mask = (mask[0] if colour else off,
                      *(m if exact else off for m in mask[1:]))
    try:
        yield
    finally:
        fbo.color_mask = mask


def clear_frame(fbo: moderngl.Framebuffer, colour, exact: bool = False) -> None:
    """Clear the bound framebuffer ``fbo`` for a new picture: colour to ``colour`` (RGBA),
    depth to 1, and with ``exact`` (an ``aux`` target) the exact channels' attachments to 0
    ("nothing").
    Everything is cleared on the framebuffer about to be drawn: llvmpipe records such
    clears into the pass that draws, while clearing another framebuffer that shares the
    attachments is a pass over memory of its own (~1 ms a frame for 1024x1024 RG32UI)."""
    if not exact:
        fbo.clear(*colour, depth=1.0)
        return
    with writing(fbo, colour=False):
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    depth_mask, fbo.depth_mask = fbo.depth_mask, False  # cleared above
    try:
        with writing(fbo, exact=False):
            fbo.clear(*colour)
    finally:
        fbo.depth_mask = depth_mask


@contextlib.contextmanager
def allocating(size, what: str = "image buffers"):
    """A GL error while making buffers of ``size`` (width, height) -> one line naming the
    likely cause (the driver out of memory: GL reports it as an incomplete framebuffer or
    an out-of-memory error), not a traceback."""
    try:
        yield
    except moderngl.Error as exc:
        w, h = size
        raise InputError(f"the GL could not make {w}x{h} {what} ({str(exc).strip()}): "
                         "most likely out of memory for this size; render smaller (--size), "
                         "with fewer samples (--msaa, --ssaa), or on a larger GPU") from None


def _allocates(method):
    """A Targets method that makes buffers on first use, under ``allocating``."""
    import functools

    @functools.wraps(method)
    def wrapper(self, *args, **kwargs):
        with allocating(self.size):
            return method(self, *args, **kwargs)
    return wrapper

class Targets:
    """The framebuffers of one image size (see the module docstring)."""

    def __init__(self, ctx: moderngl.Context, width: int, height: int):
        check_size(ctx, width, height)
        self.ctx, self.width, self.height = ctx, width, height
        self.size = (width, height)
        with allocating(self.size):
            self.zbuffer = ctx.depth_renderbuffer(self.size)
        self._color: dict[str, tuple] = {}  # dtype -> (texture, framebuffer)
        self._output: dict[str, tuple] = {}  # dtype -> (texture, framebuffer)
        self._multisample: dict[tuple[int, str], tuple] = {}  # (samples, dtype) -> buffers
        self._aux: dict[str, tuple] = {}  # attachment -> (renderbuffer, framebuffer to clear it)
        self._aux_targets: dict[tuple, moderngl.Framebuffer] = {}
        self._aux_read: dict[str, np.ndarray] = {}  # attachment -> read since its last draw
        self._pair: np.ndarray | None = None  # where depth_ids is read to (kept)

    @_allocates
    def color(self, dtype: str = "f1") -> moderngl.Framebuffer:
        """The single-sample colour target with depth; ``color_texture`` is its colour."""
        if dtype not in COLOR_DTYPES:
            raise InputError(f"colour dtype must be one of {tuple(COLOR_DTYPES)}, got {dtype!r}")
        if dtype not in self._color:
            tex = self.ctx.texture(self.size, 4, dtype=dtype)
            self._color[dtype] = (tex, self.ctx.framebuffer([tex], self.zbuffer))
        return self._color[dtype][1]

    def color_texture(self, dtype: str = "f1") -> moderngl.Texture:
        self.color(dtype)
        return self._color[dtype][0]

    @_allocates
    def output(self, dtype: str = "f1") -> moderngl.Framebuffer:
        """A colour-only target for the finishing pass."""
        if dtype not in self._output:
            tex = self.ctx.texture(self.size, 4, dtype=dtype)
            self._output[dtype] = (tex, self.ctx.framebuffer([tex]))
        return self._output[dtype][1]

    @_allocates
    def multisample(self, samples: int, dtype: str = "f1") -> moderngl.Framebuffer:
        """A multisampled colour + depth target (``samples`` in MSAA_CHOICES, within the
        context's maximum: facet.options.render.clamp_msaa decides before this)."""
        if samples not in MSAA_CHOICES or not samples:
            raise InputError(f"msaa must be one of {MSAA_CHOICES[1:]}, got {samples!r}")
        if samples > self.ctx.max_samples:
            raise InputError(f"msaa={samples} is more than this GL supports "
                             f"(max {self.ctx.max_samples} samples)")
        key = (samples, dtype)
        if key not in self._multisample:
            # moderngl re-binds the bound framebuffer after making one: bind a live one
            # before releasing the old count's (a released one there is GL_INVALID_OPERATION).
            self.color(dtype).use()
            for other in [k for k in self._multisample if k[0] != samples]:
                self._release_all(self._multisample.pop(other))
            color = self.ctx.renderbuffer(self.size, 4, samples=samples, dtype=dtype)
            depth = self.ctx.depth_renderbuffer(self.size, samples=samples)
            self._multisample[key] = (self.ctx.framebuffer([color], depth), depth, color)
        return self._multisample[key][0]

    def resolve(self, multisample: moderngl.Framebuffer, dtype: str) -> moderngl.Framebuffer:
        """Average the samples of ``multisample``'s colour into ``color(dtype)``."""
        target = self.color(dtype)
        self.ctx.copy_framebuffer(target, multisample)
        return target

    @_allocates
    def _channel(self, name: str) -> tuple:
        if name not in self._aux:
            components, dtype, _ = AUX_ATTACHMENTS[name]
            rb = self.ctx.renderbuffer(self.size, components, dtype=dtype)
            self._aux[name] = (rb, self.ctx.framebuffer([rb]))
        return self._aux[name]

    @_allocates
    def aux(self, channels, dtype: str = "f1") -> moderngl.Framebuffer:
        """Colour plus the requested auxiliary channels at the locations of
        ``aux_locations``, with the shared depth buffer; the caller clears it
        (``clear_frame``)."""
        names = tuple(aux_locations(channels))
        self._aux_read.clear()  # drawn over now
        key = (names, dtype)
        if key not in self._aux_targets:
            self._aux_targets[key] = self.ctx.framebuffer(
                [self.color_texture(dtype), *(self._channel(n)[0] for n in names)],
                self.zbuffer)
        return self._aux_targets[key]

    def read_color(self, fbo: moderngl.Framebuffer, dtype: str) -> np.ndarray:
        """(H, W, 4) uint8 (or float32 for ``f4``) of ``fbo``'s colour, row 0 at the top."""
        return self._read(fbo, 4, dtype, COLOR_DTYPES[dtype])

    def read_aux(self, name: str) -> np.ndarray:
        """(H, W) or (H, W, k) array of an auxiliary channel drawn by the last ``aux``
        target (ids shifted back: -1 = background; normals and position without w)."""
        attachment = AUX_CHANNELS[name]
        components, dtype, np_dtype = AUX_ATTACHMENTS[attachment]
        if attachment == "depth_ids":  # read once for both channels
            if attachment not in self._aux_read:
                # Into a buffer kept for the next frame: only the two channels made from
                # it are new memory (fresh pages cost a virtual machine ~1 ms per 4 MB).
                if self._pair is None:
                    self._pair = np.empty((self.height, self.width, 2), np.uint32)
                self._channel(attachment)[1].read_into(self._pair, components=components,
                                                       attachment=0, dtype=dtype)
                self._aux_read[attachment] = self._pair
            pair = self._aux_read[attachment]
            if name == "depth":
                return np.ascontiguousarray(pair[..., 0]).view(np.float32)
            return pair[..., 1].view(np.int32) - 1
        out = self._read(self._channel(attachment)[1], components, dtype, np_dtype)
        if components == 4:
            out = np.ascontiguousarray(out[..., :3])
        return out

    def _read(self, fbo, components: int, dtype: str, np_dtype) -> np.ndarray:
        shape = (self.height, self.width) + ((components,) if components > 1 else ())
        out = np.empty(shape, dtype=np_dtype)
        # Rows were drawn flipped (FLIP_Y), so GL's first row is the image's top row.
        fbo.read_into(out, components=components, attachment=0, dtype=dtype)
        return out

    @staticmethod
    def _release_all(objects) -> None:
        for obj in objects:
            obj.release()

    def release(self) -> None:
        for fbo in self._aux_targets.values():
            fbo.release()
        for group in (*self._aux.values(), *self._multisample.values()):
            self._release_all(group)
        for tex, fbo in (*self._color.values(), *self._output.values()):
            fbo.release()
            tex.release()
        self.zbuffer.release()
        for table in (self._aux_targets, self._aux, self._multisample, self._color,
                      self._output, self._aux_read):
            table.clear()


def check_size(ctx: moderngl.Context, width, height) -> None:
    limit = max_image_size(ctx)
    for name, v in (("width", width), ("height", height)):
        if not isinstance(v, (int, np.integer)) or isinstance(v, bool):
            raise InputError(f"image {name} must be an integer, got {v!r}")
        if not 1 <= v <= limit:
            raise InputError(f"image {name} must be between 1 and {limit} on this GL "
                             f"({ctx.info['GL_RENDERER']}), got {v}")
    from ..budgets import check_pixels

    check_pixels(int(width), int(height), "image size")



class Canvas:
    """A window-like framebuffer without a window: RGBA8 colour and depth of one size, drawn
    bottom-up as a window's is (``Renderer.present``), read back top row first. What the
    headless viewer (facet.viewing.session) draws into."""

    def __init__(self, ctx: moderngl.Context, width: int, height: int):
        check_size(ctx, width, height)
        self.ctx, self.size = ctx, (int(width), int(height))
        with allocating(self.size, "the viewer's canvas"):
            self._color = ctx.texture(self.size, 4)
            self._depth = ctx.depth_renderbuffer(self.size)
            self.framebuffer = ctx.framebuffer([self._color], self._depth)

    def read(self) -> np.ndarray:
        """The picture, (H, W, 3) uint8, row 0 at the top (call with the context current)."""
        w, h = self.size
        data = self.framebuffer.read(viewport=(0, 0, w, h), components=3)
        return np.frombuffer(data, np.uint8).reshape(h, w, 3)[::-1].copy()

    def release(self) -> None:
        for obj in (self.framebuffer, self._depth, self._color):
            obj.release()
