"""OpenCV pinhole intrinsics (fx, fy, cx, cy; pixel centres at integer coordinates, row 0 at
the top) and the axes that turn OpenCV's camera space into OpenGL's (numpy only)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# OpenCV camera axes (x right, y down, z forward) <-> OpenGL camera axes (x right, y up, -z fwd).
CV_TO_GL = np.diag([1.0, -1.0, -1.0, 1.0])


@dataclass
class Intrinsics:
    """OpenCV pinhole intrinsics for an image of ``width`` x ``height`` pixels
    (pixel centres at integer coordinates, row 0 at the top).

    Parameters
    ----------
    fx, fy : float
        Focal lengths, pixels.
    cx, cy : float
        The principal point, pixels.
    width, height : int
        The image size the intrinsics are for.
    """

    fx: float
    fy: float
    cx: float
    cy: float
    width: int
    height: int

    @property
    def K(self) -> np.ndarray:  # noqa: N802 - the usual name
        """The 3x3 camera matrix."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])
