"""The materials' images for the tracers: one texture array whose layers are the images the
materials sample, resized to one square side (at most ``MAX_TEXTURE_LAYER``), keyed by
(id(texture), mode) with the modes of facet.render.rays.pack: colour images decoded to
linear (LINEAR, and AS_GIVEN in the sRGB colour mode), data as stored (DATA); NEAREST-
filtered ones resized by repeating texels. Each layer is kept (``cache``) while it is
requested: a scene that gains or loses one image (a material edited, a texture stripped)
converts only that one again."""

from __future__ import annotations

import numpy as np

from . import pack

MAX_TEXTURE_LAYER = 2048  # materials' images are resized to at most this square


def texture_array(ctx, requests: list, srgb: bool, cache: dict | None = None):
    """A mipmapped texture array of the ``requests`` ((texture, mode) pairs) in order; one
    white texel when there are none (every sampler stays valid). ``cache``: the layers of
    the last call, keyed by (id(texture), mode, side, decoded) with the texture kept alive
    beside its layer; left holding this call's layers only."""
    modes = [c.removesuffix(pack.NEAREST) for _, c in requests]
    colour = [c == pack.LINEAR or (c == pack.AS_GIVEN and srgb) for c in modes]
    cache = {} if cache is None else cache
    if requests:
        side = min(max(max(t.pixels.shape[:2]) for t, _ in requests), MAX_TEXTURE_LAYER)
        kept = {}
        for (t, c), decode in zip(requests, colour, strict=True):
            key = (id(t), c, side, decode)
            if key not in kept:
                texture, layer = cache.get(key) or (t, _layer(t.pixels, side, decode,
                                                             c.endswith(pack.NEAREST)))
                kept[key] = (texture, layer)
        cache.clear()
        cache.update(kept)
        layers = [kept[(id(t), c, side, decode)][1]
                  for (t, c), decode in zip(requests, colour, strict=True)]
        # One array, one type (float16 when any layer is); rows flipped: GL's first row is
        # v = 0, the image's bottom (as gl.resources). Filled in place: no stacked copies.
        half = any(x.dtype == np.float16 for x in layers)
        data = np.empty((len(layers), side, side, 4), np.float16 if half else np.uint8)
        as_half = (np.arange(256) / 255.0).astype(np.float16)  # a byte layer, as float16
        for out, x in zip(data, layers, strict=True):
            out[...] = x[::-1] if x.dtype == data.dtype else as_half[x[::-1]]
        dtype = "f2" if half else "f1"
    else:
        cache.clear()
        side, data, dtype = 1, np.full((1, 1, 1, 4), 255, np.uint8), "f1"
    tex = ctx.texture_array((side, side, len(data)), 4, data, dtype=dtype)
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
    exact = pixels.shape[:2] == (side, side)  # no resize: straight to float16
    dtype = np.float16 if exact else np.float32
    table = np.stack([srgb_to_linear(np.arange(256) / 255.0)] * 3 + [np.arange(256) / 255.0],
                     -1).astype(dtype)  # (256, 4): colour decoded, alpha as stored
    values = np.take_along_axis(table, pixels.reshape(-1, 4).astype(np.intp), 0).reshape(
        pixels.shape)
    if exact:
        return values
    values = np.stack([np.asarray(Image.fromarray(np.ascontiguousarray(values[..., k]), "F")
                                  .resize((side, side), resample)) for k in range(4)], -1)
    return np.clip(values, 0.0, None).astype(np.float16)
