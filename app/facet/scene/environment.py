"""Environment maps (no GL): the six faces of a cube map as float images, to show as the
background and to reflect and refract (materials' ``reflectivity`` and ``ior``).

Face order and texel orientation are OpenGL's (+X, -X, +Y, -Y, +Z, -Z; row 0 first, as
uploaded): texel (s, t) of a face, with sc = 2 s - 1 and tc = 2 t - 1, looks along

    +X: ( 1, -tc, -sc)   -X: (-1, -tc,  sc)   +Y: (sc,  1,  tc)
    -Y: (sc, -1, -tc)    +Z: (sc, -tc,  1)    -Z: (-sc, -tc, -1)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Annotated

import numpy as np

from ..boundary import Array, ArrayLike, Color, Count, FilePath, Items, PathArg, checked
from ..errors import InputError
from .readers import reader  # facet.formats.environment_files reads the files

FACE_NAMES = ("px", "nx", "py", "ny", "pz", "nz")


def face_directions(size: int) -> np.ndarray:
    """(6, size, size, 3) unit directions of every texel centre (module docstring)."""
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    tc, sc = np.meshgrid(c, c, indexing="ij")  # rows: t, columns: s
    one = np.ones_like(sc)
    dirs = np.stack([np.stack([one, -tc, -sc], -1), np.stack([-one, -tc, sc], -1),
                     np.stack([sc, one, tc], -1), np.stack([sc, -one, -tc], -1),
                     np.stack([sc, -tc, one], -1), np.stack([-sc, -tc, -one], -1)])
    return dirs / np.linalg.norm(dirs, axis=-1, keepdims=True)


def equirect_directions(width: int, height: int) -> np.ndarray:
    """(height, width, 3) unit directions of a latitude-longitude image's texel centres
    (row 0 at the zenith; u = 0.5 + atan2(x, -z) / 2 pi, as ``from_equirect`` reads)."""
    phi = ((np.arange(width) + 0.5) / width - 0.5) * 2 * np.pi
    theta = (np.arange(height) + 0.5) / height * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    return np.stack([np.sin(t) * np.sin(p), np.cos(t), -np.sin(t) * np.cos(p)], -1)


def _equirect_at(img: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The texels of latitude-longitude ``img`` (H, W, C) nearest directions ``d`` (..., 3)."""
    h, w = img.shape[:2]
    n = d / np.maximum(np.linalg.norm(d, axis=-1, keepdims=True), 1e-30)
    u = 0.5 + np.arctan2(n[..., 0], -n[..., 2]) / (2 * np.pi)
    v = np.arccos(np.clip(n[..., 1], -1, 1)) / np.pi
    x = np.clip((u * w).astype(int), 0, w - 1)
    y = np.clip((v * h).astype(int), 0, h - 1)
    return img[y, x]


MAX_GRID_WIDTH = 4096  # the path tracer's sky grid: wider images are reduced (area_mean)


