"""Automatic back-face culling (facet.render.raster.culling) never changes a picture: closed meshes
seen from outside render pixel for pixel the same culled and unculled, with and without
MSAA; open meshes, a camera inside a closed mesh, transparent and mirrored objects keep
their back faces; and the decision itself is what the module says."""

import numpy as np
import pytest
import trimesh

from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.render.raster.culling import Culling
from facet.scene import DirectionalLight, Material, Mesh, Scene, primitives

from conftest import shared_model

SIZE = 96
OUTSIDE = Camera.look_at((2.2, 1.6, 3.0), (0, 0, 0), fov_y=40, near=0.5, far=20)


def _scene(*meshes, material=None):
    scene = Scene(ambient=0.15)
    for i, mesh in enumerate(meshes):
        scene.add(mesh, material or Material(color=(0.8, 0.5, 0.3), ks=0.4, shininess=30),
                  T.translate((1.1 * i - 0.5 * (len(meshes) - 1), 0, 0)))
    scene.add_light(DirectionalLight((-0.5, -0.8, -0.6)))
    return scene


def _same(renderer, scene, camera, msaa, **kw):
    r = renderer(SIZE, SIZE, msaa)
    outputs = ("color", "depth", "ids", "normals")
    auto = r.render(scene, camera, outputs=outputs, cull="auto", **kw)
    off = r.render(scene, camera, outputs=outputs, cull="off", **kw)
    for name in ("color", "depth", "object_ids", "normals"):
        np.testing.assert_array_equal(getattr(auto, name), getattr(off, name), err_msg=name)
    return auto


@pytest.mark.parametrize("msaa", [0, 4])
def test_closed_meshes_render_the_same_culled(renderer, msaa):
    meshes = [primitives.sphere(0.5), primitives.cube(0.8), primitives.torus(0.45, 0.15)]
    scene = _scene(*meshes)
    culling = Culling()
    assert all(culling.cull(o, "auto", OUTSIDE.view, OUTSIDE.near) for o in scene.objects)
    frame = _same(renderer, scene, OUTSIDE, msaa)
    assert (frame.object_ids >= 0).mean() > 0.2


@pytest.mark.parametrize("name", ["spot.obj", "cow.obj", "homer.obj", "rocker-arm.obj"])
@pytest.mark.parametrize("msaa", [0, 4])
def test_real_closed_meshes_render_the_same_culled(renderer, name, msaa):
    """Real closed meshes: the same pictures, except at a few silhouette pixels where a
    front face seen exactly edge-on has no area and the back face behind it covered the
    pixel centre (or an MSAA sample) in the unculled picture: a sliver of back face that
    culling removes. Everywhere else every channel is equal."""
    mesh = Mesh.load(shared_model(name))
    assert mesh.closed
    scene = _scene(mesh)
    camera = Camera.frame(scene.bounds, aspect=1.0)
    r = renderer(128, 128, msaa)
    outputs = ("color", "depth", "ids", "normals")
    auto = r.render(scene, camera, outputs=outputs, cull="auto", shading="blinn",
                    shadows=True)
    off = r.render(scene, camera, outputs=outputs, cull="off", shading="blinn", shadows=True)
    differ = np.zeros((128, 128), bool)
    for channel in ("color", "depth", "object_ids", "normals"):
        a, b = getattr(auto, channel), getattr(off, channel)
        differ |= (a != b).reshape(128, 128, -1).any(axis=-1)
    ids = np.pad(auto.object_ids, 1, constant_values=-1)
    window = np.stack([ids[1 + dy:129 + dy, 1 + dx:129 + dx] for dy in (-1, 0, 1)
                       for dx in (-1, 0, 1)])
    silhouette = (window != window[4]).any(axis=0)
    assert not (differ & ~silhouette).any()
    assert differ.sum() <= 0.001 * differ.size + 2


def test_open_meshes_and_cameras_inside_keep_their_back_faces(renderer):
    """A tube without caps seen into its opening, and a camera inside a closed sphere: the
    inside shows (auto = off), where culling every back face would lose it."""
    tube = trimesh.creation.cylinder(radius=0.5, height=1.0, sections=48)
    keep = np.abs(tube.face_normals[:, 1]) < 0.5  # drop the caps: an open tube
    tube = Mesh(np.asarray(tube.vertices), np.asarray(tube.faces)[keep])
    assert not tube.closed
    into = Camera.look_at((0.2, 2.0, 0.4), (0, 0, 0), fov_y=40, near=0.1, far=10)
    inside = Camera.look_at((0, 0, 0), (0, 0, -1), fov_y=60, near=0.05, far=10)
    r = renderer(SIZE, SIZE, 0)
    for scene, camera in ((_scene(tube), into), (_scene(primitives.sphere(1.0)), inside)):
        auto = _same(renderer, scene, camera, 0)
        forced = r.render(scene, camera, outputs=("color", "ids"), cull="on")
        assert (auto.object_ids >= 0).sum() > (forced.object_ids >= 0).sum() + 50


def test_what_keeps_both_faces():
    culling = Culling()
    sphere = primitives.sphere(0.5)
    cases = {
        "transparent": (Material(opacity=0.5), np.eye(4), OUTSIDE),
        "near plane cuts it": (Material(), np.eye(4),
                               Camera.look_at((0, 0, 0.9), (0, 0, -1), near=0.5, far=9)),
    }
    for name, (material, transform, camera) in cases.items():
        scene = Scene()
        scene.add(sphere, material, transform)
        obj = scene.objects[0]
        assert not culling.cull(obj, "auto", camera.view, camera.near), name
        assert not culling.cull(obj, "off", camera.view, camera.near), name
    scene = Scene()
    scene.add(sphere)
    scene.add(sphere, transform=T.scale((-1, 1, 1)))  # mirrored: culled by its own winding
    for obj in scene.objects:
        assert culling.cull(obj, "auto", OUTSIDE.view, OUTSIDE.near)
    assert not culling.cull(scene.objects[0], "off", OUTSIDE.view, OUTSIDE.near)


def test_closed_meshes_are_recognised():
    ico = trimesh.creation.icosphere(subdivisions=3)
    closed = Mesh(np.asarray(ico.vertices), np.asarray(ico.faces))
    assert closed.closed
    flipped = np.asarray(ico.faces).copy()
    flipped[7] = flipped[7][::-1]  # one triangle wound the wrong way
    assert not Mesh(closed.positions, flipped).closed
    assert not Mesh(closed.positions, np.asarray(ico.faces)[1:]).closed  # a hole
    # Texture seams split vertices without opening the surface.
    assert primitives.sphere(1.0).closed and primitives.torus(1.0, 0.3).closed
    assert not primitives.plane(1.0).closed
