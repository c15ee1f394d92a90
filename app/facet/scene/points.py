"""Point clouds and line sets (no GL): what scanners, CAD wireframes and glTF's POINTS and
LINES primitives hold, placed in a scene like meshes (``Scene.add``).

* ``Points``: positions (N, 3), optional colours (sRGB-encoded, as a mesh's) and normals.
  Drawn as round discs facing the viewer: ``size`` pixels across (screen-size, the
  default: 3 px), or ``radius`` in scene units (world-size, shrinking with distance). A disc
  lies at its point's depth, so the depth and ids channels are exact at its centre. Points
  with normals are lit like a surface; without, they show their colour, shaded by eye-dome
  lighting where ``edl`` is on (CloudCompare's and Potree's depth cue for unlit clouds).
* ``Lines``: positions (N, 3) and segments (M, 2) vertex indices (glTF LINES / LINE_STRIP /
  LINE_LOOP and OBJ ``l`` become segments), ``width`` pixels wide, unlit, in their colour.

The tracers treat points as spheres and lines as cylinders: of the world radius given, or
for sizes in pixels the radius that covers as many pixels at the camera's distance
(facet.render.trace). Arrays are read-only after construction (a renderer caches uploads by
object identity).
"""

from __future__ import annotations

from typing import Annotated

import numpy as np

from ..boundary import Array, ArrayLike, Number, checked
from ..errors import InputError

DEFAULT_POINT_SIZE = 3.0  # pixels across
DEFAULT_LINE_WIDTH = 1.5  # pixels
MAX_PIXELS = 256.0  # the largest point size or line width in pixels


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


def _positions(values, name: str) -> np.ndarray:
    p = np.asarray(values, dtype=np.float32)
    if p.ndim != 2 or p.shape[1] != 3 or len(p) == 0:
        raise InputError(f"{name}: positions must have shape (N, 3) with N >= 1, got "
                         f"{p.shape}")
    bad = ~np.isfinite(p).all(axis=1)
    if bad.any():
        raise InputError(f"{name}: {int(bad.sum())} positions are NaN or infinite (first at "
                         f"index {int(np.argmax(bad))})")
    return p


def _colors(values, n: int, name: str) -> np.ndarray | None:
    if values is None:
        return None
    c = np.asarray(values)
    if c.dtype == np.uint8:
        c = c / 255.0
    c = c.astype(np.float32)
    if c.ndim != 2 or c.shape[0] != n or c.shape[1] not in (3, 4):
        raise InputError(f"{name}: colors must have shape ({n}, 3|4), got {c.shape}")
    if not np.all(np.isfinite(c)) or c.min() < 0 or c.max() > 1:
        raise InputError(f"{name}: colours must be in [0, 1] (or uint8)")
    return c if c.shape[1] == 4 else np.hstack([c, np.ones((n, 1), np.float32)])


def _default_material(colors):
    """White where the points carry their own colours (they show as given), else None
    (the scene's default grey)."""
    if colors is None:
        return None
    from .material import Material

    return Material(color=(1.0, 1.0, 1.0))


