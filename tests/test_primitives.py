"""Built-in primitives: closed, outward-facing, the right size, with uvs; bad sizes fail."""

import numpy as np
import pytest

from facet.errors import InputError
from facet.scene import primitives as P

EXPECTED_VOLUME = {
    "sphere": 4 / 3 * np.pi * 0.7**3,
    "cube": 0.5 * 1.0 * 2.0,
    "cylinder": np.pi * 0.5**2 * 2.0,
    "cone": np.pi * 0.5**2 * 2.0 / 3,
    "torus": 2 * np.pi**2 * 1.0 * 0.25**2,
}
ARGS = {"sphere": (0.7,), "cube": ((0.5, 1.0, 2.0),), "cylinder": (0.5, 2.0),
        "cone": (0.5, 2.0), "torus": (1.0, 0.25), "plane": ((2.0, 3.0),), "disk": (1.5,)}


@pytest.mark.parametrize("name", list(P.PRIMITIVES))
def test_primitive_geometry(name):
    mesh = P.PRIMITIVES[name](*ARGS[name])
    tri = mesh.positions[mesh.faces].astype(float)
    face_n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ok = np.linalg.norm(face_n, axis=1) > 1e-12
    vertex_n = mesh.normals[mesh.faces].mean(axis=1)
    # Counter-clockwise seen from outside: face normals agree with the vertex normals.
    assert np.all(np.sum(face_n[ok] * vertex_n[ok], axis=1) > 0)
    assert mesh.uvs is not None and mesh.uvs.min() >= 0 and mesh.uvs.max() <= 1
    volume = np.sum(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2]))) / 6
    if name == "plane":
        assert np.allclose(np.ptp(mesh.positions, axis=0), [2, 0, 3])
    elif name == "disk":
        assert np.allclose(np.ptp(mesh.positions, axis=0), [3, 0, 3])
        assert np.all(np.abs(mesh.normals - [0, 1, 0]) < 1e-9)
    else:
        assert volume == pytest.approx(EXPECTED_VOLUME[name], rel=0.02)


@pytest.mark.parametrize("call,message", [
    (lambda: P.sphere(0), "sphere radius must be a number > 0"),
    (lambda: P.cube((1, 0, 1)), "cube size"),
    (lambda: P.cylinder(1, -1), "cylinder height"),
    (lambda: P.torus(1, 2), "smaller than major_radius"),
    (lambda: P.plane(float("nan")), "plane size"),
])
def test_bad_sizes(call, message):
    with pytest.raises(InputError, match=message):
        call()
