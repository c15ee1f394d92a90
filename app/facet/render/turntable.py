"""Turntables and animation sequences: a camera orbiting the scene at a fixed step, and/or
the scene's animations playing over the frames (a time per frame), rendered frame by frame
with the same options every frame."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace

import numpy as np

from ..errors import InputError
from ..geometry.camera import Camera
from ..options.render import MAX_FRAMES
from ..scene.scene import Scene


def orbit_cameras(camera: Camera, center, frames: int, axis=(0.0, 1.0, 0.0)) -> list[Camera]:
    """``frames`` cameras, ``360 / frames`` degrees apart, orbiting ``center`` about the
    world-space ``axis`` (default: y, the world's up)."""
    if not isinstance(frames, (int, np.integer)) or not 1 <= frames <= MAX_FRAMES:
        raise InputError(f"a turntable needs 1..{MAX_FRAMES} frames, got {frames!r}")
    return [camera.orbit(center, axis, 360.0 * i / frames) for i in range(frames)]


def turntable(renderer, scene: Scene, frames: int, camera: Camera | None = None,
              axis=None, options=None, center=None, times=None, **kwargs) -> Iterator:
    """Yield ``frames`` Frames of ``scene`` from a camera orbiting ``center`` (default: the
    scene's centre) about ``axis`` (default: the options' up, the world's up axis).
    ``camera`` defaults to the renderer's choice for the scene; ``options`` and keywords
    are render options, resolved once for every frame; ``times`` (one per frame, e.g.
    ``animation_times``): where the animations stand in each frame (default: the options'
    time throughout)."""
    opts = renderer.options(scene, options, **kwargs)
    camera = camera or renderer.camera(scene, opts)
    center = scene.at(opts.time, opts.animation).bounds.mean(axis=0) if center is None \
        else center
    cameras = orbit_cameras(camera, center, frames, opts.up if axis is None else axis)
    yield from play(renderer, scene, cameras, times, opts)


def play(renderer, scene: Scene, cameras, times=None, options=None, **kwargs) -> Iterator:
    """Yield a Frame of ``scene`` per camera of ``cameras`` (None: the renderer's choice
    at each frame's time: a scene camera on an animated node follows it), at ``times``
    (seconds, one per frame; None: the options' time)."""
    opts = renderer.options(scene, options, **kwargs)
    if times is not None and len(times) != len(cameras):
        raise InputError(f"{len(times)} times for {len(cameras)} frames")
    for k, cam in enumerate(cameras):
        o = opts if times is None else replace(opts, time=float(times[k]))
        yield renderer.render(scene, cam, o)


def animation_times(start: float, end: float, fps: float | None = None,
                    frames: int | None = None) -> list[float]:
    """Frame times from ``start`` towards ``end`` (seconds, end left out: a loop's last
    frame is not its first again): ``fps`` apart, or ``frames`` of them spread evenly."""
    if frames is None:
        frames = int(round((end - start) * fps))
    if not 1 <= frames <= MAX_FRAMES:
        raise InputError(f"--time {start:g}:{end:g} is {frames:,} frames; a sequence holds "
                         f"1..{MAX_FRAMES:,}")
    return [start + (end - start) * k / frames for k in range(frames)]
