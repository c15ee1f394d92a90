"""Light sources, in world space.

* ``DirectionalLight``: infinitely distant; ``direction`` is where the light travels
  (so the vector towards the light is ``-direction``).
* ``PointLight``: at ``position``; intensity falls off as 1 / (c + l d + q d^2) with
  ``attenuation = (c, l, q)`` and d the distance to the light.
* ``SpotLight``: a point light limited to a cone around ``direction``: full inside
  ``inner_angle``, smoothly to zero at ``outer_angle`` (degrees, half-angles).

Each contributes ``I_i = color * intensity`` (times attenuation and cone factor) to the
shading equation.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..boundary import finite, reals
from ..errors import InputError
from .material import as_color


def _vec3(v, name: str, nonzero: bool = False) -> np.ndarray:
    a = reals(v, name, most=3).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be 3 finite numbers, got {v!r}")
    if nonzero and not np.linalg.norm(a) > 0:
        raise InputError(f"{name} must not be the zero vector")
    return a


def _intensity(v) -> float:
    if not (finite(v) and v >= 0):
        raise InputError(f"light intensity must be a number >= 0, got {v!r}")
    return float(v)


def _attenuation(v) -> np.ndarray:
    a = _vec3(v, "attenuation")
    if a.min() < 0 or a.sum() <= 0:
        raise InputError(f"attenuation (c, l, q) must be >= 0 and not all zero, got {v!r}")
    return a


@dataclass
class DirectionalLight:
    """An infinitely distant light (the sun).

    Parameters
    ----------
    direction : (3,) float
        Where the light travels, world space (towards the light is ``-direction``).
    color : (3,) float
        Linear RGB, each >= 0.
    intensity : float
        Multiplies ``color`` (>= 0).
    cast_shadows : bool
        Whether it casts shadows when a render asks for them.
    """
    direction: np.ndarray = field(default_factory=lambda: np.array([-1.0, -1.0, -1.0]))
    color: np.ndarray = field(default_factory=lambda: np.ones(3))
    intensity: float = 1.0
    cast_shadows: bool = True  # when a render asks for shadows

    def __post_init__(self):
        d = _vec3(self.direction, "light direction", nonzero=True)
        self.direction = d / np.linalg.norm(d)
        self.color = as_color(self.color, "light color")
        self.intensity = _intensity(self.intensity)


@dataclass
class PointLight:
    """A light at a point, shining every way.

    Parameters
    ----------
    position : (3,) float
        World space.
    color : (3,) float
        Linear RGB, each >= 0.
    intensity : float
        Multiplies ``color`` (>= 0).
    cast_shadows : bool
        Whether it casts shadows when a render asks for them.
    attenuation : (3,) float
        ``(c, l, q)``: intensity falls off as 1 / (c + l d + q d^2), d the distance.
    """
    position: np.ndarray = field(default_factory=lambda: np.array([0.0, 5.0, 5.0]))
    color: np.ndarray = field(default_factory=lambda: np.ones(3))
    intensity: float = 1.0
    attenuation: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0]))
    cast_shadows: bool = True

    def __post_init__(self):
        self.position = _vec3(self.position, "light position")
        self.color = as_color(self.color, "light color")
        self.intensity = _intensity(self.intensity)
        self.attenuation = _attenuation(self.attenuation)


@dataclass
class SpotLight:
    """A point light limited to a cone: full inside ``inner_angle``, falling smoothly to
    zero at ``outer_angle``.

    Parameters
    ----------
    position : (3,) float
        World space.
    direction : (3,) float
        The cone's axis, where the light travels.
    color : (3,) float
        Linear RGB, each >= 0.
    intensity : float
        Multiplies ``color`` (>= 0).
    cast_shadows : bool
        Whether it casts shadows when a render asks for them.
    attenuation : (3,) float
        ``(c, l, q)``: intensity falls off as 1 / (c + l d + q d^2), d the distance.
    inner_angle, outer_angle : float
        Half-angles, degrees, 0 <= inner <= outer < 90.
    """
    position: np.ndarray = field(default_factory=lambda: np.array([0.0, 5.0, 5.0]))
    direction: np.ndarray = field(default_factory=lambda: np.array([0.0, -1.0, -1.0]))
    color: np.ndarray = field(default_factory=lambda: np.ones(3))
    intensity: float = 1.0
    attenuation: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0]))
    inner_angle: float = 20.0
    outer_angle: float = 30.0
    cast_shadows: bool = True

    def __post_init__(self):
        self.position = _vec3(self.position, "light position")
        d = _vec3(self.direction, "light direction", nonzero=True)
        self.direction = d / np.linalg.norm(d)
        self.color = as_color(self.color, "light color")
        self.intensity = _intensity(self.intensity)
        self.attenuation = _attenuation(self.attenuation)
        if not 0 <= self.inner_angle <= self.outer_angle < 90:
            raise InputError("spot light needs 0 <= inner_angle <= outer_angle < 90 degrees, "
                             f"got {self.inner_angle}, {self.outer_angle}")


@dataclass
class AreaLight:
    """A rectangle emitting ``color * intensity`` in total, facing ``normal``.

    Rendered by supersampling: each sample replaces it by a point light at another point of
    its area (a jittered pattern), so shadow edges turn into penumbrae; a render without
    supersampling uses its centre. The path tracer samples it as an emitter.

    Parameters
    ----------
    position : (3,) float
        Its centre, world space.
    normal : (3,) float
        The side it lights.
    size : (float, float)
        Width and height, scene units (> 0).
    color : (3,) float
        Linear RGB, each >= 0.
    intensity : float
        Multiplies ``color`` (>= 0).
    cast_shadows : bool
        Whether it casts shadows when a render asks for them.
    attenuation : (3,) float
        ``(c, l, q)``: intensity falls off as 1 / (c + l d + q d^2), d the distance.
    """

    position: np.ndarray = field(default_factory=lambda: np.array([0.0, 5.0, 0.0]))
    normal: np.ndarray = field(default_factory=lambda: np.array([0.0, -1.0, 0.0]))
    size: tuple = (1.0, 1.0)
    color: np.ndarray = field(default_factory=lambda: np.ones(3))
    intensity: float = 1.0
    attenuation: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0]))
    cast_shadows: bool = True

    def __post_init__(self):
        self.position = _vec3(self.position, "light position")
        n = _vec3(self.normal, "area light normal", nonzero=True)
        self.normal = n / np.linalg.norm(n)
        size = reals(self.size, "area light size", most=2).reshape(-1)
        w, h = (float(v) for v in size) if size.shape == (2,) else (0.0, 0.0)
        if not (np.isfinite(w) and np.isfinite(h) and w > 0 and h > 0):
            raise InputError(f"area light size must be two numbers > 0, got {self.size!r}")
        self.size = (w, h)
        self.color = as_color(self.color, "light color")
        self.intensity = _intensity(self.intensity)
        self.attenuation = _attenuation(self.attenuation)

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        """The rectangle's unit edge directions.

        Returns
        -------
        tuple of two (3,) float64 ndarray
            ``(a, b)`` with ``a x b = normal``.
        """
        n = self.normal
        a = np.cross(n, (0.0, 1.0, 0.0) if abs(n[1]) < 0.99 else (1.0, 0.0, 0.0))
        a /= np.linalg.norm(a)
        return a, np.cross(n, a)

    def corners(self) -> np.ndarray:
        """The rectangle's corners.

        Returns
        -------
        (4, 3) float64 ndarray
            Counter-clockwise seen from its lit side, world space.
        """
        a, b = self.axes()
        w, h = self.size
        return np.array([self.position + a * u * w + b * v * h
                         for u, v in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))])

    def point_light(self, u: float = 0.0, v: float = 0.0) -> PointLight:
        """The point light at one point of the rectangle.

        Parameters
        ----------
        u, v : float
            Coordinates in [-0.5, 0.5] along ``axes()`` (0, 0: the centre).

        Returns
        -------
        PointLight
            A light of the rectangle's colour, intensity and attenuation there.
        """
        a, b = self.axes()
        p = self.position + a * u * self.size[0] + b * v * self.size[1]
        return PointLight(p, self.color, self.intensity, self.attenuation,
                          cast_shadows=self.cast_shadows)


@dataclass
class SphereLight(AreaLight):
    """A sphere of ``radius`` around ``position`` that lights as a point light of
    ``color * intensity`` does from afar (a USD SphereLight; ``normal`` and ``size`` are
    not used).

    The rasterizer and the Whitted tracer light by one point of its surface per supersample
    (soft shadows; its centre without supersampling), as for an AreaLight; the path tracer
    samples it as an emitting sphere of radiance ``color * intensity / radius^2`` (the
    irradiance far from it is then pi I / d^2, a point light's).

    Parameters
    ----------
    radius : float
        > 0, scene units.
    """

    radius: float = 0.5

    def __post_init__(self):
        super().__post_init__()
        if not (finite(self.radius) and self.radius > 0):
            raise InputError(f"sphere light radius must be a number > 0, got {self.radius!r}")
        self.radius = float(self.radius)

    def point_light(self, u: float = 0.0, v: float = 0.0) -> PointLight:
        """The point light at one point of the sphere.

        Parameters
        ----------
        u, v : float
            Coordinates in [-0.5, 0.5] over the sphere, uniform by area (0, 0: its centre).

        Returns
        -------
        PointLight
            A light of the sphere's colour, intensity and attenuation there.
        """
        p = self.position
        if u != 0.0 or v != 0.0:
            z = float(np.clip(2.0 * v, -1.0, 1.0))
            phi = 2.0 * np.pi * (u + 0.5)
            ring = np.sqrt(max(0.0, 1.0 - z * z))
            p = p + self.radius * np.array([ring * np.cos(phi), ring * np.sin(phi), z])
        return PointLight(p, self.color, self.intensity, self.attenuation,
                          cast_shadows=self.cast_shadows)


Light = DirectionalLight | PointLight | SpotLight | AreaLight


# Default rig in camera space (x right, y up, looking down -z), as directions of travel:
# a key light from the upper left behind the viewer and a dimmer fill from the right.
_RIG = (((0.45, -0.55, -1.0), 0.85), ((-0.8, -0.1, -0.6), 0.3))


def camera_rig(view) -> list[DirectionalLight]:
    """The default key + fill lights for a camera with 4x4 world->camera matrix ``view``,
    turned into world space so they light what the camera sees."""
    to_world = np.linalg.inv(np.asarray(view, dtype=np.float64)[:3, :3])
    return [DirectionalLight(direction=to_world @ np.array(d), intensity=i) for d, i in _RIG]


def active_lights(lights, view, mode: str = "auto") -> list:
    """The lights that shine in a render, by the ``lights`` option (facet.options.render):
    "auto" the scene's own or, when it has none, the camera rig for the world -> camera
    matrix ``view``; "scene" only its own; "camera" the rig in any case."""
    if mode == "camera" or (mode == "auto" and not lights):
        return camera_rig(view)
    return list(lights)
