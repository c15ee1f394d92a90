"""Built-in primitives as meshes with normals and texture coordinates, centred at the origin.

Object space, y up. Every size must be a finite number > 0.

* ``sphere(radius)``: latitude-longitude sphere; u around (from +x towards -z), v from the
  south pole (0) to the north pole (1).
* ``plane(size)``: the square (or ``[width, depth]`` rectangle) in the xz plane facing +y;
  uv (0, 0) at (-x, +z), (1, 1) at (+x, -z).
* ``cube(size)``: side ``size`` (or ``[x, y, z]``), 24 vertices with flat face normals, each
  face mapped to the whole [0, 1]^2.
* ``disk(radius)``: in the xz plane facing +y.
* ``cylinder(radius, height)`` and ``cone(radius, height)``: axis along y, base at
  -height / 2, with capped ends.
* ``torus(major_radius, minor_radius)``: in the xz plane around the y axis.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated

import numpy as np

from ..boundary import Count, checked, reals
from ..errors import InputError
from .mesh import Mesh

SEGMENTS = 64  # around the axis
RINGS = 32  # pole to pole / along the tube
Segments = Annotated[int, Count(3, 1 << 14)]  # around an axis
Rings = Annotated[int, Count(2, 1 << 14)]  # pole to pole, along a tube


def _size(value, name: str, n: int = 1) -> np.ndarray:
    a = reals(value, name, most=n).reshape(-1)
    if a.size == 1 and n > 1:
        a = np.repeat(a, n)
    if a.size != n or not np.all(np.isfinite(a)) or np.any(a <= 0):
        want = "a number > 0" if n == 1 else f"a number > 0 or {n} numbers > 0"
        raise InputError(f"{name} must be {want}, got {value!r}")
    return a


def _grid(rows: int, cols: int, wrap: bool = False) -> np.ndarray:
    """Triangles of a (rows + 1) x (cols + 1) vertex grid, counter-clockwise seen from the
    side the caller's normals point to (i runs along v, j along u)."""
    i, j = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    w = cols + 1
    a, b = i * w + j, i * w + j + 1
    c, d = (i + 1) * w + j + 1, (i + 1) * w + j
    return np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                           np.stack([a, c, d], -1).reshape(-1, 3)])


@checked
def sphere(radius=1.0, segments: Segments = SEGMENTS, rings: Rings = RINGS) -> Mesh:
    """A latitude-longitude sphere: u around (from +x towards -z), v from the south pole (0)
    to the north pole (1).

    Parameters
    ----------
    radius : float
        > 0.
    segments : int
        Divisions around the axis.
    rings : int
        Divisions from pole to pole.

    Returns
    -------
    Mesh
        With normals and texture coordinates, centred at the origin (y up).
    """
    r = _size(radius, "sphere radius")[0]
    u = np.linspace(0, 1, segments + 1)
    v = np.linspace(0, 1, rings + 1)
    vv, uu = np.meshgrid(v, u, indexing="ij")
    theta, phi = uu * 2 * np.pi, (vv - 0.5) * np.pi
    n = np.stack([np.cos(phi) * np.cos(theta), np.sin(phi), -np.cos(phi) * np.sin(theta)], -1)
    n = n.reshape(-1, 3)
    return Mesh(n * r, _grid(rings, segments), n, np.stack([uu, vv], -1).reshape(-1, 2),
                name="sphere")


@checked
def plane(size=1.0) -> Mesh:
    """A square (or rectangle) in the xz plane facing +y; uv (0, 0) at (-x, +z).

    Parameters
    ----------
    size : float or (float, float)
        Side, or (width along x, depth along z).

    Returns
    -------
    Mesh
        With normals and texture coordinates, centred at the origin (y up).
    """
    w, d = _size(size, "plane size", 2) / 2
    pos = [[-w, 0, d], [w, 0, d], [w, 0, -d], [-w, 0, -d]]
    uv = [[0, 0], [1, 0], [1, 1], [0, 1]]
    return Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 1, 0]] * 4, uv, name="plane")


