"""Colour quantisation (notes §1.3): fewer bits per channel, dithering, palettes.

Inputs are float colours in [0, 1], (H, W, 3). ``reduce_bits`` maps each channel to
2^bits levels and returns uint8 values spread over 0..255 (so banding shows on screen);
``bits=(4,)`` first converts to grey (Rec. 709 luma). Dithering:

* ``none``: round to the nearest level.
* ``bayer4`` / ``bayer8``: ordered dithering, adds the Bayer threshold matrix (tiled over the
  image, values in (-0.5, 0.5) of one level) before rounding; vectorised numpy.
* ``floyd-steinberg``: error diffusion (7/16, 3/16, 5/16, 1/16). It is sequential by nature,
  so it runs in Pillow's C quantiser, one channel at a time against a palette of the levels.

``palette`` reduces to N colours with Pillow's median cut (optionally refined by k-means).
Everything here is deterministic: the same input gives the same bytes.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

DITHERS = ("none", "bayer4", "bayer8", "floyd-steinberg")
PALETTE_METHODS = ("median-cut", "kmeans")
LUMA = np.array([0.2126, 0.7152, 0.0722])


def bayer_matrix(n: int) -> np.ndarray:
    """The n x n Bayer index matrix (n a power of two), values 0 .. n^2 - 1."""
    m = np.zeros((1, 1), dtype=np.int64)
    while m.shape[0] < n:
        m = np.block([[4 * m, 4 * m + 2], [4 * m + 3, 4 * m + 1]])
    return m


def parse_bits(text) -> tuple[int, ...]:
    """Bits per channel from ``8``, ``16``, ``5,6,5`` (R,G,B) or one value below 8 (grey);
    each value 1..8, or 16 alone. See ``is_grey``."""
    if isinstance(text, (tuple, list)):
        values = tuple(int(v) for v in text)
    else:
        try:
            values = tuple(int(v) for v in str(text).split(","))
        except ValueError:
            raise InputError(f"--bits {text!r}: expected N, N,N,N or 16") from None
    if values == (16,):
        return values
    if len(values) not in (1, 3) or not all(1 <= v <= 8 for v in values):
        raise InputError(f"--bits {text!r}: expected one value (every channel) or three "
                         "(R,G,B), each 1..8, or 16 for 16-bit PNG")
    return values


def is_grey(bits: tuple[int, ...]) -> bool:
    """One value below 8 means a grey image of that depth (``--bits 4``)."""
    return len(bits) == 1 and bits[0] < 8


def reduce_bits(rgb: np.ndarray, bits, dither: str = "none", grey: bool = False) -> np.ndarray:
    """Quantise float RGB (H, W, 3) in [0, 1] to ``bits`` per channel; uint8 (H, W, 3), or
    (H, W) when ``grey``. See the module docstring for the dithering modes."""
    if dither not in DITHERS:
        raise InputError(f"unknown dithering {dither!r}; choose one of {', '.join(DITHERS)}")
    x = np.clip(np.asarray(rgb, dtype=np.float64), 0.0, 1.0)
    if grey:
        x = (x @ LUMA)[..., None]
    bits = tuple(bits) * (x.shape[-1] if len(tuple(bits)) == 1 else 1)
    if len(bits) != x.shape[-1]:
        raise InputError(f"bits {bits} do not match {x.shape[-1]} channels")
    out = np.empty(x.shape, dtype=np.uint8)
    for c, b in enumerate(bits):
        levels = (1 << b) - 1
        if dither == "floyd-steinberg":
            index = _floyd_steinberg(x[..., c], levels)
        else:
            v = x[..., c] * levels
            if dither != "none":
                n = int(dither.removeprefix("bayer"))
                t = (bayer_matrix(n) + 0.5) / (n * n) - 0.5  # zero-mean thresholds
                h, w = v.shape
                v = v + np.tile(t, (h // n + 1, w // n + 1))[:h, :w]
            index = np.clip(np.rint(v), 0, levels)
        out[..., c] = np.rint(index * (255.0 / levels)).astype(np.uint8)
    return out[..., 0] if grey else out


def _floyd_steinberg(channel: np.ndarray, levels: int) -> np.ndarray:
    """Level index (H, W) of one channel after Floyd-Steinberg error diffusion (Pillow)."""
    from PIL import Image

    grey = np.rint(channel * 255.0).astype(np.uint8)
    img = Image.fromarray(np.repeat(grey[..., None], 3, axis=2), "RGB")
    palette_values = np.rint(np.arange(levels + 1) * (255.0 / levels)).astype(np.uint8)
    pal = Image.new("P", (1, 1))
    entries = np.repeat(palette_values[:, None], 3, axis=1).reshape(-1)
    pal.putpalette(np.concatenate([entries, np.zeros(768 - entries.size, np.uint8)]).tolist())
    quantised = img.quantize(palette=pal, dither=Image.Dither.FLOYDSTEINBERG)
    return np.asarray(quantised, dtype=np.float64)


def palette(rgb: np.ndarray, colors: int, method: str = "median-cut",
            dither: str = "none") -> np.ndarray:
    """Reduce float RGB (H, W, 3) to ``colors`` colours (2..256); uint8 (H, W, 3)."""
    from PIL import Image

    if not 2 <= int(colors) <= 256:
        raise InputError(f"--palette {colors}: the number of colours must be 2..256")
    if method not in PALETTE_METHODS:
        raise InputError(f"unknown palette method {method!r}; choose "
                         f"{', '.join(PALETTE_METHODS)}")
    if dither not in ("none", "floyd-steinberg"):
        raise InputError("palette quantisation dithers with 'none' or 'floyd-steinberg'")
    img = Image.fromarray(np.rint(np.clip(rgb, 0, 1) * 255).astype(np.uint8), "RGB")
    q = img.quantize(colors=int(colors), method=Image.Quantize.MEDIANCUT,
                     kmeans=8 if method == "kmeans" else 0,
                     dither=Image.Dither.FLOYDSTEINBERG if dither != "none"
                     else Image.Dither.NONE)
    return np.asarray(q.convert("RGB"))
