"""Planes: the reflection through a plane (a mirror's view), and the plane points lie on
(a mirror's, fitted to its mesh). World space, numpy only."""

from __future__ import annotations

import numpy as np


def reflection(plane) -> np.ndarray:
    """The mirror image in the plane ``n . x + d = 0``: ``x' = x - 2 (n . x + d) n``.
    Its determinant is -1 (it swaps handedness).

    Parameters
    ----------
    plane : (4,) float
        ``(n, d)`` with ``n`` a unit normal.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    plane = np.asarray(plane, dtype=np.float64)
    n, d = plane[:3], plane[3]
    m = np.eye(4)
    m[:3, :3] -= 2.0 * np.outer(n, n)
    m[:3, 3] = -2.0 * d * n
    return m


def fit_plane(points, tolerance: float = 1e-4) -> np.ndarray | None:
    """The plane through ``points``, if they are flat.

    Parameters
    ----------
    points : (N, 3) float
        The points.
    tolerance : float
        How far from the plane a point may lie, relative to the points' extent.

    Returns
    -------
    (4,) float64 ndarray or None
        ``(n, d)`` with unit ``n`` (``n . x + d = 0``), or None when the points are not
        flat within the tolerance or span no plane.
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    centre = p.mean(axis=0)
    extent = float(np.ptp(p, axis=0).max()) if len(p) else 0.0
    if len(p) < 3 or extent == 0.0:
        return None
    _, sv, vt = np.linalg.svd(p - centre, full_matrices=False)
    if len(sv) < 3 or sv[1] <= tolerance * extent:  # a line or a point: no plane
        return None
    n = vt[2]
    if np.abs((p - centre) @ n).max() > tolerance * extent:
        return None
    return np.append(n, -float(n @ centre))
