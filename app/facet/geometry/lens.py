"""Distributed effects' geometry (notes §2.11), numpy only: the thin lens for depth of field
and the shutter interval for motion blur.

Depth of field: each sample looks through another point (lx, ly) of the lens disc (camera
space, scene units). The camera moves to that point and the image is sheared so that the
plane at the focus distance f projects exactly as before:

    view_k = S @ T(-lx, -ly, 0) @ view,   S: x += -(lx / f) z,  y += -(ly / f) z

(z is negative in front of an OpenGL camera, so at z = -f the shift cancels). A point at
depth d then spreads over a disc of diameter, in pixels,

    c = A * f_px * |d - f| / (d * f)      (the circle of confusion; f_px the focal length
                                           in pixels, A the aperture)

Motion blur: an object's transform moves from its shutter-open to its shutter-close matrix;
a sample at time t in [0, 1) sees translation and scale interpolated linearly and rotation
along the shortest arc (quaternion slerp).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .camera import Camera
from .orbit import matrix_to_quat, quat_to_matrix


def concentric_disk(points) -> np.ndarray:
    """Shirley's concentric map of square samples in [-0.5, 0.5)^2 onto the unit disc
    (radius 1), keeping their stratification."""
    p = np.asarray(points, dtype=np.float64) * 2.0
    x, y = p[:, 0], p[:, 1]
    out = np.zeros_like(p)
    big_x = np.abs(x) > np.abs(y)
    nz = (x != 0) | (y != 0)
    r = np.where(big_x, x, y)
    theta = np.where(big_x, np.pi / 4 * y / np.where(x == 0, 1, x),
                     np.pi / 2 - np.pi / 4 * x / np.where(y == 0, 1, y))
    out[:, 0] = np.where(nz, r * np.cos(theta), 0.0)
    out[:, 1] = np.where(nz, r * np.sin(theta), 0.0)
    return out


def check_lens(camera: Camera) -> bool:
    """Whether the camera has depth of field; InputError for an inconsistent lens."""
    if not np.isfinite(camera.aperture) or camera.aperture < 0:
        raise InputError(f"aperture must be a number >= 0, got {camera.aperture!r}")
    if camera.aperture == 0:
        return False
    if camera.focus_distance is None:
        raise InputError("an aperture needs a focus distance (the distance that stays sharp)")
    if not (np.isfinite(camera.focus_distance) and camera.focus_distance > 0):
        raise InputError(f"focus distance must be > 0, got {camera.focus_distance!r}")
    if camera.is_orthographic:
        raise InputError("depth of field needs a perspective camera")
    return True


def with_lens(camera: Camera, aperture: float | None, focus: float | None) -> Camera:
    """``camera`` with the lens a render's options ask for (None: the camera's own value),
    checked like the camera's own lens; the camera itself is not changed."""
    if aperture is None and focus is None:
        return camera
    import copy

    lens = copy.copy(camera)
    if aperture is not None:
        lens.aperture = aperture
    if focus is not None:
        if not lens.aperture:
            raise InputError("a focus distance needs an aperture (a lens diameter > 0)")
        lens.focus_distance = focus
    check_lens(lens)
    return lens


def lens_camera(camera: Camera, lx: float, ly: float) -> Camera:
    """The camera seen through lens point (lx, ly) (camera space, scene units)."""
    f = camera.focus_distance
    shift = np.eye(4)
    shift[0, 3], shift[1, 3] = -lx, -ly
    shear = np.eye(4)
    shear[0, 2], shear[1, 2] = -lx / f, -ly / f
    moved = Camera(shear @ shift @ camera.view, fov_y=camera.fov_y,
                   intrinsics=camera.intrinsics, near=camera.near, far=camera.far)
    moved.shift = camera.shift
    return moved


def circle_of_confusion(camera: Camera, depth: float, height: int) -> float:
    """Blur disc diameter in pixels of a point at ``depth`` (along the axis), for an image
    ``height`` pixels tall (module docstring)."""
    f_px = height / 2.0 / np.tan(np.radians(camera.fov_y) / 2.0)
    f = camera.focus_distance
    return camera.aperture * f_px * abs(depth - f) / (depth * f)


def interpolate_transform(start: np.ndarray, end: np.ndarray, t: float) -> np.ndarray:
    """The object -> world matrix at shutter time t in [0, 1] (module docstring)."""
    a, b = np.asarray(start, dtype=np.float64), np.asarray(end, dtype=np.float64)
    sa, sb = np.linalg.norm(a[:3, :3], axis=0), np.linalg.norm(b[:3, :3], axis=0)
    qa, qb = matrix_to_quat(a[:3, :3] / sa), matrix_to_quat(b[:3, :3] / sb)
    if np.dot(qa, qb) < 0:
        qb = -qb
    angle = np.arccos(np.clip(np.dot(qa, qb), -1.0, 1.0))
    if angle < 1e-9:
        q = qa
    else:
        q = (np.sin((1 - t) * angle) * qa + np.sin(t * angle) * qb) / np.sin(angle)
    m = np.eye(4)
    m[:3, :3] = quat_to_matrix(q) * ((1 - t) * sa + t * sb)
    m[:3, 3] = (1 - t) * a[:3, 3] + t * b[:3, 3]
    return m
