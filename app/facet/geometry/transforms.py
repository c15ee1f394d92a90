"""The 4x4 homogeneous matrices of the notes: modelling, viewing and projection transforms.

Conventions (stated here once, used everywhere in facet):

* Matrices are 4x4 float64 numpy arrays acting on **column vectors**, right-handed axes.
  A point goes from object space to clip space as ``p_clip = P @ V @ M @ p``.
* Composition reads right to left: ``R @ Sh`` means "shear, then rotate". To apply
  ``A`` first and then ``B``, write ``B @ A`` (or ``compose(A, B)``).
* Angles are in **degrees** throughout the public API (rotations and field of view).
* Camera (view) space is OpenGL's: x right, y up, the camera looks down -z.
* ``perspective`` and ``orthographic`` map view space to OpenGL clip space
  (NDC z in [-1, 1], near plane to -1).

numpy arrays are row-major; uploading to GLSL (column-major) transposes them, in one helper
(``facet.gl.resources.mat_bytes``).
"""

from __future__ import annotations

from typing import Annotated

import numpy as np

from ..boundary import Array, ArrayLike, Number, Positive, Real, Vec3, checked, finite
from ..errors import InputError

Matrix = Annotated[ArrayLike, Array("4,4")]  # a transform

_AXES = {"x": 0, "y": 1, "z": 2}