def area_mean(img: np.ndarray, width: int, height: int) -> np.ndarray:
    """``img`` (H, W, C) reduced to (height, width, C) by box filtering: each output texel
    the mean of the input area it covers, fractional texels by their share, so every
    stretch of the image keeps its integral (a 3 x 3-texel sun keeps its power wherever
    it falls; taking every k-th texel dropped it or counted it k^2 times)."""
    def along(a: np.ndarray, n: int, axis: int) -> np.ndarray:
        m = a.shape[axis]
        if n == m:
            return a
        edges = np.linspace(0.0, m, n + 1)
        i = np.minimum(edges.astype(np.int64), m - 1)
        f = (edges - i)[:, None, None] if axis == 0 else (edges - i)[None, :, None]
        out = []
        chunk = max(1, (1 << 24) // max(1, a.shape[1 - axis] * a.shape[2]))
        for s in range(0, a.shape[1 - axis], chunk):  # bounded memory for a 16K image
            part = a[:, s:s + chunk] if axis == 0 else a[s:s + chunk]
            c = np.cumsum(part, axis=axis, dtype=np.float64)
            c = np.concatenate([np.zeros_like(np.take(c, [0], axis=axis)), c], axis=axis)
            lo, hi = np.take(c, i, axis=axis), np.take(c, i + 1, axis=axis)
            at = lo + f * (hi - lo)  # the integral from 0 to each edge
            out.append(np.diff(at, axis=axis) * (n / m))
        return np.concatenate(out, axis=1 - axis).astype(np.float32)

    return along(along(np.asarray(img, np.float32), width, 1), height, 0)


def sky_grid(img: np.ndarray) -> np.ndarray:
    """The path tracer's latitude-longitude grid of an image (H, W, 3): the image itself,
    or its area mean at MAX_GRID_WIDTH when it is wider (facet.render.path.sky samples
    it texel for texel)."""
    h, w = img.shape[:2]
    if w <= MAX_GRID_WIDTH:
        return np.ascontiguousarray(img[..., :3], np.float32)
    return area_mean(img[..., :3], MAX_GRID_WIDTH, max(1, round(h * MAX_GRID_WIDTH / w)))


def sky_color(directions, zenith, horizon, ground) -> np.ndarray:
    """The generated sky: horizon -> zenith above, a darker ground below (smooth in y)."""
    d = np.asarray(directions, dtype=np.float64)
    y = d[..., 1:2]
    up = np.sqrt(np.clip(y, 0.0, 1.0))
    down = np.clip(-y * 4.0, 0.0, 1.0)
    zenith, horizon, ground = (np.asarray(c, dtype=np.float64) for c in (zenith, horizon,
                                                                          ground))
    return np.where(y >= 0, horizon + (zenith - horizon) * up, horizon + (ground - horizon) * down)


@checked
class Environment:
    """Light from every direction around the scene, as a cube map (``Scene(environment=)``,
    the ``environment`` option): what mirrors and glass reflect, what the path tracer and
    image-based lighting are lit by.

    Parameters
    ----------
    faces : (6, S, S, 3) float32
        Radiance >= 0 (above 1 from HDR images), OpenGL cube-map order (+X, -X, +Y, -Y, +Z,
        -Z).
    name : str
        Label used in messages.
    equirect : (H, W, 3) float32, optional
        The same radiance as a latitude-longitude image (row 0 the zenith,
        u = 0.5 + atan2(x, -z) / 2 pi): what the path tracer importance-samples.
    """

    SKY = ((0.25, 0.45, 0.85), (0.85, 0.9, 1.0), (0.3, 0.28, 0.25))

    def __init__(self, faces: Annotated[ArrayLike, Array("6,S,S,3", budget="pixels", unit=3)],
                 name: str = "environment",
                 equirect: Annotated[ArrayLike | None,
                                     Array("H,W,3", budget="pixels", unit=3)] = None):
        f = np.asarray(faces, dtype=np.float32)
        if f.ndim != 4 or f.shape[0] != 6 or f.shape[1] != f.shape[2] or f.shape[3] != 3:
            raise InputError(f"{name}: a cube map needs 6 square RGB faces of one size, got "
                             f"{f.shape}")
        if not np.all(np.isfinite(f)):
            raise InputError(f"{name}: the environment holds NaN or infinite values")
        self.faces = np.ascontiguousarray(np.maximum(f, 0.0))
        self.equirect = None if equirect is None else \
            np.ascontiguousarray(np.maximum(np.asarray(equirect, np.float32), 0.0))
        self.name = name
        # Linear radiance (HDR images, constant colours); else display values, as the
        # generated sky's and 8-bit images' are (a linear-light engine decodes them where
        # the rasterizer shows them as given: facet.render.path.engine).
        self.linear = False

    def decoded(self) -> Environment:
        """This environment's display values decoded to linear radiance (itself when it is
        linear); made once.

        Returns
        -------
        Environment
            The linear environment.
        """
        if self.linear:
            return self
        cached = getattr(self, "_decoded", None)
        if cached is None:
            from ..srgb import srgb_to_linear

            cached = Environment(srgb_to_linear(self.faces), self.name,
                                 None if self.equirect is None else
                                 srgb_to_linear(self.equirect))
            cached.linear = True
            self._decoded = cached
        return cached

    def transformed(self, rotation=None, scale=None) -> Environment:
        """A linear copy turned by ``rotation`` (3x3: the environment's frame -> world) and
        scaled by ``scale`` (3,) (a USD dome's placement and emission): its cube and its
        latitude-longitude grid resampled alike (nearest texel), so every engine sees the
        same sky. Without a grid (cube faces from files) the cube is kept as it is turned
        by no more than the identity.

        Parameters
        ----------
        rotation : (3, 3) float, optional
            Orthonormal.
        scale : (3,) float, optional
            Multiplies the radiance.

        Returns
        -------
        Environment
            The turned, scaled, linear environment.
        """
        env = self.decoded()
        faces, grid = env.faces, env.equirect
        if rotation is not None and grid is not None and \
                not np.allclose(rotation, np.eye(3), atol=1e-9):
            r = np.asarray(rotation, np.float64)
            faces = _equirect_at(grid, face_directions(env.size) @ r)  # world -> its frame
            grid = _equirect_at(grid, equirect_directions(grid.shape[1], grid.shape[0]) @ r)
        k = np.ones(3, np.float32) if scale is None else np.asarray(scale, np.float32)
        out = Environment(faces * k, env.name, None if grid is None else grid * k)
        out.linear = True
        return out

    @classmethod
    @checked
    def sky(cls, zenith: Color = SKY[0], horizon: Color = SKY[1], ground: Color = SKY[2],
            size: Annotated[int, Count(1, per_pixels=6)] = 128) -> Environment:
        """A generated sky gradient.

        Parameters
        ----------
        zenith, horizon, ground : (3,) float
            The colours overhead, at the horizon and below it.
        size : int
            Texels along a cube face's side.

        Returns
        -------
        Environment
            The sky.
        """
        # (the grid the path tracer's eye sees and samples: as fine as the cube's texels,
        # 4 x size across the horizon, so both engines show the same sky)
        grid = sky_color(equirect_directions(4 * size, 2 * size), zenith, horizon, ground)
        return cls(sky_color(face_directions(size), zenith, horizon, ground), "sky", grid)

    @classmethod
    @checked
    def constant(cls, color: Color) -> Environment:
        """The same radiance from every direction.

        Parameters
        ----------
        color : (3,) float
            Linear RGB.

        Returns
        -------
        Environment
            The environment.
        """
        from .material import as_color

        c = as_color(color, "environment color")
        env = cls(np.broadcast_to(c[:3], (6, 1, 1, 3)), "constant environment")
        env.linear = True
        return env

    @classmethod
    @checked
    def from_faces(cls, paths: Annotated[Sequence, Items(6, PathArg(), "face images")]
                   ) -> Environment:
        """A cube map of six images (read by facet.formats.environment_files).

        Parameters
        ----------
        paths : six str or Path
            The faces in the order +X, -X, +Y, -Y, +Z, -Z, square and of one size.

        Returns
        -------
        Environment
            The environment.
        """
        return reader("cube faces")(paths)

    @classmethod
    @checked
    def from_equirect(cls, path: FilePath,
                      size: Annotated[int, Count(1, per_pixels=6)] = 256) -> Environment:
        """An equirectangular (latitude-longitude) image resampled onto the cube (read by
        facet.formats.environment_files).

        HDR files (.hdr, .exr) keep their linear radiance, above 1 too; 8-bit images are values
        in [0, 1].

        Parameters
        ----------
        path : str or Path
            The image.
        size : int
            Texels along a cube face's side.

        Returns
        -------
        Environment
            The environment.
        """
        return reader("environment")(path, size)

    @property
    def size(self) -> int:
        return self.faces.shape[1]

    @property
    def uniform_color(self) -> np.ndarray | None:
        """The one radiance of an environment that is the same in every direction
        (``constant``, or images of one colour), else None: the tracers then read it as a
        value, not a cube map (a texture lookup for every ray that escapes).

        Returns
        -------
        (3,) float32 or None
            Its texels' value, as stored (display values unless ``linear``).
        """
        if not hasattr(self, "_uniform"):
            first = self.faces[0, 0, 0]
            same = bool(np.all(self.faces == first)) and (
                self.equirect is None or bool(np.all(self.equirect == first)))
            self._uniform: np.ndarray | None = first.copy() if same else None
        return self._uniform
