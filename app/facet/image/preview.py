"""Colourised previews, so a person can look at depth and id images.

* depth: near is bright, far is dark, along a viridis-like ramp between the nearest and the
  farthest hit; no hit is black.
* ids: each id gets a fixed colour (hue stepped by the golden ratio); background is black.
* normals: the usual n * 0.5 + 0.5.
"""

from __future__ import annotations

import numpy as np

# Anchors of a perceptually ordered ramp (viridis-like), dark to bright.
_RAMP = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]],
                 dtype=np.float64)
_GOLDEN = 0.618033988749895


def ramp(t: np.ndarray) -> np.ndarray:
    """(…,) values in [0, 1] -> (…, 3) uint8 along the ramp."""
    x = np.clip(t, 0, 1) * (len(_RAMP) - 1)
    i = np.minimum(x.astype(int), len(_RAMP) - 2)
    f = (x - i)[..., None]
    return np.rint(_RAMP[i] * (1 - f) + _RAMP[i + 1] * f).astype(np.uint8)


_RAMP_LUT = ramp(np.linspace(0.0, 1.0, 256))  # per-pixel work is one table look-up


def depth_preview(depth: np.ndarray) -> np.ndarray:
    hit = depth > 0
    out = np.zeros(depth.shape + (3,), np.uint8)
    if hit.any():
        d = depth[hit]
        lo, hi = d.min(), d.max()
        level = ((hi - d) * (255.0 / max(hi - lo, 1e-12))).astype(np.uint8)  # near = 255
        out[hit] = _RAMP_LUT[level]
    return out


def id_colors(count: int) -> np.ndarray:
    """(count, 3) uint8: the colour of ids 0 .. count-1 (golden-ratio hue steps)."""
    hue = (np.arange(count) * _GOLDEN + 0.1) % 1.0
    # HSV (hue, 0.65, 0.95) to RGB, vectorised.
    h6 = hue * 6.0
    k = np.stack([(5 + h6) % 6, (3 + h6) % 6, (1 + h6) % 6], axis=-1)
    rgb = 0.95 - 0.95 * 0.65 * np.clip(np.minimum(k, 4 - k), 0, 1)
    return np.rint(rgb * 255).astype(np.uint8)


def ids_preview(ids: np.ndarray) -> np.ndarray:
    lut = np.vstack([np.zeros((1, 3), np.uint8), id_colors(int(ids.max()) + 1 if ids.size
                                                          else 0)])
    return lut[np.maximum(ids, -1) + 1]  # background (-1) -> row 0, black


def normals_preview(normals: np.ndarray) -> np.ndarray:
    hit = np.any(normals != 0, axis=-1)
    out = np.rint((np.clip(normals, -1, 1) * 0.5 + 0.5) * 255).astype(np.uint8)
    out[~hit] = 0
    return out