@checked
def cube(size=1.0) -> Mesh:
    """A box of 24 vertices with flat face normals, each face mapped to the whole [0, 1]^2.

    Parameters
    ----------
    size : float or (3,) float
        Side, or the sides along x, y and z.

    Returns
    -------
    Mesh
        With normals and texture coordinates, centred at the origin (y up).
    """
    half = _size(size, "cube size", 3) / 2
    pos: list = []
    nrm: list = []
    uvs: list = []
    faces: list = []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = np.zeros(3)
            n[axis] = sign
            # Tangents with t1 x t2 = n, so the quad winds counter-clockwise seen from outside.
            t1 = np.roll(np.abs(n), 1)
            t2 = np.cross(n, t1)
            base = len(pos)
            for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos.append((n + su * t1 + sv * t2) * half)
                nrm.append(n)
                uvs.append(((su + 1) / 2, (sv + 1) / 2))
            faces += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
    return Mesh(pos, faces, nrm, uvs, name="cube")


def _lathe(profile: np.ndarray, normals: np.ndarray, v: np.ndarray, segments: int):
    """Revolve (k, 2) (radius, y) points with (k, 2) normals about the y axis."""
    u = np.linspace(0, 1, segments + 1)
    th = u * 2 * np.pi
    c, s = np.cos(th)[None, :], -np.sin(th)[None, :]
    pos = np.stack([profile[:, :1] * c, np.repeat(profile[:, 1:], len(u), 1),
                    profile[:, :1] * s], -1)
    nrm = np.stack([normals[:, :1] * c, np.repeat(normals[:, 1:], len(u), 1),
                    normals[:, :1] * s], -1)
    uv = np.stack(np.meshgrid(u, v), -1)
    faces = _grid(len(profile) - 1, segments)
    return pos.reshape(-1, 3), nrm.reshape(-1, 3), uv.reshape(-1, 2), faces


def _merge(parts, name: str) -> Mesh:
    pos, nrm, uv, faces, offset = [], [], [], [], 0
    for p, n, t, f in parts:
        pos.append(p)
        nrm.append(n)
        uv.append(t)
        faces.append(f + offset)
        offset += len(p)
    return Mesh(np.concatenate(pos), np.concatenate(faces), np.concatenate(nrm),
                np.concatenate(uv), name=name)


def _cap(radius: float, y: float, up: bool, segments: int):
    """A disc at height y facing +y (up) or -y. The lathe faces outwards when its profile
    runs counter-clockwise in the (radius, y) plane: rim to centre for a top cap."""
    prof = np.array([[radius, y], [0.0, y]])
    if not up:
        prof = prof[::-1]
    n = np.repeat([[0.0, 1.0 if up else -1.0]], 2, axis=0)
    return _lathe(prof, n, np.array([0.0, 1.0]), segments)


@checked
def disk(radius=1.0, segments: Segments = SEGMENTS) -> Mesh:
    """A disc in the xz plane facing +y.

    Parameters
    ----------
    radius : float
        > 0.
    segments : int
        Divisions around the axis.

    Returns
    -------
    Mesh
        With normals and texture coordinates, centred at the origin (y up).
    """
    r = _size(radius, "disk radius")[0]
    pos, nrm, uv, faces = _cap(r, 0.0, True, segments)
    return Mesh(pos, faces, nrm, uv, name="disk")


@checked
def cylinder(radius=0.5, height=1.0, segments: Segments = SEGMENTS) -> Mesh:
    """A capped cylinder, its axis along y, its base at -height / 2.

    Parameters
    ----------
    radius, height : float
        > 0.
    segments : int
        Divisions around the axis.

    Returns
    -------
    Mesh
        With normals and texture coordinates, centred at the origin (y up).
    """
    r = _size(radius, "cylinder radius")[0]
    h = _size(height, "cylinder height")[0]
    side = _lathe(np.array([[r, -h / 2], [r, h / 2]]), np.array([[1.0, 0.0], [1.0, 0.0]]),
                  np.array([0.0, 1.0]), segments)
    return _merge([side, _cap(r, h / 2, True, segments), _cap(r, -h / 2, False, segments)],
                  "cylinder")


