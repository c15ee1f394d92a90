"""Turntables: a camera orbiting the scene at a fixed step, rendered frame by frame with the
same options every frame."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from ..errors import InputError
from ..geometry.camera import Camera
from ..scene.options import MAX_FRAMES
from ..scene.scene import Scene


def orbit_cameras(camera: Camera, center, frames: int, axis=(0.0, 1.0, 0.0)) -> list[Camera]:
    """``frames`` cameras, ``360 / frames`` degrees apart, orbiting ``center`` about the
    world-space ``axis`` (default: y, the world's up)."""
    if not isinstance(frames, (int, np.integer)) or not 1 <= frames <= MAX_FRAMES:
        raise InputError(f"a turntable needs 1..{MAX_FRAMES} frames, got {frames!r}")
    return [camera.orbit(center, axis, 360.0 * i / frames) for i in range(frames)]


def turntable(renderer, scene: Scene, frames: int, camera: Camera | None = None,
              axis=None, options=None, center=None, **kwargs) -> Iterator:
    """Yield ``frames`` Frames of ``scene`` from a camera orbiting ``center`` (default: the
    scene's centre) about ``axis`` (default: the options' up, the world's up axis).
    ``camera`` defaults to the renderer's choice for the scene; ``options`` and keywords
    are render options, resolved once for every frame."""
    opts = renderer.options(scene, options, **kwargs)
    camera = camera or renderer.camera(scene, opts)
    center = scene.bounds.mean(axis=0) if center is None else center
    for cam in orbit_cameras(camera, center, frames, opts.up if axis is None else axis):
        yield renderer.render(scene, cam, opts)
