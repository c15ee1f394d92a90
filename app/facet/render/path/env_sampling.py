"""Importance sampling of an environment by its luminance (numpy, no GL).

The path tracer draws sky directions for next-event estimation from the environment's
latitude-longitude image (``Environment.equirect``): a texel with probability proportional
to its luminance times sin(theta) (its solid angle), then a point uniformly within it. A
texel (x, y) of a W x H image has density p(x, y) = w(x, y) / sum(w) x W H over the unit
square of (u, v), and a direction's density is p / (2 pi^2 sin theta) per steradian.
glsl/trace/path.frag samples by two binary searches: the rows' cumulative shares (the
marginal) in column W of ``cdf``, then the chosen row's own cumulative shares.
"""

from __future__ import annotations

import numpy as np

LUMINANCE = np.array([0.2126, 0.7152, 0.0722], np.float64)


def distribution(equirect: np.ndarray):
    """(cdf (H, W + 1), pdf (H, W)) float32 for ``equirect`` (H, W, 3), or None when it
    is black (nothing to sample: light sampling of the sky is then skipped)."""
    img = np.asarray(equirect, dtype=np.float64)
    h, w = img.shape[:2]
    theta = (np.arange(h) + 0.5) / h * np.pi
    weight = (img[..., :3] @ LUMINANCE) * np.sin(theta)[:, None]
    total = weight.sum()
    if not total > 0:
        return None
    rows = weight.sum(axis=1)
    cdf = np.empty((h, w + 1), np.float64)
    safe = np.where(rows > 0, rows, 1.0)[:, None]
    cdf[:, :w] = np.where(rows[:, None] > 0, np.cumsum(weight, axis=1) / safe,
                          (np.arange(w) + 1.0) / w)
    cdf[:, w] = np.cumsum(rows) / total
    cdf[:, w - 1] = cdf[-1, w] = 1.0 + 1e-6  # the last entries catch every u < 1
    pdf = weight / total * (w * h)
    return cdf.astype(np.float32), pdf.astype(np.float32)
