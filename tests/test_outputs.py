"""Tier 2: every output channel against analytic values, all from one render call."""

import json

import numpy as np
import pytest

from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Material, Mesh, Scene

from conftest import sphere_mesh
from reference import erode, pixel_rays, ray_sphere

SIZE = 64
ALL = ("color", "depth", "ids", "normals", "position", "uv")


def _scene(mesh, transform=None):
    scene = Scene()
    scene.add(mesh, Material(), transform=transform)
    scene.add_light(DirectionalLight((0, 0, -1)))
    return scene


@pytest.mark.parametrize("msaa", [0, 4])
@pytest.mark.parametrize("ortho", [False, True])
def test_sphere_normals_and_positions(renderer, msaa, ortho):
    centre = np.array([0.3, -0.2, 0.1])
    camera = Camera.look_at((1, 1.5, 4), (0, 0, 0), fov_y=40,
                            ortho_height=3 if ortho else None, near=1, far=10)
    scene = _scene(sphere_mesh(), T.translate(centre))
    frame = renderer(SIZE, SIZE, msaa).render(scene, camera, outputs=ALL)
    o, d = pixel_rays(camera.view, camera.projection(SIZE, SIZE), SIZE, SIZE)
    t = ray_sphere(o, d, centre, 1.0)
    hit = np.isfinite(t)
    p = o + np.where(hit, t, 0)[..., None] * d
    inner = erode(hit, 2)
    assert np.array_equal(frame.object_ids == 0, frame.depth > 0)
    assert np.abs(frame.position - p)[inner].max() < 2e-3
    n_exact = (p - centre)
    assert np.abs(frame.normals - n_exact)[inner].max() < 2e-3
    assert np.all(frame.normals[~hit & (frame.object_ids == -1)] == 0)
    # Camera-space normals: the same vectors rotated into the camera's axes; they face us.
    cam_n = frame.camera_normals()[inner]
    assert np.allclose(cam_n, n_exact[inner] @ camera.view[:3, :3].T, atol=2e-3)
    assert np.all(cam_n[:, 2] > -1e-3)


def test_plane_positions_and_uvs(renderer):
    """A unit quad with uvs (0..1) scaled to 4x4 and tilted: position and uv are exact
    functions of each other, and both match the ray-plane intersection."""
    pos = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]
    uvs = [[0, 0], [1, 0], [1, 1], [0, 1]]
    quad = Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4, uvs)
    m = T.compose(T.scale(2), T.rotate_x(-50), T.translate((0, -0.5, 0)))
    camera = Camera.look_at((0.5, 1, 5), (0, 0, 0), fov_y=45, near=1, far=20)
    frame = renderer(SIZE, SIZE).render(_scene(quad, m), camera, outputs=ALL)
    o, d = pixel_rays(camera.view, camera.projection(SIZE, SIZE), SIZE, SIZE)
    q, n = m[:3, 3], T.normal_matrix(m) @ [0, 0, 1]
    t = np.sum((q - o) * n, -1) / np.sum(d * n, -1)
    p = o + t[..., None] * d
    inner = erode(frame.object_ids == 0, 1)
    assert inner.sum() > 500
    assert np.abs(frame.position - p)[inner].max() < 2e-3
    local = (p - m[:3, 3]) @ np.linalg.inv(m[:3, :3]).T  # back to the quad's own space
    expected_uv = (local[..., :2] + 1) / 2
    assert np.abs(frame.uv - expected_uv)[inner].max() < 2e-3
    assert np.ptp(frame.uv[inner][:, 0]) > 0.5 and np.ptp(frame.uv[inner][:, 1]) > 0.5


def test_mesh_without_uvs_gives_zero_uv(renderer):
    frame = renderer(SIZE, SIZE).render(_scene(sphere_mesh(2)),
                                        Camera.look_at((0, 0, 4), (0, 0, 0)), outputs=("uv",))
    assert frame.color is None and frame.depth is None
    assert np.all(frame.uv == 0)


def test_camera_description_reprojects_positions(renderer):
    """The JSON camera (K and OpenCV world->camera) maps rendered world positions back to
    their own pixel centres."""
    camera = Camera.look_at((2, 1, 3), (0, 0, 0), fov_y=50, near=0.5, far=20)
    w, h = 80, 60
    frame = renderer(w, h).render(_scene(sphere_mesh(4)), camera, outputs=("ids", "position"))
    info = json.loads(json.dumps(frame.camera_info()))
    assert info["width"] == w and info["height"] == h and info["model"] == "perspective"
    K, E = np.array(info["K"]), np.array(info["world_to_camera"])
    hit = frame.object_ids == 0
    rows, cols = np.nonzero(hit)
    pw = frame.position[hit]
    pc = pw @ E[:3, :3].T + E[:3, 3]
    uv = pc @ K.T
    u, v = uv[:, 0] / uv[:, 2], uv[:, 1] / uv[:, 2]
    assert np.abs(u - cols).max() < 1e-2 and np.abs(v - rows).max() < 1e-2
    assert np.all(pc[:, 2] > 0)  # OpenCV: in front of the camera is +z
