"""Cameras: the viewing transformation plus a perspective, parallel or intrinsics projection.

A ``Camera`` holds ``view`` (world -> camera space, OpenGL axes: x right, y up, looking down -z)
and the parameters of its projection. ``projection(width, height)`` builds the clip matrix for
an image of that size.

Images are row 0 = top. OpenCV intrinsics (fx, fy, cx, cy) use pixel centres at integer
coordinates and the origin at the top-left corner, so pixel (i, j) covers
[i - 0.5, i + 0.5] x [j - 0.5, j + 0.5]; a point OpenCV projects to (u, v) lands in the pixel
(round(u), round(v)). OpenCV's camera axes are x right, y down, z forward; they differ from
OpenGL's by a flip of y and z.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np

from ..boundary import Array, ArrayLike, Count, Number, Positive, Real, Vec3, checked
from ..errors import InputError
from . import transforms as T
from .framing import default_direction, depth_range
from .intrinsics import CV_TO_GL, Intrinsics

# Padding around a framed bounding box, as a factor on the tight fit.
FRAME_MARGIN = 1.05


class Camera:
    """A camera: ``view`` (world -> camera, OpenGL axes) and one projection.

    Build one with ``Camera.look_at``, ``Camera.from_intrinsics`` or ``Camera.frame``.
    Exactly one of ``fov_y``, ``ortho_height`` or ``intrinsics`` is set.

    Parameters
    ----------
    view : (4, 4) float
        World -> camera transform (x right, y up, looking down -z).
    fov_y : float or None
        Vertical field of view, degrees (a perspective camera).
    ortho_height : float or None
        Height of the view in scene units (a parallel projection).
    intrinsics : Intrinsics or None
        OpenCV intrinsics (a pinhole camera of a fixed image size).
    near, far : float
        Clipping distances along the view axis, 0 < near < far.
    """

    def __init__(self, view, *, fov_y: float | None = 45.0, ortho_height: float | None = None,
                 intrinsics: Intrinsics | None = None, near: float = 0.1, far: float = 100.0):
        self.view = np.array(view, dtype=np.float64).reshape(4, 4)
        if not np.all(np.isfinite(self.view)):
            raise InputError("camera view matrix must be finite")
        self.fov_y = None if (ortho_height is not None or intrinsics is not None) else fov_y
        self.ortho_height = ortho_height
        self.intrinsics = intrinsics
        self.near = float(near)
        self.far = float(far)
        # Thin lens for depth of field (facet.geometry.lens): lens diameter in scene units
        # (0: a pinhole, everything sharp) and the distance of the sharp plane along the
        # viewing axis.
        self.aperture = 0.0
        self.focus_distance: float | None = None
        # A shifted lens (a tilt-shift's shift, USD's aperture offsets): the view window's
        # centre moved right and up by these fractions of its height, the eye and axis kept
        # (an off-axis frustum). Perspective and parallel cameras; intrinsics give cx, cy.
        self.shift = (0.0, 0.0)
        if ortho_height is not None and not ortho_height > 0:
            raise InputError(f"ortho_height must be > 0, got {ortho_height}")
        # Validates near/far and fov up front, so a bad camera fails where it is made.
        self.projection(1, 1) if intrinsics is None else self.projection(
            intrinsics.width, intrinsics.height)

    @property
    def is_orthographic(self) -> bool:
        return self.ortho_height is not None

    @property
    def eye(self) -> np.ndarray:
        """Camera position in world space, (3,)."""
        # Asked for on every draw: the inverse is kept until the view changes (compared by
        # value: ``view`` is a public array that may be changed in place).
        key = self.view.tobytes()
        cached = self.__dict__.get("_eye")
        if cached is None or cached[0] != key:
            cached = self._eye = (key, np.linalg.inv(self.view)[:3, 3])
        return cached[1].copy()

    @property
    def forward(self) -> np.ndarray:
        """Unit viewing direction in world space, (3,)."""
        return -self.view[2, :3] / np.linalg.norm(self.view[2, :3])

    # -- constructors ------------------------------------------------------------------------
    @classmethod
    @checked
    def look_at(cls, eye: Vec3, target: Vec3, up: Vec3 = (0.0, 1.0, 0.0), *,
                fov_y: Annotated[float, Number(0, 180, open_lo=True, open_hi=True)] = 45.0,
                ortho_height: Annotated[float | None, Number(0, open_lo=True)] = None,
                near: Annotated[float, Number(0, open_lo=True)] = 0.1,
                far: Annotated[float, Number(0, open_lo=True)] = 100.0) -> Camera:
        """A camera at ``eye`` looking at ``target``; perspective unless ``ortho_height``
        is given.

        Parameters
        ----------
        eye, target : (3,) float
            Position and the point looked at, world space.
        up : (3,) float
            World up (not parallel to the viewing direction).
        fov_y : float
            Vertical field of view, degrees.
        ortho_height : float, optional
            Make a parallel projection this many scene units tall.
        near, far : float
            Clipping distances.

        Returns
        -------
        Camera
            The camera.
        """
        return cls(T.look_at(eye, target, up), fov_y=fov_y, ortho_height=ortho_height,
                   near=near, far=far)

    @classmethod
    @checked
    def from_intrinsics(cls, fx: Positive, fy: Positive, cx: Real, cy: Real,
                        width: Annotated[int, Count(1)], height: Annotated[int, Count(1)],
                        pose: Annotated[ArrayLike | None, Array("4,4")] = None, *,
                        near: Positive = 0.01, far: Positive = 100.0) -> Camera:
        """A camera from OpenCV intrinsics; reprojects to OpenCV's pixels exactly.

        Parameters
        ----------
        fx, fy, cx, cy : float
            Focal lengths and principal point, pixels.
        width, height : int
            The image size (renders must use it).
        pose : (4, 4) float, optional
            Camera -> world in OpenCV camera axes (x right, y down, z forward): the inverse of
            OpenCV's extrinsics [R | t]. Default: identity.
        near, far : float
            Clipping distances.

        Returns
        -------
        Camera
            The camera.
        """
        vals = np.array([fx, fy, cx, cy], dtype=np.float64)
        if not np.all(np.isfinite(vals)) or fx <= 0 or fy <= 0:
            raise InputError(f"intrinsics need finite fx, fy > 0, got {vals.tolist()}")
        if int(width) < 1 or int(height) < 1:
            raise InputError(f"intrinsics image size must be >= 1, got {width}x{height}")
        pose = np.eye(4) if pose is None else np.asarray(pose, dtype=np.float64).reshape(4, 4)
        view = CV_TO_GL @ np.linalg.inv(pose)
        k = Intrinsics(float(fx), float(fy), float(cx), float(cy), int(width), int(height))
        return cls(view, intrinsics=k, near=near, far=far)

    @classmethod
    @checked
    def frame(cls, bounds: Annotated[ArrayLike, Array("2,3")],
              direction: Annotated[ArrayLike | None, Array("3")] = None,
              up: Vec3 = (0.0, 1.0, 0.0), *,
              fov_y: Annotated[float, Number(0, 180, open_lo=True, open_hi=True)] = 40.0,
              aspect: Annotated[float, Number(1e-6, 1e6)] = 1.0, ortho: bool = False,
              margin: Annotated[float, Number(1e-3, 1e3)] = FRAME_MARGIN) -> Camera:
        """A camera looking along ``direction`` that fits the box ``bounds`` in view.

        The distance is the smallest for which all eight corners fall inside the frustum (for an
        image of the given ``aspect``), times ``margin``.

        Parameters
        ----------
        bounds : (2, 3) float
            Min and max corners of the box, world space (``scene.bounds``).
        direction : (3,) float, optional
            Viewing direction (default: from the front, right and above, relative to ``up``).
        up : (3,) float
            World up.
        fov_y : float
            Vertical field of view, degrees.
        aspect : float
            Image width / height.
        ortho : bool
            A parallel projection instead.
        margin : float
            Room around the box (1: touching).

        Returns
        -------
        Camera
            The camera, near and far fitted around the box.
        """
        b = np.asarray(bounds, dtype=np.float64).reshape(2, 3)
        if not np.all(np.isfinite(b)):
            raise InputError("frame: bounds must be finite")
        d = T._vec3(default_direction(up) if direction is None else direction, "direction")
        if np.linalg.norm(d) == 0:
            raise InputError("frame: direction must not be zero")
        d = d / np.linalg.norm(d)
        center = b.mean(axis=0)
        radius = max(float(np.linalg.norm(b[1] - b[0])) / 2.0, 1e-6)
        corners = np.array([[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]])
        # Corners in the basis of a camera at `center` (x right, y up, z towards the viewer).
        rot = T.look_at(center, center + d, up)[:3, :3]
        local = (corners - center) @ rot.T
        tan_y = np.tan(np.radians(fov_y) / 2.0)
        if ortho:
            half = max(float(np.abs(local[:, 1]).max()),
                       float(np.abs(local[:, 0]).max()) / aspect, 1e-6)
            dist = 2.0 * radius * margin
            height: float | None = 2.0 * half * margin
        else:
            need = np.maximum(np.abs(local[:, 0]) / (tan_y * aspect), np.abs(local[:, 1]) / tan_y)
            dist = max(float((local[:, 2] + need).max()) * margin, 1e-6)
            height = None
        eye = center - d * dist
        near = max(dist - radius * 1.01, radius * 1e-3)
        far = dist + radius * 1.01
        return cls(T.look_at(eye, center, up), fov_y=fov_y, ortho_height=height,
                   near=near, far=far)

    @classmethod
    def looking_at_bounds(cls, eye, target, up, bounds, *, fov_y: float = 40.0,
                          ortho_height: float | None = None) -> Camera:
        """``look_at`` with near and far planes fitted around a box.

        Parameters
        ----------
        eye, target, up : (3,) float
            As ``look_at``.
        bounds : (2, 3) float
            The box the clipping planes must hold.
        fov_y : float
            Vertical field of view, degrees.
        ortho_height : float, optional
            A parallel projection this tall instead.

        Returns
        -------
        Camera
            The camera.
        """
        view = T.look_at(eye, target, up)
        near, far = depth_range(view, bounds)
        return cls(view, fov_y=fov_y, ortho_height=ortho_height, near=near, far=far)

    # -- projection --------------------------------------------------------------------------
    @checked
    def projection(self, width: Annotated[int, Count(1)],
                   height: Annotated[int, Count(1)]) -> np.ndarray:
        """The camera -> clip matrix for an image of ``width`` x ``height`` pixels.

        Parameters
        ----------
        width, height : int
            The image size (the intrinsics' for an intrinsics camera).

        Returns
        -------
        (4, 4) float64 ndarray
            OpenGL's projection matrix.
        """
        if self.intrinsics is not None:
            return self._intrinsics_projection(width, height)
        aspect = width / height
        if self.ortho_height is not None:
            h = self.ortho_height / 2.0
            m = T.orthographic(-h * aspect, h * aspect, -h, h, self.near, self.far)
        else:
            assert self.fov_y is not None  # a perspective camera without intrinsics has one
            m = T.perspective(self.fov_y, aspect, self.near, self.far)
        sx, sy = self.shift
        if sx or sy:  # the window's centre to NDC's: clip x' = x - 2 sx / aspect w
            m = m.copy()
            m[0] -= 2.0 * sx / aspect * m[3]
            m[1] -= 2.0 * sy * m[3]
        return m

    def _intrinsics_projection(self, width: int, height: int) -> np.ndarray:
        k = self.intrinsics
        assert k is not None
        if (width, height) != (k.width, k.height):
            raise InputError(f"camera intrinsics are for {k.width}x{k.height} images, "
                             f"but the render is {width}x{height}")
        T._check_depth_range(self.near, self.far, perspective=True)
        n, f = self.near, self.far
        # Derived from u = fx x_cv / z_cv + cx with x_cv = x, y_cv = -y, z_cv = -z (GL view
        # space) and NDC x = 2 (u + 0.5) / W - 1, NDC y = 1 - 2 (v + 0.5) / H (row 0 at top).
        m = np.zeros((4, 4))
        m[0, 0] = 2.0 * k.fx / width
        m[0, 2] = 1.0 - 2.0 * (k.cx + 0.5) / width
        m[1, 1] = 2.0 * k.fy / height
        m[1, 2] = 2.0 * (k.cy + 0.5) / height - 1.0
        m[2, 2] = -(f + n) / (f - n)
        m[2, 3] = -2.0 * f * n / (f - n)
        m[3, 2] = -1.0
        return m

    def K(self, width: int, height: int) -> np.ndarray:  # noqa: N802
        """The OpenCV camera matrix for an image of this size (perspective cameras only).

        Parameters
        ----------
        width, height : int
            The image size.

        Returns
        -------
        (3, 3) float64 ndarray
            ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``.
        """
        if self.intrinsics is not None:
            return self.intrinsics.K
        if self.fov_y is None:
            raise InputError("an orthographic camera has no pinhole intrinsics")
        f = height / 2.0 / np.tan(np.radians(self.fov_y) / 2.0)
        sx, sy = self.shift  # (the window's centre moved right and up by heights)
        return np.array([[f, 0.0, (width - 1) / 2.0 - sx * height],
                         [0.0, f, (height - 1) / 2.0 + sy * height], [0.0, 0.0, 1.0]])

    @checked
    def orbit(self, center: Vec3, axis: Vec3, degrees: Real) -> Camera:
        """This camera moved ``degrees`` around the line through ``center`` along
        ``axis`` (right-handed), looking the same way relative to the centre.

        Parameters
        ----------
        center : (3,) float
            A point on the axis, world space.
        axis : (3,) float
            The axis direction.
        degrees : float
            The angle.

        Returns
        -------
        Camera
            A new camera (projection, near and far kept).
        """
        m = T.compose(T.translate(-np.asarray(center, dtype=np.float64)),
                      T.rotate(axis, degrees), T.translate(center))
        # The camera's pose (camera -> world) is moved by m, so the view is view @ m^-1.
        return self.with_view(self.view @ np.linalg.inv(m))

    def with_view(self, view) -> Camera:
        """The same camera (projection, near, far, lens) with another view.

        Parameters
        ----------
        view : (4, 4) float
            World -> camera, e.g. ``view @ reflection`` for a mirror's camera.

        Returns
        -------
        Camera
            A new camera.
        """
        moved = Camera(view, fov_y=self.fov_y, ortho_height=self.ortho_height,
                       intrinsics=self.intrinsics, near=self.near, far=self.far)
        moved.aperture, moved.focus_distance = self.aperture, self.focus_distance
        moved.shift = self.shift
        return moved

    def describe(self, width: int, height: int) -> dict:
        """Plain data for re-projecting a render of ``width`` x ``height`` (JSON-ready).

        Parameters
        ----------
        width, height : int
            The image size.

        Returns
        -------
        dict
            ``model``, ``width``, ``height``, ``near``, ``far``, ``K`` (3x3 lists; None for
            orthographic cameras, which give ``ortho_height``), ``world_to_camera`` (OpenCV axes:
            x right, y down, z forward, matching ``K``), ``world_to_camera_opengl`` (``view``),
            ``projection_opengl`` (camera -> clip) and ``eye``.
        """
        info = {
            "model": "orthographic" if self.is_orthographic else "perspective",
            "width": int(width), "height": int(height),
            "near": self.near, "far": self.far,
            "K": None if self.is_orthographic else self.K(width, height).tolist(),
            "world_to_camera": (CV_TO_GL @ self.view).tolist(),
            "world_to_camera_opengl": self.view.tolist(),
            "projection_opengl": self.projection(width, height).tolist(),
            "eye": self.eye.tolist(),
        }
        if self.is_orthographic:
            info["ortho_height"] = self.ortho_height
        else:
            info["fov_y"] = float(2 * np.degrees(np.arctan(height / 2 / self.K(width,
                                                                               height)[1, 1])))
        return info

    def __repr__(self) -> str:
        kind = ("intrinsics" if self.intrinsics else
                f"ortho_height={self.ortho_height:g}" if self.is_orthographic else
                f"fov_y={self.fov_y:g}")
        return f"Camera(eye={np.round(self.eye, 4).tolist()}, {kind}, near={self.near:g}, " \
               f"far={self.far:g})"
