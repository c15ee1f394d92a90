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


def depth_preview(depth: np.ndarray) -> np.ndarray:
    hit = depth > 0
    out = np.zeros(depth.shape + (3,), np.uint8)
    if hit.any():
        lo, hi = depth[hit].min(), depth[hit].max()
        t = 1.0 - (depth - lo) / max(hi - lo, 1e-12)  # near = 1 = bright
        out[hit] = ramp(t[hit])
    return out


def ids_preview(ids: np.ndarray) -> np.ndarray:
    hue = (ids.astype(np.float64) * _GOLDEN + 0.1) % 1.0
    # HSV (hue, 0.65, 0.95) to RGB, vectorised.
    h6 = hue * 6.0
    k = np.stack([(5 + h6) % 6, (3 + h6) % 6, (1 + h6) % 6], axis=-1)
    rgb = 0.95 - 0.95 * 0.65 * np.clip(np.minimum(k, 4 - k), 0, 1)
    out = np.rint(rgb * 255).astype(np.uint8)
    out[ids < 0] = 0
    return out


def normals_preview(normals: np.ndarray) -> np.ndarray:
    hit = np.any(normals != 0, axis=-1)
    out = np.rint((np.clip(normals, -1, 1) * 0.5 + 0.5) * 255).astype(np.uint8)
    out[~hit] = 0
    return out
