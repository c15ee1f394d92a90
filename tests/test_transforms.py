"""Tier 1: the matrices against pyrr (row-vector convention, so transposed) and properties."""

import numpy as np
import pyrr
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from facet.geometry import planes
from facet.geometry import transforms as T

finite = st.floats(-10, 10, allow_nan=False)
vec3 = st.tuples(finite, finite, finite)
angle = st.floats(-360, 360, allow_nan=False)
axis = vec3.filter(lambda v: np.linalg.norm(v) > 1e-3)


def test_translate_matches_pyrr():
    m = T.translate((1, -2, 3))
    assert np.allclose(m, pyrr.matrix44.create_from_translation([1, -2, 3]).T)
    assert np.allclose(m @ [0, 0, 0, 1], [1, -2, 3, 1])


def test_scale_matches_pyrr():
    assert np.allclose(T.scale((2, 3, 4)), pyrr.matrix44.create_from_scale([2, 3, 4]).T)
    assert np.allclose(T.scale(2), np.diag([2, 2, 2, 1]))


@pytest.mark.parametrize("fn,pyrr_fn", [(T.rotate_x, pyrr.matrix44.create_from_x_rotation),
                                        (T.rotate_y, pyrr.matrix44.create_from_y_rotation),
                                        (T.rotate_z, pyrr.matrix44.create_from_z_rotation)])
@pytest.mark.parametrize("deg", [0, 30, 90, -135, 270])
def test_axis_rotations_match_pyrr(fn, pyrr_fn, deg):
    # pyrr's create_from_{x,y,z}_rotation turn row vectors clockwise for positive angles
    # (v @ M == R(-angle) v), so as arrays they equal our counter-clockwise column-vector R.
    ours = fn(deg)
    theirs = pyrr_fn(np.radians(deg))
    v = np.array([0.3, -0.7, 1.1, 1.0])
    assert np.allclose(theirs, ours, atol=1e-12)
    assert np.allclose(v @ theirs, np.linalg.inv(ours) @ v, atol=1e-12)


def test_rotation_direction_is_right_handed():
    assert np.allclose(T.rotate_z(90) @ [1, 0, 0, 1], [0, 1, 0, 1])
    assert np.allclose(T.rotate_x(90) @ [0, 1, 0, 1], [0, 0, 1, 1])
    assert np.allclose(T.rotate_y(90) @ [0, 0, 1, 1], [1, 0, 0, 1])


@given(axis, angle)
def test_rotate_axis_matches_pyrr(a, deg):
    ours = T.rotate(a, deg)
    unit = np.asarray(a) / np.linalg.norm(a)
    theirs = pyrr.matrix44.create_from_axis_rotation(unit, np.radians(deg))
    # pyrr's axis rotation is counter-clockwise for row vectors: v @ M == R v.
    v = np.array([0.3, -0.7, 1.1, 1.0])
    assert np.allclose(v @ theirs, ours @ v, atol=1e-9)


@given(axis, angle)
def test_rotations_orthonormal_det_one(a, deg):
    r = T.rotate(a, deg)[:3, :3]
    assert np.allclose(r @ r.T, np.eye(3), atol=1e-12)
    assert np.isclose(np.linalg.det(r), 1.0)


@given(vec3, vec3.filter(lambda s: min(abs(c) for c in s) > 0.1), axis, angle)
def test_inverses_compose_to_identity(t, s, a, deg):
    pairs = [(T.translate(t), T.translate(-np.asarray(t))),
             (T.scale(s), T.scale(1 / np.asarray(s))),
             (T.rotate(a, deg), T.rotate(a, -deg))]
    for m, inv in pairs:
        assert np.allclose(m @ inv, np.eye(4), atol=1e-9)


def test_shear_each_pair_and_order():
    p = np.array([1.0, 2.0, 3.0, 1.0])
    assert np.allclose(T.shear(xy=0.5) @ p, [2, 2, 3, 1])
    assert np.allclose(T.shear(zx=2) @ p, [1, 2, 5, 1])
    assert np.allclose(T.shear(yz=-1) @ p, [1, -1, 3, 1])
    # "shear then rotate" is R @ Sh; compose() applies its arguments first to last.
    r, sh = T.rotate_z(90), T.shear(xy=1)
    assert np.allclose(T.compose(sh, r), r @ sh)
    assert not np.allclose(r @ sh, sh @ r)
    with pytest.raises(ValueError):
        T.shear(xx=1)


