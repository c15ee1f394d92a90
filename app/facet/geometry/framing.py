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


_CORNERS = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], bool)


def boxes_in_view(view_projection, boxes, transforms) -> np.ndarray:
    """Which of n object-space boxes, placed by their transforms, may show in the view.

    Parameters
    ----------
    view_projection : (4, 4) float
        World -> clip.
    boxes : (n, 2, 3) float
        Object-space (lo, hi) boxes.
    transforms : (n, 4, 4) float
        Object -> world.

    Returns
    -------
    (n,) bool ndarray
        False where all eight corners lie outside one clip plane (the box is out of view);
        True otherwise (in view, or across a plane: it may show).
    """
    b = np.asarray(boxes, np.float64)
    corners = np.where(_CORNERS[None], b[:, None, 1], b[:, None, 0])  # (n, 8, 3)
    world = np.einsum("nij,nkj->nki", np.asarray(transforms, np.float64)[:, :3, :3], corners) \
        + np.asarray(transforms, np.float64)[:, None, :3, 3]
    clip = np.concatenate([world, np.ones(world.shape[:2] + (1,))], axis=2) \
        @ np.asarray(view_projection, np.float64).T  # (n, 8, 4)
    w = clip[..., 3:4]
    outside = np.concatenate([clip[..., :3] < -w, clip[..., :3] > w], axis=2)  # (n, 8, 6)
    return ~outside.all(axis=1).any(axis=1)
