"""Camera control math for the viewer (no GL, no window)."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from facet.geometry import transforms as T
from facet.geometry.orbit import (
    OrbitControl,
    arcball_point,
    arcball_rotation,
    matrix_to_quat,
    quat_to_matrix,
)

W, H = 800, 600
BOUNDS = [[-1, -1, -1], [1, 1, 1]]


def test_arcball_centre_and_rim():
    assert np.allclose(arcball_point(400, 300, W, H), [0, 0, 1])
    assert np.allclose(arcball_point(700, 300, W, H), [1, 0, 0])  # radius = 300 px
    assert np.allclose(arcball_point(400, 0, W, H), [0, 1, 0])  # screen y grows down
    assert np.allclose(arcball_point(800, 300, W, H), [1, 0, 0])  # outside: on the rim


def test_horizontal_drag_is_a_rotation_about_the_view_up_axis():
    q = arcball_rotation((400, 300), (700, 300), W, H)
    assert np.allclose(quat_to_matrix(q), T.rotate_y(90)[:3, :3], atol=1e-12)
    # The grabbed point follows the cursor.
    a, b = arcball_point(450, 250, W, H), arcball_point(520, 330, W, H)
    r = quat_to_matrix(arcball_rotation((450, 250), (520, 330), W, H))
    assert np.allclose(r @ a, b)


@given(st.floats(0, 800), st.floats(0, 600), st.floats(0, 800), st.floats(0, 600))
def test_arcball_rotations_are_proper(x0, y0, x1, y1):
    r = quat_to_matrix(arcball_rotation((x0, y0), (x1, y1), W, H))
    assert np.allclose(r @ r.T, np.eye(3), atol=1e-9) and np.isclose(np.linalg.det(r), 1)


def test_quaternion_round_trip():
    for m in (T.rotate((1, 2, 3), 170), T.rotate_x(180), T.rotate_y(-90), np.eye(4)):
        assert np.allclose(quat_to_matrix(matrix_to_quat(m[:3, :3])), m[:3, :3], atol=1e-12)


def test_orbit_turns_the_scene_with_the_cursor():
    c = OrbitControl(BOUNDS, direction=(0, 0, -1))
    before = c.camera(W / H).view
    c.orbit((400, 300), (700, 300), W, H)  # drag right by a ball radius: 90 degrees
    after = c.camera(W / H).view
    # The scene turned +90 degrees about the view's up axis through the target, which sits
    # at (0, 0, -distance) in camera space.
    d = c.distance
    expected = T.translate((0, 0, -d)) @ T.rotate_y(90) @ T.translate((0, 0, d)) @ before
    assert np.allclose(after, expected, atol=1e-9)
    assert np.isclose(np.linalg.norm(c.eye - c.target), c.distance)


def test_pan_moves_the_target_with_the_cursor():
    c = OrbitControl(BOUNDS, direction=(0, 0, -1))
    cam = c.camera(W / H)
    p = c.target.copy()
    c.pan(100, 0, W, H)
    cam2 = c.camera(W / H)
    # The old target now projects 100 px to the right of the centre.
    clip = cam2.projection(W, H) @ cam2.view @ [*p, 1]
    x_px = (clip[0] / clip[3] + 1) / 2 * W
    assert x_px == pytest.approx(W / 2 + 100, abs=1e-6)
    assert np.allclose(cam.forward, cam2.forward)


@pytest.mark.parametrize("ortho", [False, True])
def test_zoom_towards_the_cursor_keeps_the_point_under_it(ortho):
    c = OrbitControl(BOUNDS, direction=(0, 0, -1))
    if ortho:
        c.toggle_projection()
    cam = c.camera(W / H)
    x, y = 600, 200
    # The point of the target plane under the cursor, in world space.
    ndc = np.array([2 * x / W - 1, 1 - 2 * y / H])
    inv = np.linalg.inv(cam.projection(W, H) @ cam.view)
    depth_ndc = (cam.projection(W, H) @ cam.view @ [*c.target, 1])
    z = depth_ndc[2] / depth_ndc[3]
    p = inv @ [*ndc, z, 1]
    p = p[:3] / p[3]
    d0 = c.distance if not ortho else c.ortho_height
    c.zoom(3, x, y, W, H)
    cam2 = c.camera(W / H)
    clip = cam2.projection(W, H) @ cam2.view @ [*p, 1]
    assert np.allclose(clip[:2] / clip[3], ndc, atol=1e-9)
    assert (c.distance if not ortho else c.ortho_height) == pytest.approx(d0 * 0.9**3)


def test_reset_and_projection_toggle():
    c = OrbitControl(BOUNDS)
    home = c.camera(1.0).view.copy()
    c.orbit((100, 100), (300, 400), W, H)
    c.pan(20, 30, W, H)
    c.reset(1.0)
    assert np.allclose(c.camera(1.0).view, home)
    height = 2 * c.distance * np.tan(np.radians(c.fov_y) / 2)
    c.toggle_projection()
    cam = c.camera(1.0)
    assert cam.is_orthographic and cam.ortho_height == pytest.approx(height)
