"""Interactive camera control (numpy only): arcball orbit, pan and zoom towards the cursor.

``OrbitControl`` keeps a target point, a distance and an orientation (a unit quaternion,
w-first, camera -> world rotation) and turns them into a ``Camera``. Cursor positions are in
window pixels with the origin at the top-left, as GLFW reports them.

The arcball maps a cursor position to a point on a unit sphere filling the smaller window
side (Shoemake); a drag from p0 to p1 rotates the scene by the rotation that takes p0's point
to p1's, composed as quaternions, so there is no gimbal lock.
"""

from __future__ import annotations

import numpy as np

from . import transforms as T
from .camera import Camera
from .framing import default_direction, depth_range

ZOOM_STEP = 0.9  # distance factor per scroll notch (towards the cursor)
MAX_NOTCHES = 50.0  # the most notches one scroll event zooms
MIN_DISTANCE = 1e-4


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a * b of (w, x, y, z) quaternions."""
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
                     w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """3x3 rotation of a unit (w, x, y, z) quaternion."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def matrix_to_quat(m: np.ndarray) -> np.ndarray:
    """(w, x, y, z) of a 3x3 rotation matrix (Shepperd's method, stable for all angles)."""
    m = np.asarray(m, dtype=np.float64)
    t = np.trace(m)
    if t > 0:
        s = 2.0 * np.sqrt(t + 1.0)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = np.zeros(4)
        q[0] = (m[k, j] - m[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + k] = (m[k, i] + m[i, k]) / s
    q = np.asarray(q, dtype=np.float64)
    return q / np.linalg.norm(q)


def arcball_point(x: float, y: float, width: int, height: int) -> np.ndarray:
    """The unit-sphere point under cursor (x, y) (camera axes: x right, y up, z to viewer)."""
    r = min(width, height) / 2.0
    px, py = (x - width / 2.0) / r, (height / 2.0 - y) / r
    d2 = px * px + py * py
    if d2 <= 1.0:
        return np.array([px, py, np.sqrt(1.0 - d2)])
    return np.array([px, py, 0.0]) / np.sqrt(d2)  # outside the ball: on its rim


def arcball_rotation(p0, p1, width: int, height: int) -> np.ndarray:
    """Quaternion (camera axes) that rotates the ball point under p0 onto the one under p1."""
    a = arcball_point(*p0, width, height)
    b = arcball_point(*p1, width, height)
    # (1 + a.b, a x b), normalised, is the rotation by the angle between a and b about
    # a x b: the grabbed point of the ball stays under the cursor. (Shoemake's (a.b, a x b)
    # would turn twice as far.)
    q = np.array([1.0 + np.dot(a, b), *np.cross(a, b)])
    n = np.linalg.norm(q)
    return np.array([1.0, 0.0, 0.0, 0.0]) if n < 1e-12 else q / n


class OrbitControl:
    """Orbit / pan / zoom state for a viewer; ``camera(aspect)`` builds the Camera."""

    def __init__(self, bounds, direction=None, up=(0.0, 1.0, 0.0),
                 fov_y: float = 40.0, aspect: float = 1.0):
        self.fov_y = fov_y
        self.orthographic = False
        self.aperture, self.focus_distance = 0.0, None  # a thin lens, from set_camera
        self.shift = (0.0, 0.0)  # a shifted lens, from set_camera (Camera.shift)
        self.bounds = np.asarray(bounds, dtype=np.float64).reshape(2, 3)

        if direction is None:  # the default view for this up axis (Camera.frame's)
            direction = default_direction(up)
        self._home = (np.asarray(direction, dtype=np.float64), np.asarray(up, np.float64))
        self.frame(aspect)

    def frame(self, aspect: float = 1.0) -> None:
        """Fit the bounds in view along the initial direction (like ``Camera.frame``)."""
        direction, up = self._home
        cam = Camera.frame(self.bounds, direction, up, fov_y=self.fov_y, aspect=aspect)
        self.target = self.bounds.mean(axis=0)
        self.distance = float(np.linalg.norm(cam.eye - self.target))
        self.rotation = matrix_to_quat(np.linalg.inv(cam.view)[:3, :3])  # camera -> world
        self.ortho_height = 2.0 * self.distance * np.tan(np.radians(self.fov_y) / 2.0)

    reset = frame

    def set_camera(self, camera: Camera) -> None:
        """Take over a camera's position and orientation (its target: the bounds' centre
        projected onto the viewing axis)."""
        rot = np.linalg.inv(camera.view)[:3, :3]
        eye = camera.eye
        forward = -rot[:, 2]
        self.distance = max(float(np.dot(self.bounds.mean(axis=0) - eye, forward)),
                            MIN_DISTANCE)
        self.target = eye + forward * self.distance
        self.rotation = matrix_to_quat(rot)
        self.orthographic = camera.is_orthographic
        self.aperture, self.focus_distance = camera.aperture, camera.focus_distance  # lens
        self.shift = camera.shift
        if camera.is_orthographic:
            self.ortho_height = camera.ortho_height
        elif camera.fov_y is not None:
            self.fov_y = camera.fov_y

    @property
    def basis(self) -> np.ndarray:
        """3x3 camera -> world rotation (columns: right, up, backwards)."""
        return quat_to_matrix(self.rotation)

    @property
    def eye(self) -> np.ndarray:
        return self.target + self.basis[:, 2] * self.distance

    def orbit(self, p0, p1, width: int, height: int) -> None:
        """Drag from cursor p0 to p1: the scene turns with the cursor (arcball)."""
        q_cam = arcball_rotation(p0, p1, width, height)
        # Turning the scene by q is turning the camera by q^-1 (in camera axes).
        q_inv = q_cam * np.array([1.0, -1.0, -1.0, -1.0])
        self.rotation = quat_multiply(self.rotation, q_inv)
        self.rotation /= np.linalg.norm(self.rotation)

    def pan(self, dx: float, dy: float, width: int, height: int) -> None:
        """Drag by (dx, dy) pixels: the point under the cursor follows it (at target depth)."""
        per_pixel = self._view_height() / height
        b = self.basis
        self.target = self.target - b[:, 0] * dx * per_pixel + b[:, 1] * dy * per_pixel

    def zoom(self, notches: float, x: float, y: float, width: int, height: int) -> None:
        """Scroll ``notches`` (positive = in) towards the point under cursor (x, y): the point
        of the target plane under the cursor stays under the cursor. One call zooms at
        most ``MAX_NOTCHES`` notches either way (a wheel event of a million pixels)."""
        factor = ZOOM_STEP ** float(np.clip(notches, -MAX_NOTCHES, MAX_NOTCHES))
        per_pixel = self._view_height() / height
        b = self.basis
        offset = b[:, 0] * (x - width / 2.0) * per_pixel - b[:, 1] * (y - height / 2.0) * \
            per_pixel  # cursor point on the target plane, relative to the target
        self.target = self.target + offset * (1.0 - factor)
        if self.orthographic:
            self.ortho_height *= factor
        else:
            self.distance = max(self.distance * factor, MIN_DISTANCE)

    def _view_height(self) -> float:
        """Scene units spanned by the window height at the target's depth."""
        if self.orthographic:
            return self.ortho_height
        return 2.0 * self.distance * np.tan(np.radians(self.fov_y) / 2.0)

    def toggle_projection(self) -> None:
        """Switch perspective <-> orthographic, keeping the target plane the same size."""
        if not self.orthographic:
            self.ortho_height = self._view_height()
        self.orthographic = not self.orthographic

    def camera(self, aspect: float = 1.0) -> Camera:
        b = self.basis
        view = T.look_at(self.eye, self.target, b[:, 1])
        near, far = depth_range(view, self.bounds)
        near = min(near, max(self.distance * 0.01, 1e-4))
        far = max(far, self.distance * 1.01)
        if self.orthographic:
            cam = Camera(view, ortho_height=self.ortho_height, near=near, far=far)
        else:
            cam = Camera(view, fov_y=self.fov_y, near=max(near, far * 1e-5), far=far)
            cam.aperture, cam.focus_distance = self.aperture, self.focus_distance
        cam.shift = self.shift
        return cam