def test_look_at_matches_pyrr():
    eye, target, up = [3.0, 2.0, 5.0], [0.0, 0.5, 0.0], [0.0, 1.0, 0.0]
    ours = T.look_at(eye, target, up)
    theirs = pyrr.matrix44.create_look_at(eye, target, up).T
    assert np.allclose(ours, theirs)
    # The target lies on the -z axis of camera space.
    p = ours @ [*target, 1.0]
    assert np.allclose(p[:2], 0) and p[2] < 0


def test_perspective_and_ortho_match_pyrr():
    assert np.allclose(T.perspective(60, 1.5, 0.1, 50),
                       pyrr.matrix44.create_perspective_projection(60, 1.5, 0.1, 50).T)
    assert np.allclose(T.orthographic(-2, 2, -1, 1, 0.5, 9),
                       pyrr.matrix44.create_orthogonal_projection(-2, 2, -1, 1, 0.5, 9).T)
    # Near plane maps to NDC z = -1, far plane to +1.
    p = T.perspective(60, 1.5, 0.1, 50)
    for z, ndc in ((-0.1, -1.0), (-50.0, 1.0)):
        c = p @ [0, 0, z, 1]
        assert np.isclose(c[2] / c[3], ndc)


@settings(max_examples=200)
@given(st.lists(finite, min_size=9, max_size=9), vec3, vec3)
def test_normal_matrix_keeps_normals_perpendicular(entries, a, b):
    """The notes' argument: n.t = 0 before => (G n).(M t) = 0 after, G = (M^-1)^T, for any
    invertible M (non-uniform scale and shear included)."""
    m = np.eye(4)
    m[:3, :3] = np.reshape(entries, (3, 3))
    if abs(np.linalg.det(m[:3, :3])) < 1e-2:
        return
    t = np.asarray(a)
    n = np.cross(t, b)
    if np.linalg.norm(n) < 1e-3 or np.linalg.norm(t) < 1e-3:
        return
    g = T.normal_matrix(m)
    t2, n2 = m[:3, :3] @ t, g @ n
    assert abs(np.dot(n2, t2)) <= 1e-8 * np.linalg.norm(n2) * np.linalg.norm(t2) * 1e3


def test_normal_matrix_differs_from_m_under_nonuniform_scale():
    m = T.compose(T.scale((1, 4, 1)), T.shear(xy=0.7))
    t, n = np.array([1.0, 1.0, 0.0]), np.array([1.0, -1.0, 0.0])
    assert abs(np.dot(m[:3, :3] @ n, m[:3, :3] @ t)) > 0.1  # M is wrong for normals
    assert abs(np.dot(T.normal_matrix(m) @ n, m[:3, :3] @ t)) < 1e-12


def test_bad_arguments():
    with pytest.raises(ValueError):
        T.look_at([0, 0, 0], [0, 0, 0])
    with pytest.raises(ValueError):
        T.look_at([0, 0, 1], [0, 0, 0], [0, 0, 1])
    with pytest.raises(ValueError):
        T.perspective(60, 1, 0, 10)
    with pytest.raises(ValueError):
        T.normal_matrix(T.scale((1, 0, 1)))


def test_reflection_and_plane_fit():
    """The mirror matrix fixes its plane, negates its normal, is its own inverse with
    determinant -1; fit_plane finds a tilted plane and rejects what is not flat."""
    n = np.array([1.0, 2.0, 2.0]) / 3.0
    plane = np.append(n, -1.5)  # n . x = 1.5
    m = planes.reflection(plane)
    on = 1.5 * n + np.cross(n, [0.0, 0.0, 1.0])
    assert np.allclose(m @ np.append(on, 1), np.append(on, 1))
    assert np.allclose(m[:3, :3] @ n, -n)
    assert np.allclose(m @ m, np.eye(4)) and np.isclose(np.linalg.det(m), -1.0)
    rng = np.random.default_rng(0)
    a, b = np.cross(n, [0, 0, 1.0]), np.cross(n, np.cross(n, [0, 0, 1.0]))
    pts = 1.5 * n + rng.random((50, 1)) * a + rng.random((50, 1)) * b
    fit = planes.fit_plane(pts)
    assert np.allclose(fit, plane) or np.allclose(fit, -plane)
    assert planes.fit_plane(pts + rng.normal(0, 0.05, pts.shape)) is None
    assert planes.fit_plane(np.outer(np.arange(5.0), n)) is None  # a line spans no plane
