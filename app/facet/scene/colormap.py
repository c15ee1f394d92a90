"""Per-vertex scalars shown through a named colormap (no GL): matplotlib's colormaps when it
is installed (every name it knows), else a few built in, each sampled from its published
definition at evenly spaced points and interpolated linearly (viridis; Moreland's coolwarm;
grey). Colours come out as facet stores them: sRGB-encoded, as displayed.

``colormap(name)`` gives a function from values in [0, 1] to (N, 3) colours; ``colors_for``
maps scalars with their range (the values' own, or the one given); ``colorbar`` draws a
vertical bar with its range's ends labelled onto a picture (through Pillow).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

# Colours at 0, 1/(n-1), ..., 1 (display values).
BUILTIN = {
    # viridis (van der Walt and Smith, CC0) at 11 points; coolwarm (Moreland) at 5.
    "viridis": [(0.267004, 0.004874, 0.329415), (0.28229, 0.145912, 0.46151),
                (0.253935, 0.265254, 0.529983), (0.206756, 0.371758, 0.553117),
                (0.163625, 0.471133, 0.558148), (0.127568, 0.566949, 0.550556),
                (0.134692, 0.658636, 0.517649), (0.259857, 0.745492, 0.444467),
                (0.477504, 0.821444, 0.318195), (0.741388, 0.873449, 0.149561),
                (0.993248, 0.906157, 0.143936)],
    "coolwarm": [(0.2298, 0.2987, 0.7537), (0.553, 0.6889, 0.9954), (0.8654, 0.8654, 0.8654),
                 (0.958, 0.6028, 0.4818), (0.7057, 0.0156, 0.1502)],
    "gray": [(0.0, 0.0, 0.0), (1.0, 1.0, 1.0)],
}
BUILTIN["grey"] = BUILTIN["gray"]
DEFAULT = "viridis"


def colormap(name: str = DEFAULT):
    """values (N,) in [0, 1] -> (N, 3) float32 display colours, by ``name``."""
    try:
        import matplotlib

        cmap = matplotlib.colormaps[name]
        return lambda t: np.asarray(cmap(np.clip(t, 0, 1)), dtype=np.float32)[..., :3]
    except ImportError:
        pass
    except KeyError:
        raise InputError(f"colormap {name!r}: matplotlib knows no such colormap") from None
    if name not in BUILTIN:
        raise InputError(f"colormap {name!r}: built in are {', '.join(sorted(BUILTIN))} "
                         "(pip install matplotlib for all of its colormaps)")
    table = np.asarray(BUILTIN[name], dtype=np.float64)
    stops = np.linspace(0.0, 1.0, len(table))

    def lookup(t):
        t = np.clip(np.asarray(t, dtype=np.float64), 0, 1)
        return np.stack([np.interp(t, stops, table[:, k]) for k in range(3)],
                        axis=-1).astype(np.float32)

    return lookup


def scalar_range(values, limits=None) -> tuple[float, float]:
    v = np.asarray(values, dtype=np.float64)
    if limits is not None:
        lo, hi = (float(x) for x in limits)
    else:
        finite = v[np.isfinite(v)]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if not (np.isfinite(lo) and np.isfinite(hi)) or hi < lo:
        raise InputError(f"scalar range must be two finite numbers, low <= high, got "
                         f"{(lo, hi)}")
    return lo, hi


def scalars(values, what: str = "values") -> np.ndarray:
    """(N,) float64 of ``values`` (numbers, one per vertex or point); InputError naming
    ``what`` when they are not numbers (text, objects, nested lists)."""
    try:
        v = np.asarray(values, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{what}: expected numbers (one per vertex or point), got "
                         f"{type(values).__name__} of {_kind(values)}") from None
    return v


def _kind(values) -> str:
    """What ``values`` hold, for a message."""
    try:
        first = next(iter(values))
    except (TypeError, StopIteration):
        return "nothing"
    return type(first).__name__


def colors_for(values, name: str = DEFAULT, limits=None) -> np.ndarray:
    """(N, 3) float32 display colours of scalars ``values`` (N,) through colormap ``name``
    over ``limits`` (low, high; default the values' own range; NaN shows grey)."""
    v = np.asarray(values, dtype=np.float64).reshape(-1)
    lo, hi = scalar_range(v, limits)
    t = (v - lo) / (hi - lo) if hi > lo else np.full(len(v), 0.5)
    out = colormap(name)(np.nan_to_num(t, nan=0.5))
    out[~np.isfinite(v)] = 0.5
    return out


def colorbar(image: np.ndarray, name: str, limits, width: int | None = None) -> np.ndarray:
    """``image`` (H, W, 3|4) uint8 with a vertical colour bar of ``name`` over ``limits``
    at its right edge, low at the bottom, its ends labelled (a copy)."""
    from PIL import Image, ImageDraw

    img = np.array(image, dtype=np.uint8, copy=True)
    h, w = img.shape[:2]
    bar_w = width or max(4, w // 32)
    margin = max(2, h // 16)
    x1 = w - margin
    x0 = max(0, x1 - bar_w)
    top, bottom = margin, h - margin
    if bottom - top < 4 or x0 >= x1:
        return img
    ramp = colormap(name)(np.linspace(1.0, 0.0, bottom - top))
    img[top:bottom, x0:x1, :3] = np.rint(ramp[:, None, :] * 255).astype(np.uint8)
    if img.shape[2] == 4:
        img[top:bottom, x0:x1, 3] = 255
    pil = Image.fromarray(img)
    draw = ImageDraw.Draw(pil)
    lo, hi = scalar_range([0.0], limits)
    for text, y in ((f"{hi:.3g}", top), (f"{lo:.3g}", bottom - 10)):
        box = draw.textbbox((0, 0), text)
        x = max(0, x0 - 3 - (box[2] - box[0]))
        # The label in the colour that contrasts with what lies behind it (white on a dark
        # picture, black on a light one), edged in the other.
        behind = img[max(0, y):max(0, y) + (box[3] - box[1]) + 1,
                     x:x + (box[2] - box[0]) + 1, :3]
        lum = behind.reshape(-1, 3) @ np.array([0.2126, 0.7152, 0.0722])
        light = lum.size > 0 and float(lum.mean()) > 128
        ink, edge = ((0, 0, 0), (255, 255, 255)) if light else ((255, 255, 255), (0, 0, 0))
        if img.shape[2] == 4:
            ink, edge = (*ink, 255), (*edge, 255)
        draw.text((x, y), text, fill=ink, stroke_width=1, stroke_fill=edge)
    return np.asarray(pil)
