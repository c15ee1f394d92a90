"""Denoising (the ``denoise`` render option): the path tracer's mean colour, linear
radiance, through Intel Open Image Denoise's "RT" filter (the pyoidn binding, an optional
extra: ``pip install 'facet-render[denoise]'``), guided by the first hit's albedo and shading
normal at each pixel's centre (glsl/trace/primary.frag with ALBEDO). Only colour: the exact
channels are never touched. Never on by default: a denoised picture is an estimate of the
converged one, not an unbiased sample of it.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

INSTALL = "pip install 'facet-render[denoise]' (Intel Open Image Denoise through pyoidn)"


def require():
    """The pyoidn module; InputError naming the extra when it is not installed."""
    try:
        import pyoidn
    except ImportError as exc:
        raise InputError(f"denoise needs Intel Open Image Denoise: {INSTALL}") from exc
    return pyoidn


def denoise(color: np.ndarray, albedo: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """The denoised ``color``: (H, W, 3) float32 linear radiance (HDR: above 1 kept), with
    ``albedo`` (H, W, 3) in [0, 1] and ``normal`` (H, W, 3) unit vectors (0 where nothing
    was hit), all with the same row order. Returns (H, W, 3) float32."""
    pyoidn = require()
    c = np.ascontiguousarray(np.maximum(np.nan_to_num(color[..., :3]), 0.0), np.float32)
    a = np.ascontiguousarray(np.clip(albedo[..., :3], 0.0, 1.0), np.float32)
    n = np.ascontiguousarray(np.clip(normal[..., :3], -1.0, 1.0), np.float32)
    return np.asarray(pyoidn.denoise(c, a, n, hdr=True), dtype=np.float32)


def denoise_lines(engine, dest) -> list[str]:
    """What a render asked to denoise cannot have, one warning line each; InputError
    (naming the extra) when it would denoise and pyoidn is not installed."""
    if not engine.radiance:
        return [f"denoise removes the path tracer's sampling noise: the {engine.name} "
                "engine's picture is left as drawn"]
    if dest.window is not None:
        return ["the viewer shows the path tracer's picture as it refines, not denoised "
                "(denoise applies to rendered images)"]
    require()
    return []