@checked
def cone(radius=0.5, height=1.0, segments: Segments = SEGMENTS) -> Mesh:
    """A capped cone, its axis along y, its base at -height / 2, its tip at +height / 2.

    Parameters
    ----------
    radius, height : float
        > 0.
    segments : int
        Divisions around the axis.

    Returns
    -------
    Mesh
        With normals and texture coordinates, centred at the origin (y up).
    """
    r = _size(radius, "cone radius")[0]
    h = _size(height, "cone height")[0]
    slope = np.array([h, r]) / np.hypot(h, r)  # outward normal of the side, (radial, y)
    side = _lathe(np.array([[r, -h / 2], [1e-6 * r, h / 2]]), np.array([slope, slope]),
                  np.array([0.0, 1.0]), segments)
    return _merge([side, _cap(r, -h / 2, False, segments)], "cone")


@checked
def capsule(radius=0.5, height=1.0, segments: Segments = SEGMENTS,
            rings: Rings = RINGS) -> Mesh:
    """A capsule: a cylinder of ``height`` along y, its ends closed by hemispheres of its
    radius (USD's Capsule: the whole is height + 2 radius long).

    Parameters
    ----------
    radius, height : float
        > 0 (the cylinder part's length).
    segments : int
        Divisions around the axis.
    rings : int
        Divisions from pole to pole over both hemispheres.

    Returns
    -------
    Mesh
        With normals and texture coordinates, centred at the origin (y up).
    """
    r = _size(radius, "capsule radius")[0]
    h = _size(height, "capsule height")[0]
    half = max(rings // 2, 2)
    phi = np.linspace(-np.pi / 2, 0.0, half + 1)  # south pole to the equator
    low = np.stack([np.cos(phi), np.sin(phi)], -1)
    normals = np.concatenate([low, low[::-1] * [1, -1]])  # then equator to north pole
    profile = normals * r + np.concatenate([np.full((half + 1, 1), -h / 2),
                                            np.full((half + 1, 1), h / 2)])[:, [0]] * [0, 1]
    v = (profile[:, 1] - profile[0, 1]) / (profile[-1, 1] - profile[0, 1])
    pos, nrm, uv, faces = _lathe(profile, normals, v, segments)
    return Mesh(pos, faces, nrm, uv, name="capsule")


@checked
def torus(major_radius=1.0, minor_radius=0.25, segments: Segments = SEGMENTS,
          rings: Rings = RINGS) -> Mesh:
    """A torus in the xz plane around the y axis.

    Parameters
    ----------
    major_radius : float
        From the axis to the tube's centre.
    minor_radius : float
        The tube's radius (< major_radius).
    segments : int
        Divisions around the axis.
    rings : int
        Divisions around the tube.

    Returns
    -------
    Mesh
        With normals and texture coordinates, centred at the origin (y up).
    """
    big = _size(major_radius, "torus major_radius")[0]
    small = _size(minor_radius, "torus minor_radius")[0]
    if small >= big:
        raise InputError(f"torus minor_radius ({small:g}) must be smaller than major_radius "
                         f"({big:g})")
    a = np.linspace(0, 2 * np.pi, rings + 1)
    # Tube cross-section in (radial, y), counter-clockwise so the revolved quads face out.
    prof = np.stack([big + small * np.cos(a), small * np.sin(a)], -1)
    nrm = np.stack([np.cos(a), np.sin(a)], -1)
    return _merge([_lathe(prof, nrm, np.linspace(0, 1, rings + 1), segments)], "torus")


PRIMITIVES: dict[str, Callable[..., Mesh]] = {
    "sphere": sphere, "plane": plane, "disk": disk, "cube": cube, "cylinder": cylinder,
    "cone": cone, "torus": torus}
# The size parameters each primitive takes (scene files validate against these).
PRIMITIVE_PARAMS = {"sphere": ("radius",), "plane": ("size",), "disk": ("radius",),
                    "cube": ("size",),
                    "cylinder": ("radius", "height"), "cone": ("radius", "height"),
                    "torus": ("major_radius", "minor_radius")}
