"""Framing a view: the default viewing direction for a world's up axis, and the near and far
planes that hold a bounding box (numpy only)."""

from __future__ import annotations

import numpy as np

from . import transforms as T

# Default viewing direction for framing: from the front (+z), a little right and above.
DEFAULT_DIRECTION = (-0.55, -0.4, -1.0)


def default_direction(up=(0.0, 1.0, 0.0)) -> np.ndarray:
    """DEFAULT_DIRECTION (given for y up) for a world whose up axis is ``up``: turned by
    the smallest rotation taking +y to ``up``, so the view is from as high above."""
    u = np.asarray(up, dtype=np.float64)
    u = u / np.linalg.norm(u)
    y = np.array([0.0, 1.0, 0.0])
    d = np.asarray(DEFAULT_DIRECTION, dtype=np.float64)
    axis = np.cross(y, u)
    s, c = np.linalg.norm(axis), float(np.dot(y, u))
    if s < 1e-12:  # up is +y (no turn) or -y (half a turn about z)
        return d if c > 0 else d * np.array([-1.0, -1.0, 1.0])
    return T.rotate(axis, np.degrees(np.arctan2(s, c)))[:3, :3] @ d


def depth_range(view, bounds) -> tuple[float, float]:
    """(near, far) that contain the box ``bounds`` (2, 3) seen through ``view``, with a margin;
    near stays positive (a box partly behind the camera is clipped there)."""
    b = np.asarray(bounds, dtype=np.float64).reshape(2, 3)
    corners = np.array([[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]])
    depth = -(corners @ view[:3, :3].T + view[:3, 3])[:, 2]  # distance along the view axis
    extent = max(float(depth.max() - depth.min()), float(np.linalg.norm(b[1] - b[0])), 1e-6)
    far = max(float(depth.max()) + 0.01 * extent, 1e-3 * extent)
    near = max(float(depth.min()) - 0.01 * extent, far * 1e-4)
    return near, far
