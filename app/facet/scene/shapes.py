"""Exact analytic shapes (no GL): the ray tracer intersects them by their equations, the
rasterizer draws a tessellation fine enough for the image (``Shape.mesh``).

Object space, y up, centred at the origin like facet.scene.primitives (same texture
coordinates, so a texture lands in the same place in both engines):

* ``Sphere(radius)``: |p| = r.
* ``Plane(size)``: the plane y = 0 facing +y; ``size`` [w, d] bounds it to a rectangle,
  None leaves it infinite (drawn by the rasterizer as a square of ``INFINITE_EXTENT``, and
  left out of the scene's bounds).
* ``Disk(radius)``: y = 0, x^2 + z^2 <= r^2, facing +y.
* ``Cylinder(radius, height)``: x^2 + z^2 = r^2 for |y| <= h / 2, with capped ends.
* ``Cone(radius, height)``: the right circular cone with its apex at y = h / 2 and base of
  radius r at y = -h / 2: x^2 + z^2 = (r (h / 2 - y) / h)^2, with a capped base.
* ``Box(size)``: |x| <= sx / 2, |y| <= sy / 2, |z| <= sz / 2.

Place them with the object's transform (any affine matrix, shear and non-uniform scale
included: the tracer intersects in object space).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..boundary import reals
from ..errors import InputError
from . import primitives as P
from .mesh import Mesh

SEGMENTS = 128  # the rasterizer's tessellation around an axis: ~0.03% of r off the surface
RINGS = 64
INFINITE_EXTENT = 2000.0  # side of the square that stands for an infinite plane when drawn


@dataclass(eq=False)
class Shape:
    """An analytic shape: ``kind`` (one of ``KINDS``) and its ``params`` (floats)."""

    kind: str
    params: tuple = ()
    _mesh: Mesh | None = field(default=None, repr=False)
    material: object = field(default=None, repr=False)  # a file's own (Scene.add's default)

    @property
    def name(self) -> str:
        return self.kind

    @property
    def infinite(self) -> bool:
        return self.kind == "plane" and self.params[0] == np.inf

    def mesh(self) -> Mesh:
        """The tessellation the rasterizer draws (shapes of one kind and size share one)."""
        if self._mesh is None:
            self._mesh = _tessellation(self.kind, tuple(self.params))
        return self._mesh

    @property
    def bounds(self) -> np.ndarray:
        """Object-space (2, 3) box; an infinite plane's is infinite in x and z."""
        if self.infinite:
            return np.array([[-np.inf, 0.0, -np.inf], [np.inf, 0.0, np.inf]])
        return self.mesh().bounds


def _positive(value, name: str) -> float:
    v = reals(value, name, most=1)
    if v.shape != () or not np.isfinite(v) or v <= 0:
        raise InputError(f"{name} must be a number > 0, got {value!r}")
    return float(v)


def _sizes(value, name: str, n: int) -> tuple:
    a = reals(value, name, most=n).reshape(-1)
    if a.size == 1:
        a = np.repeat(a, n)
    if a.size != n or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise InputError(f"{name} must be a number > 0 or {n} numbers > 0, got {value!r}")
    return tuple(float(x) for x in a)


def Sphere(radius=1.0) -> Shape:  # noqa: N802 - constructors read as classes
    """The sphere |p| = r.

    Parameters
    ----------
    radius : float
        > 0.

    Returns
    -------
    Shape
        An exact shape: the tracers intersect its equation, the rasterizer draws a fine
        tessellation (``Shape.mesh``). Place it with the object's transform.
    """
    return Shape("sphere", (_positive(radius, "sphere radius"),))


