"""Tier 2: linear depth, object ids (exact, never blended) and OpenCV intrinsics."""

import numpy as np
import pytest

from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Material, Scene

from conftest import quad_mesh, sphere_mesh
from reference import erode, linear_depth, pixel_rays, sphere_reference

SIZE = 64


def _scene(*meshes_and_transforms):
    scene = Scene()
    for mesh, m in meshes_and_transforms:
        scene.add(mesh, Material(), transform=m)
    scene.add_light(DirectionalLight((0, 0, -1)))
    return scene


@pytest.mark.parametrize("ortho", [False, True])
def test_plane_depth_is_linear(renderer, ortho):
    """A tilted plane: depth along the camera axis, exact to 1e-3 relative, both projections."""
    plane = T.compose(T.rotate_x(-60), T.translate((0, 0, -1)))
    scene = _scene((quad_mesh(5.0), plane))
    camera = Camera.look_at((0, 0.5, 4), (0, 0, 0), fov_y=50, ortho_height=3 if ortho else None,
                            near=0.5, far=30)
    frame = renderer(SIZE, SIZE).render(scene, camera)
    origins, dirs = pixel_rays(camera.view, camera.projection(SIZE, SIZE), SIZE, SIZE)
    # Ray-plane intersection with the transformed plane (point q, normal n, world space).
    q = plane[:3, 3]
    n = T.normal_matrix(plane) @ [0, 0, 1]
    t = np.sum((q - origins) * n, -1) / np.sum(dirs * n, -1)
    expected = linear_depth(camera.view, origins + t[..., None] * dirs)
    hit = erode(frame.object_ids == 0, 1)
    assert hit.sum() > 0.3 * SIZE * SIZE
    rel = np.abs(frame.depth - expected)[hit] / expected[hit]
    assert rel.max() < 1e-3
    assert np.all(frame.depth[frame.object_ids == -1] == 0)
    assert np.ptp(expected[hit]) > 0.5  # the plane really is tilted in depth


@pytest.mark.parametrize("ortho", [False, True])
def test_sphere_depth(renderer, ortho):
    camera = Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=35, ortho_height=2.4 if ortho else None,
                            near=1, far=20)
    scene = _scene((sphere_mesh(), np.eye(4)))
    frame = renderer(SIZE, SIZE).render(scene, camera)
    _, mask, depth = sphere_reference(camera, SIZE, SIZE, (0, 0, 0), 1.0, Material(), [], 0)
    inner = erode(mask, 2)
    rel = np.abs(frame.depth - depth)[inner] / depth[inner]
    assert rel.max() < 1e-3
    assert frame.depth.dtype == np.float32