def _vec3(v, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be 3 finite numbers, got {v!r}")
    return a


def identity() -> np.ndarray:
    """The 4x4 identity.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    return np.eye(4)


@checked
def translate(offset: Vec3) -> np.ndarray:
    """Translation by ``offset``: ``p' = p + offset``.

    Parameters
    ----------
    offset : (3,) float
        The displacement, in the units of the space it acts in.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    m = np.eye(4)
    m[:3, 3] = _vec3(offset, "offset")
    return m


@checked
def scale(factor: Annotated[ArrayLike, Array("", "1", "3")]) -> np.ndarray:
    """Scale about the origin.

    Parameters
    ----------
    factor : float or (3,) float
        One factor for every axis, or one per axis (non-zero).

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    f = np.asarray(factor, dtype=np.float64).reshape(-1)
    if f.size == 1:
        f = np.repeat(f, 3)
    return np.diag([*_vec3(f, "factor"), 1.0])


@checked
def rotate(axis: Vec3, degrees: Real) -> np.ndarray:
    """Rotation by ``degrees`` about ``axis`` through the origin (right-handed:
    counter-clockwise looking down the axis towards the origin).

    Parameters
    ----------
    axis : (3,) float
        The axis direction (normalised here; non-zero).
    degrees : float
        The angle.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    a = _vec3(axis, "axis")
    n = np.linalg.norm(a)
    if n == 0.0:
        raise InputError("rotation axis must not be the zero vector")
    a = a / n
    t = np.radians(float(degrees))
    c, s = np.cos(t), np.sin(t)
    cross = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    m = np.eye(4)
    m[:3, :3] = c * np.eye(3) + s * cross + (1.0 - c) * np.outer(a, a)
    return m


@checked
def rotate_x(degrees: Real) -> np.ndarray:
    """Rotation about +x (y towards z).

    Parameters
    ----------
    degrees : float
        The angle.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    return rotate((1, 0, 0), degrees)


@checked
def rotate_y(degrees: Real) -> np.ndarray:
    """Rotation about +y (z towards x).

    Parameters
    ----------
    degrees : float
        The angle.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    return rotate((0, 1, 0), degrees)


@checked
def rotate_z(degrees: Real) -> np.ndarray:
    """Rotation about +z (x towards y).

    Parameters
    ----------
    degrees : float
        The angle.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    return rotate((0, 0, 1), degrees)


def shear(**amounts: float) -> np.ndarray:
    """Shear: ``shear(xy=a)`` adds ``a * y`` to x (the first letter is the coordinate
    changed, the second the one it follows).

    Parameters
    ----------
    **amounts : float
        Any of ``xy``, ``xz``, ``yx``, ``yz``, ``zx``, ``zy``.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    m = np.eye(4)
    for key, value in amounts.items():
        if len(key) != 2 or key[0] not in _AXES or key[1] not in _AXES or key[0] == key[1]:
            raise InputError(f"shear key must be two different axes like 'xy', got {key!r}")
        if not finite(value):
            raise InputError(f"shear amount {key}={value!r} must be finite")
        m[_AXES[key[0]], _AXES[key[1]]] = float(value)
    return m


def compose(*steps: np.ndarray) -> np.ndarray:
    """The matrix that applies ``steps`` first to last: ``compose(A, B, C) = C @ B @ A``
    ("shear then rotate" is ``compose(Sh, R)``).

    Parameters
    ----------
    *steps : (4, 4) float
        Transforms, in the order they act.

    Returns
    -------
    (4, 4) float64 ndarray
        The matrix (column vectors: ``p' = M @ p``).
    """
    m = np.eye(4)
    for step in steps:
        m = np.asarray(step, dtype=np.float64) @ m
    return m


@checked
def look_at(eye: Vec3, target: Vec3, up: Vec3 = (0.0, 1.0, 0.0)) -> np.ndarray:
    """The viewing transformation: world space -> camera space (OpenGL axes: x right,
    y up, looking down -z).

    Parameters
    ----------
    eye : (3,) float
        The camera's position, world space.
    target : (3,) float
        The point it looks at (not ``eye``).
    up : (3,) float
        World up (not parallel to ``target - eye``).

    Returns
    -------
    (4, 4) float64 ndarray
        world -> camera (``view``).
    """
    eye, target, up = _vec3(eye, "eye"), _vec3(target, "target"), _vec3(up, "up")
    w = eye - target
    if np.linalg.norm(w) == 0.0:
        raise InputError("look_at: eye and target are the same point")
    w = w / np.linalg.norm(w)
    u = np.cross(up, w)
    if np.linalg.norm(u) < 1e-9 * max(float(np.linalg.norm(up)), 1e-300):
        raise InputError("look_at: up is parallel to the viewing direction; choose another up")
    u = u / np.linalg.norm(u)
    v = np.cross(w, u)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = u, v, w
    m[:3, 3] = -m[:3, :3] @ eye
    return m


@checked
def perspective(fov_y: Annotated[float, Number(0, 180, open_lo=True, open_hi=True)],
                aspect: Positive, near: Positive, far: Positive) -> np.ndarray:
    """Perspective projection to OpenGL clip space.

    Parameters
    ----------
    fov_y : float
        Vertical field of view, degrees (0, 180).
    aspect : float
        Width / height of the image.
    near, far : float
        Distances of the clipping planes, 0 < near < far.

    Returns
    -------
    (4, 4) float64 ndarray
        camera -> clip.
    """
    if not 0.0 < fov_y < 180.0:
        raise InputError(f"fov_y must be in (0, 180) degrees, got {fov_y}")
    _check_depth_range(near, far, perspective=True)
    if aspect <= 0:
        raise InputError(f"aspect must be > 0, got {aspect}")
    f = 1.0 / np.tan(np.radians(float(fov_y)) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0] = f / aspect
    m[1, 1] = f
    m[2, 2] = -(far + near) / (far - near)
    m[2, 3] = -2.0 * far * near / (far - near)
    m[3, 2] = -1.0
    return m


@checked
def orthographic(left: Real, right: Real, bottom: Real, top: Real,
                 near: Real, far: Real) -> np.ndarray:
    """Parallel projection of the camera-space box [left, right] x [bottom, top] x
    [-far, -near] to OpenGL clip space.

    Parameters
    ----------
    left, right, bottom, top : float
        The box's sides, camera space.
    near, far : float
        Distances of the clipping planes, near < far.

    Returns
    -------
    (4, 4) float64 ndarray
        camera -> clip.
    """
    if right == left or top == bottom:
        raise InputError("orthographic: left == right or bottom == top: the box has zero "
                         "width or height")
    _check_depth_range(near, far, perspective=False)
    m = np.eye(4)
    m[0, 0] = 2.0 / (right - left)
    m[1, 1] = 2.0 / (top - bottom)
    m[2, 2] = -2.0 / (far - near)
    m[0, 3] = -(right + left) / (right - left)
    m[1, 3] = -(top + bottom) / (top - bottom)
    m[2, 3] = -(far + near) / (far - near)
    return m


def _check_depth_range(near: float, far: float, perspective: bool) -> None:
    if not (finite(near) and finite(far)) or far <= near:
        raise InputError(f"need near < far, got near={near}, far={far}")
    if perspective and near <= 0:
        raise InputError(f"perspective near must be > 0, got {near}")


@checked
def normal_matrix(m: Annotated[ArrayLike, Array("4,4", "3,3")]) -> np.ndarray:
    """(M^-1)^T of the upper 3x3: transforms normals so they stay perpendicular to
    surfaces (never transform normals by M).

    Parameters
    ----------
    m : (4, 4) or (3, 3) float
        An invertible transform.

    Returns
    -------
    (3, 3) float64 ndarray
        The normal matrix; renormalise normals after applying it.
    """
    # (M^-1)^T = cof(M) / det(M): the cofactors in plain floats (this runs per object per
    # frame, where numpy's inverse of a 3x3 costs more than the arithmetic).
    (a, b, c), (d, e, f), (g, h, i) = np.asarray(m, dtype=np.float64)[:3, :3].tolist()
    cof = ((e * i - f * h, f * g - d * i, d * h - e * g),
           (c * h - b * i, a * i - c * g, b * g - a * h),
           (b * f - c * e, c * d - a * f, a * e - b * d))
    det = a * cof[0][0] + b * cof[0][1] + c * cof[0][2]
    if abs(det) < 1e-12:
        raise InputError("normal_matrix: the transform is singular (zero scale?)")
    return np.array([[x / det for x in row] for row in cof])


@checked
def transform_points(m: Matrix, points: Annotated[ArrayLike, Array("N,3")]) -> np.ndarray:
    """Apply a 4x4 matrix to points, with the perspective divide.

    Parameters
    ----------
    m : (4, 4) float
        The transform.
    points : (N, 3) float
        The points.

    Returns
    -------
    (N, 3) float64 ndarray
        The transformed points (divided by w).
    """
    p = np.asarray(points, dtype=np.float64)
    h = p @ m[:3, :3].T + m[:3, 3]
    w = p @ m[3, :3] + m[3, 3]
    return h / w[:, None]