def Plane(size=None) -> Shape:  # noqa: N802
    """The plane y = 0 facing +y, infinite or bounded to a rectangle.

    Parameters
    ----------
    size : float or (float, float), optional
        Side, or (width, depth); None: infinite (drawn as a square of ``INFINITE_EXTENT``,
        left out of the scene's bounds).

    Returns
    -------
    Shape
        An exact shape: the tracers intersect its equation, the rasterizer draws a fine
        tessellation (``Shape.mesh``). Place it with the object's transform.
    """
    if size is None or (isinstance(size, (int, float, np.floating)) and size == np.inf):
        return Shape("plane", (np.inf, np.inf))
    return Shape("plane", _sizes(size, "plane size", 2))


def Disk(radius=1.0) -> Shape:  # noqa: N802
    """The disc y = 0, x^2 + z^2 <= r^2, facing +y.

    Parameters
    ----------
    radius : float
        > 0.

    Returns
    -------
    Shape
        An exact shape: the tracers intersect its equation, the rasterizer draws a fine
        tessellation (``Shape.mesh``). Place it with the object's transform.
    """
    return Shape("disk", (_positive(radius, "disk radius"),))


def Cylinder(radius=0.5, height=1.0) -> Shape:  # noqa: N802
    """The cylinder x^2 + z^2 = r^2 for |y| <= h / 2, with capped ends.

    Parameters
    ----------
    radius, height : float
        > 0.

    Returns
    -------
    Shape
        An exact shape: the tracers intersect its equation, the rasterizer draws a fine
        tessellation (``Shape.mesh``). Place it with the object's transform.
    """
    return Shape("cylinder", (_positive(radius, "cylinder radius"),
                              _positive(height, "cylinder height")))


def Cone(radius=0.5, height=1.0) -> Shape:  # noqa: N802
    """The right circular cone with its apex at y = h / 2 and a capped base of radius r at
    y = -h / 2.

    Parameters
    ----------
    radius, height : float
        > 0.

    Returns
    -------
    Shape
        An exact shape: the tracers intersect its equation, the rasterizer draws a fine
        tessellation (``Shape.mesh``). Place it with the object's transform.
    """
    return Shape("cone", (_positive(radius, "cone radius"), _positive(height, "cone height")))


def Box(size=1.0) -> Shape:  # noqa: N802
    """The box |x| <= sx / 2, |y| <= sy / 2, |z| <= sz / 2.

    Parameters
    ----------
    size : float or (3,) float
        Side, or (sx, sy, sz).

    Returns
    -------
    Shape
        An exact shape: the tracers intersect its equation, the rasterizer draws a fine
        tessellation (``Shape.mesh``). Place it with the object's transform.
    """
    return Shape("box", _sizes(size, "box size", 3))


def _plane_mesh(w: float, d: float) -> Mesh:
    if w == np.inf:
        w = d = INFINITE_EXTENT
    return P.plane([w, d])


_TESSELLATE: dict[str, Callable[..., Mesh]] = {
    "sphere": lambda r: P.sphere(r, SEGMENTS, RINGS),
    "plane": _plane_mesh,
    "disk": lambda r: P.disk(r, SEGMENTS),
    "cylinder": lambda r, h: P.cylinder(r, h, SEGMENTS),
    "cone": lambda r, h: P.cone(r, h, SEGMENTS),
    "box": lambda x, y, z: P.cube([x, y, z]),
}
KINDS = tuple(_TESSELLATE)


@lru_cache(maxsize=256)
def _tessellation(kind: str, params: tuple) -> Mesh:
    """One Mesh per shape kind and size: a scene of many like shapes makes (and the
    renderer uploads) it once."""
    return _TESSELLATE[kind](*params)
# Scene-file primitives that are shapes (their parameters as facet.scene.primitives names).
SHAPES: dict[str, Callable[..., Shape]] = {
    "sphere": lambda radius=1.0: Sphere(radius), "plane": lambda size=1.0: Plane(size),
    "disk": lambda radius=1.0: Disk(radius), "cube": lambda size=1.0: Box(size),
    "cylinder": lambda radius=0.5, height=1.0: Cylinder(radius, height),
    "cone": lambda radius=0.5, height=1.0: Cone(radius, height)}
