"""The sRGB transfer curves (IEC 61966-2-1), elementwise on numpy arrays.

At the bottom of the package (next to errors) because every layer needs them: the scene
(glTF's colours are linear, facet's vertex colours sRGB-encoded), the renderer and the
output stage. How facet uses them is facet.image.colorspace's business.
"""

from __future__ import annotations

import numpy as np


def srgb_to_linear(c) -> np.ndarray:
    """The sRGB decoding curve, elementwise on values in [0, 1]."""
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(c) -> np.ndarray:
    """The sRGB encoding curve, elementwise on values in [0, 1] (clipped first)."""
    c = np.clip(np.asarray(c, dtype=np.float64), 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1 / 2.4) - 0.055)
