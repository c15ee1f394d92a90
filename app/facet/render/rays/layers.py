"""The materials' images for the tracers: one texture array whose layers are the images the
materials sample, resized to one square side (at most ``MAX_TEXTURE_LAYER``), keyed by
(id(texture), mode) with the modes of facet.render.rays.pack: colour images decoded to
linear (LINEAR, and AS_GIVEN in the sRGB colour mode), data as stored (DATA); NEAREST-
filtered ones resized by repeating texels."""

from __future__ import annotations

import numpy as np

from . import pack

MAX_TEXTURE_LAYER = 2048  # materials' images are resized to at most this square


def texture_array(ctx, requests: list, srgb: bool):
    """A mipmapped texture array of the ``requests`` ((texture, mode) pairs) in order; one
    white texel when there are none (every sampler stays valid)."""
    modes = [c.removesuffix(pack.NEAREST) for _, c in requests]
    colour = [c == pack.LINEAR or (c == pack.AS_GIVEN and srgb) for c in modes]
    if requests:
        side = min(max(max(t.pixels.shape[:2]) for t, _ in requests), MAX_TEXTURE_LAYER)
        layers = [_layer(t.pixels, side, decode, c.endswith(pack.NEAREST))
                  for (t, c), decode in zip(requests, colour, strict=True)]
        if any(x.dtype == np.float16 for x in layers):  # one array, one type
            layers = [x if x.dtype == np.float16 else (x / 255.0).astype(np.float16)
                      for x in layers]
        # Rows flipped: GL's first row is v = 0, the image's bottom (as gl.resources).
        data = np.ascontiguousarray(np.stack(layers)[:, ::-1])
        dtype = "f2" if data.dtype == np.float16 else "f1"
    else:
        side, data, dtype = 1, np.full((1, 1, 1, 4), 255, np.uint8), "f1"
    tex = ctx.texture_array((side, side, len(data)), 4, data.tobytes(), dtype=dtype)
    tex.build_mipmaps()
    tex.filter = (ctx.LINEAR_MIPMAP_LINEAR, ctx.LINEAR)
    return tex


def _layer(pixels: np.ndarray, side: int, decode: bool, nearest: bool = False) -> np.ndarray:
    """(side, side, 4) one layer of the texture array: uint8 as stored, or, for an image
    decoded to linear, float16 decoded *before* it is resized (filtering sRGB-encoded bytes
    would darken fine patterns: glTF's TextureLinearInterpolationTest). ``nearest``:
    resized by repeating texels (a nearest-filtered image: glsl/trace/material.glsl reads
    its texels' centres)."""
    from PIL import Image

    from ...image.colorspace import srgb_to_linear

    resample = Image.Resampling.NEAREST if nearest else Image.Resampling.LANCZOS
    if not decode:
        if pixels.shape[:2] == (side, side):
            return pixels
        return np.asarray(Image.fromarray(pixels).resize((side, side), resample))
    values = (np.arange(256) / 255.0).astype(np.float32)[pixels]
    values[..., :3] = srgb_to_linear(np.arange(256) / 255.0).astype(np.float32)[
        pixels[..., :3]]
    if pixels.shape[:2] != (side, side):
        values = np.stack([np.asarray(Image.fromarray(values[..., k], "F").resize(
            (side, side), resample)) for k in range(4)], -1)
    return np.clip(values, 0.0, None).astype(np.float16)
