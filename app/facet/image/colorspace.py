"""Colour management, stated once.

facet has two colour modes:

* default ("as the notes"): every colour value (material colours, light colours, texture
  bytes / 255, vertex colours) goes into the shading equation as given, and the equation's
  result is written as the pixel value. The analytic tests rely on this.
* sRGB (``--srgb``, ``Renderer(srgb=True)``): inputs are taken to be sRGB-encoded and are
  linearised (textures by the GPU's sRGB sampling, everything else by ``srgb_to_linear``),
  lighting happens in linear space on a float target (so MSAA averages linear light), and
  the result is encoded back to sRGB for 8-bit output.

Float colour out (``float_color``) is never sRGB-encoded, in any engine and either mode:
linear light in the sRGB mode (and for glTF materials, whose model is linear, in both).
"""

from __future__ import annotations

import numpy as np

from ..srgb import linear_to_srgb, srgb_to_linear

__all__ = ["linear_to_srgb", "srgb_to_linear", "unpremultiply"]


def unpremultiply(rgba: np.ndarray, empty=None) -> np.ndarray:
    """Straight alpha from premultiplied colour, in place; returns ``rgba``. Pixels with
    alpha 0 get the colour ``empty`` (floats in [0, 1]) when given.

    Renders over a transparent background are drawn premultiplied (the background cleared
    to rgb * alpha), so MSAA resolves, supersample means and transparent layers average
    correctly; files and arrays get straight alpha (what PNG means), so an edge pixel keeps
    its object's colour instead of fading towards the background's. uint8 images round.
    """
    full = 255 if rgba.dtype == np.uint8 else 1.0
    a = rgba[..., 3]
    partial = (a > 0) & (a < full)
    if partial.any():
        rgb = rgba[..., :3][partial].astype(np.float64) * (full / a[partial, None])
        if rgba.dtype == np.uint8:
            rgb = np.rint(np.clip(rgb, 0, 255))
        rgba[..., :3][partial] = rgb
    if empty is not None:
        fill = np.asarray(empty, dtype=np.float64) * full
        rgba[..., :3][a == 0] = np.rint(fill) if rgba.dtype == np.uint8 else fill
    return rgba