def _pixels(value, name: str, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            not 0 < value <= MAX_PIXELS:
        raise InputError(f"{name}: {what} must be a number of pixels in (0, {MAX_PIXELS:g}], "
                         f"got {value!r}")
    return float(value)


class Points:
    """A point cloud: round discs a number of pixels across, or spheres of a radius in scene
    units (module docstring).

    Parameters
    ----------
    positions : (N, 3) float
        Finite positions, object space.
    colors : (N, 3) or (N, 4) float in [0, 1] or uint8, optional
        sRGB-encoded colours; None: the material's colour.
    normals : (N, 3) float, optional
        Points with normals are lit; without, they are drawn unlit (eye-dome lit).
    size : float, optional
        Pixels across (screen-size points); the default when ``radius`` is not given.
    radius : float, optional
        Scene units (world-size discs); give ``size`` or ``radius``, not both.
    edl : bool, optional
        Eye-dome lighting for unlit points (default: on when there are no normals).
    name : str
        Label used in messages.
    """

    kind = "points"

    @checked
    def __init__(self, positions: Annotated[ArrayLike, Array("N,3")],
                 colors: Annotated[ArrayLike | None, Array("N,3", "N,4")] = None,
                 normals: Annotated[ArrayLike | None, Array("N,3", finite=False)] = None, *,
                 size: Annotated[float | None, Number(0, open_lo=True)] = None,
                 radius: Annotated[float | None, Number(0, open_lo=True)] = None,
                 edl: bool | None = None, name: str = "points", material=None,
                 scalars: dict | None = None):
        self.name = name
        self.scalars = scalars or {}  # {name: (N,) floats} per point (PLY properties)
        self.positions = _readonly(_positions(positions, name))
        n = len(self.positions)
        c = _colors(colors, n, name)
        self.colors = None if c is None else _readonly(c)
        self.normals = None
        if normals is not None:
            nrm = np.asarray(normals, dtype=np.float32)
            if nrm.shape != (n, 3):
                raise InputError(f"{name}: normals must have shape ({n}, 3), got {nrm.shape}")
            length = np.linalg.norm(nrm, axis=1, keepdims=True)
            if np.all(np.isfinite(length)) and np.all(length > 0):
                self.normals = _readonly(nrm / length)
        if size is not None and radius is not None:
            raise InputError(f"{name}: give a size in pixels or a radius in scene units, "
                             "not both")
        if radius is not None:
            if isinstance(radius, bool) or not isinstance(radius, (int, float)) or \
                    not (np.isfinite(radius) and radius > 0):
                raise InputError(f"{name}: radius must be a positive number of scene units, "
                                 f"got {radius!r}")
            self.radius: float | None = float(radius)
            self.size: float | None = None
        else:
            self.size = _pixels(DEFAULT_POINT_SIZE if size is None else size, name, "size")
            self.radius = None
        self.edl = self.normals is None if edl is None else bool(edl)
        self.material = material if material is not None else _default_material(self.colors)
        self._bounds: np.ndarray | None = None

    @checked
    def colored_by(self, values: Annotated[ArrayLike, Array("N")], colormap: str = "viridis",
                   limits: Annotated[ArrayLike | None, Array("2")] = None) -> Points:
        """The same cloud coloured by per-point scalars through a colormap.

        Parameters
        ----------
        values : (N,) float
            One value per point (NaN shows grey).
        colormap : str
            A colormap name (facet.scene.colormap).
        limits : (float, float), optional
            The values mapped to the colormap's ends (default: the values' range).

        Returns
        -------
        Points
            The coloured cloud (positions shared).
        """
        from .colormap import colors_for, scalars

        v = scalars(values, f"{self.name}: colored_by values")
        if len(v) != len(self.positions):
            raise InputError(f"{self.name}: values: {len(v)} scalars for {len(self.positions)} "
                             "points")
        return Points(self.positions, colors_for(v, colormap, limits), self.normals,
                      size=self.size, radius=self.radius, edl=self.edl, name=self.name,
                      scalars=self.scalars)

    @checked
    def sized(self, size: Annotated[float | None, Number(0, open_lo=True)] = None,
              radius: Annotated[float | None, Number(0, open_lo=True)] = None) -> Points:
        """The same cloud drawn at another size (one of ``size`` and ``radius``).

        Parameters
        ----------
        size : float, optional
            Pixels across.
        radius : float, optional
            Scene units.

        Returns
        -------
        Points
            The resized cloud (arrays shared).
        """
        return Points(self.positions, self.colors, self.normals, size=size, radius=radius,
                      edl=self.edl, name=self.name, material=self.material,
                      scalars=self.scalars)

    @property
    def vertex_count(self) -> int:
        return len(self.positions)

    face_count = 0  # (meshes' triangle counts; a cloud has none)
    uvs = uvs1 = _tangents = tangents = None

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float64 min and max of the positions (padded by a world radius)."""
        if self._bounds is None:
            pad = self.radius or 0.0
            self._bounds = np.stack([self.positions.min(axis=0) - pad,
                                     self.positions.max(axis=0) + pad]).astype(np.float64)
        return self._bounds

    def __repr__(self) -> str:
        how = f"radius={self.radius:g}" if self.radius else f"size={self.size:g}px"
        return f"Points({self.name!r}, {len(self.positions):,} points, {how})"


class Lines:
    """Line segments a number of pixels wide (module docstring).

    Parameters
    ----------
    positions : (N, 3) float
        Finite vertex positions, object space.
    segments : (M, 2) int, optional
        Vertex indices of each segment, M >= 1 (default: consecutive pairs 0-1, 2-3, ...).
    colors : (N, 3) or (N, 4) float in [0, 1] or uint8, optional
        sRGB-encoded colours per vertex.
    width : float, optional
        Pixels (default DEFAULT_LINE_WIDTH).
    name : str
        Label used in messages.
    """

    kind = "lines"

    @checked
    def __init__(self, positions: Annotated[ArrayLike, Array("N,3")],
                 segments: Annotated[ArrayLike | None, Array("M,2", finite=False)] = None,
                 colors: Annotated[ArrayLike | None, Array("N,3", "N,4")] = None, *,
                 width: Annotated[float | None, Number(0, open_lo=True)] = None,
                 name: str = "lines", material=None):
        self.name = name
        self.positions = _readonly(_positions(positions, name))
        n = len(self.positions)
        if segments is None:
            if n % 2:
                raise InputError(f"{name}: {n} positions do not pair up into segments; give "
                                 "segments (M, 2)")
            segments = np.arange(n).reshape(-1, 2)
        seg = np.asarray(segments)
        if seg.ndim != 2 or seg.shape[1] != 2 or len(seg) == 0 or \
                not np.issubdtype(seg.dtype, np.integer):
            raise InputError(f"{name}: segments must be (M, 2) integer indices with M >= 1, "
                             f"got {seg.shape} {seg.dtype}")
        if seg.min() < 0 or seg.max() >= n:
            raise InputError(f"{name}: segment indices must be in [0, {n - 1}], got "
                             f"[{seg.min()}, {seg.max()}]")
        self.segments = _readonly(seg.astype(np.uint32))
        c = _colors(colors, n, name)
        self.colors = None if c is None else _readonly(c)
        self.width = _pixels(DEFAULT_LINE_WIDTH if width is None else width, name, "width")
        self.material = material if material is not None else _default_material(self.colors)
        self.normals = None
        self._bounds: np.ndarray | None = None

    @checked
    def widened(self, width: Annotated[float, Number(0, open_lo=True)]) -> Lines:
        """The same lines at another width.

        Parameters
        ----------
        width : float
            Pixels.

        Returns
        -------
        Lines
            The lines (arrays shared).
        """
        return Lines(self.positions, self.segments, self.colors, width=width, name=self.name,
                     material=self.material)

    @property
    def vertex_count(self) -> int:
        return len(self.positions)

    face_count = 0
    uvs = uvs1 = _tangents = tangents = None

    @property
    def bounds(self) -> np.ndarray:
        if self._bounds is None:
            self._bounds = np.stack([self.positions.min(axis=0),
                                     self.positions.max(axis=0)]).astype(np.float64)
        return self._bounds

    def __repr__(self) -> str:
        return f"Lines({self.name!r}, {len(self.segments):,} segments, width={self.width:g}px)"


def resize_sprites(mesh, point_size=None, point_radius=None, line_width=None):
    """``mesh`` with the sizes given (None: as it is); meshes pass through."""
    if mesh.kind == "points" and (point_size is not None or point_radius is not None):
        return mesh.sized(point_size, point_radius)
    if mesh.kind == "lines" and line_width is not None:
        return mesh.widened(line_width)
    return mesh


def resize_scene(scene, sizes: dict) -> None:
    """Every point cloud and line set of ``scene`` at ``sizes`` ({"point_size",
    "point_radius", "line_width"}: None keeps the file's)."""
    if all(v is None for v in sizes.values()):
        return
    from dataclasses import replace

    scene.objects = [replace(o, mesh=resize_sprites(o.mesh, **sizes)) for o in scene.objects]


def strip_segments(indices: np.ndarray, loop: bool = False) -> np.ndarray:
    """(M, 2) segments of a line strip (each index to the next; ``loop``: and the last back
    to the first)."""
    idx = np.asarray(indices, dtype=np.int64)
    seg = np.stack([idx[:-1], idx[1:]], axis=1)
    if loop and len(idx) > 2:
        seg = np.vstack([seg, [[idx[-1], idx[0]]]])
    return seg
