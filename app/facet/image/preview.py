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


# Palette of indexed depth previews: 0 is "no hit" (black), 1..255 run from far to near.
_DEPTH_PALETTE = np.vstack([np.zeros((1, 3), np.uint8), ramp(np.linspace(0.0, 1.0, 255))])


def depth_indexed(depth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(H, W) uint8 palette indices and the (256, 3) palette of the depth preview. Written
    as an indexed PNG: a third of the bytes of RGB to compress."""
    hit = depth > 0
    index = np.zeros(depth.shape, np.uint8)
    if hit.any():
        d = depth[hit]
        lo, hi = d.min(), d.max()
        index[hit] = 255 - ((d - lo) * (254.0 / max(hi - lo, 1e-12))).astype(np.uint8)
    return index, _DEPTH_PALETTE


def id_colors(count: int) -> np.ndarray:
    """(count, 3) uint8: the colour of ids 0 .. count-1 (golden-ratio hue steps)."""
    hue = (np.arange(count) * _GOLDEN + 0.1) % 1.0
    # HSV (hue, 0.65, 0.95) to RGB, vectorised.
    h6 = hue * 6.0
    k = np.stack([(5 + h6) % 6, (3 + h6) % 6, (1 + h6) % 6], axis=-1)
    rgb = 0.95 - 0.95 * 0.65 * np.clip(np.minimum(k, 4 - k), 0, 1)
    return np.rint(rgb * 255).astype(np.uint8)


def ids_indexed(ids: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Palette indices (id + 1; 0 = background) and palette, or None beyond 255 ids."""
    top = int(ids.max()) if ids.size else -1
    if top >= 255:
        return None
    palette = np.vstack([np.zeros((1, 3), np.uint8), id_colors(max(top + 1, 0))])
    return (np.maximum(ids, -1) + 1).astype(np.uint8), palette


def ids_preview(ids: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8: a fixed colour per id, background black."""
    lut = np.vstack([np.zeros((1, 3), np.uint8), id_colors(int(ids.max()) + 1 if ids.size
                                                          else 0)])
    return lut[np.maximum(ids, -1) + 1]


def normals_preview(normals: np.ndarray) -> np.ndarray:
    hit = np.any(normals != 0, axis=-1)
    out = np.rint((np.clip(normals, -1, 1) * 0.5 + 0.5) * 255).astype(np.uint8)
    out[~hit] = 0
    return out