def test_ids_exact_and_unblended_with_msaa(renderer):
    """Two overlapping objects: ids are exactly {-1, 0, 1}, equal with and without MSAA, and
    depth too, while the MSAA colour does blend at the edges."""
    scene = _scene((sphere_mesh(4, 0.8), T.translate((-0.5, 0, 0))),
                   (sphere_mesh(4, 0.8), T.translate((0.5, 0, -0.5))))
    camera = Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=40, near=1, far=20)
    plain = renderer(SIZE, SIZE, 0).render(scene, camera)
    msaa = renderer(SIZE, SIZE, 4).render(scene, camera)
    assert set(np.unique(plain.object_ids)) == {-1, 0, 1}
    assert np.array_equal(plain.object_ids, msaa.object_ids)
    assert np.array_equal(plain.depth, msaa.depth)
    # Object 0 is nearer, so it covers the overlap.
    assert plain.object_ids[SIZE // 2, SIZE // 2 - 2] == 0
    colours_plain = {tuple(c) for c in plain.color.reshape(-1, 4)}
    colours_msaa = {tuple(c) for c in msaa.color.reshape(-1, 4)}
    assert len(colours_msaa - colours_plain) > 20  # edge pixels averaged by MSAA


def test_intrinsics_reprojection(renderer):
    """Vertices projected with OpenCV's pinhole model land on the rendered pixels."""
    w, h = 80, 60
    fx, fy, cx, cy = 70.0, 65.0, 41.3, 27.8
    pose = np.eye(4)  # camera at the origin, OpenCV axes: looking down +z, y down
    pose[:3, 3] = (0.1, -0.2, 0.0)
    camera = Camera.from_intrinsics(fx, fy, cx, cy, w, h, pose=pose, near=0.1, far=50)
    # A 4 x 3 grid of points at varied depths, with off-grid sub-pixel positions.
    gx, gy = np.meshgrid(np.linspace(-0.9, 0.9, 4), np.linspace(-0.6, 0.6, 3))
    z = np.linspace(3.0, 6.0, gx.size)
    pts_cv = np.column_stack([gx.ravel() * z / 4 + 0.013, gy.ravel() * z / 4 - 0.021, z])
    world = (np.column_stack([pts_cv, np.ones(len(z))]) @ pose.T)[:, :3]
    scene = Scene()
    marker = sphere_mesh(3, 1.0)
    for p, depth in zip(world, z, strict=True):  # a marker about 2 px in radius at each point
        scene.add(marker, Material(), transform=T.compose(T.scale(2.0 * depth / fx),
                                                          T.translate(p)))
    scene.add_light(DirectionalLight((0, 0, 1)))
    frame = renderer(w, h).render(scene, camera)
    u = fx * pts_cv[:, 0] / pts_cv[:, 2] + cx
    v = fy * pts_cv[:, 1] / pts_cv[:, 2] + cy
    rows, cols = np.mgrid[0:h, 0:w]
    for i in range(len(world)):
        assert frame.object_ids[int(round(v[i])), int(round(u[i]))] == i, (i, u[i], v[i])
        mask = frame.object_ids == i
        centroid = cols[mask].mean(), rows[mask].mean()
        assert abs(centroid[0] - u[i]) < 0.35 and abs(centroid[1] - v[i]) < 0.35
    # Projection matrix agrees with the pinhole model to 1e-3 px.
    clip = np.column_stack([world, np.ones(len(world))]) @ (
        camera.projection(w, h) @ camera.view).T
    ndc = clip[:, :3] / clip[:, 3:]
    u_gl = (ndc[:, 0] + 1) * w / 2 - 0.5
    v_gl = (1 - ndc[:, 1]) * h / 2 - 0.5
    assert np.abs(u_gl - u).max() < 1e-3 and np.abs(v_gl - v).max() < 1e-3


def test_transparent_background(renderer):
    scene = Scene(background=(0.2, 0.4, 0.6, 0.0))
    scene.add(sphere_mesh(3, 0.5), Material())
    scene.add_light(DirectionalLight((0, 0, -1)))
    frame = renderer(SIZE, SIZE).render(scene, Camera.look_at((0, 0, 4), (0, 0, 0)))
    bg = frame.object_ids == -1
    assert np.all(frame.color[bg][:, 3] == 0)
    assert np.all(np.abs(frame.color[bg][:, :3].astype(int) - [51, 102, 153]) <= 1)
    assert np.all(frame.color[~bg][:, 3] == 255)


@pytest.mark.parametrize("msaa", [0, 4])
def test_sky_and_wireframe_leave_the_exact_channels_alone(renderer, msaa):
    """The environment background and the wireframe overlay draw colour only: depth, ids
    and normals are those of the plain scene, byte for byte (GL leaves an attachment a
    shader does not write undefined; they are masked)."""
    from facet.scene.environment import Environment

    scene = _scene((sphere_mesh(4), T.translate((-0.6, 0, 0))),
                   (sphere_mesh(4), T.translate((0.8, 0.2, -1))))
    camera = Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=50)
    outputs = ("color", "depth", "ids", "normals")
    r = renderer(SIZE, SIZE, msaa)
    plain = r.render(scene, camera, outputs=outputs)
    scene.environment = Environment.sky(size=32)
    for _ in range(3):  # undefined values would show on some frame, not always the first
        dressed = r.render(scene, camera, outputs=outputs, wireframe=True)
        assert np.abs(dressed.color.astype(int) - plain.color).max() > 50  # sky and lines
        for name in ("depth", "object_ids", "normals"):
            assert np.array_equal(getattr(dressed, name), getattr(plain, name)), name
