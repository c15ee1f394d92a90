"""Tier 2: the same surface in every format renders the same mask; real meshes render lit."""

import numpy as np
import pytest
import trimesh

from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Mesh, Scene
from facet.scene.light import camera_rig

from conftest import shared_model
from reference import erode, phong

SIZE = 96


@pytest.fixture(scope="module")
def ico_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("formats")
    ico = trimesh.creation.icosphere(subdivisions=2)
    paths = {}
    for ext in ("obj", "stl", "ply", "glb"):
        ico.export(d / f"ico.{ext}")
        paths[ext] = d / f"ico.{ext}"
    return paths


def test_formats_render_the_same_mask(renderer, ico_files):
    camera = Camera.look_at((1.5, 1.0, 3.0), (0, 0, 0), fov_y=45, near=0.5, far=10)
    masks = {}
    for ext, path in ico_files.items():
        scene = Scene()
        scene.add(Mesh.load(path))
        scene.add_light(DirectionalLight((-1, -1, -1)))
        frame = renderer(SIZE, SIZE).render(scene, camera)
        masks[ext] = frame.object_ids == 0
    assert masks["obj"].sum() > 0.2 * SIZE * SIZE
    for ext, mask in masks.items():
        assert np.array_equal(mask, masks["obj"]), ext


REAL = ["stanford-bunny.obj", "spot.obj", "teapot.obj", "suzanne.obj", "cow.obj",
        "fandisk.obj", "rocker-arm.obj", "homer.obj", "beetle.obj"]


@pytest.mark.parametrize("name", REAL)
def test_real_mesh_renders_lit(renderer, name):
    """Framed automatically, each model fills a good part of the image, touches no border,
    and every interior pixel is the shading equation (tests/reference.py) at that pixel's
    own surface point and normal, under the default light rig: lit as the notes say, not
    merely "not black"."""
    from facet.scene import Material

    scene = Scene()
    scene.add(Mesh.load(shared_model(name)))
    camera = Camera.frame(scene.bounds, aspect=1.0)
    for light in camera_rig(camera.view):
        scene.add_light(light)
    frame = renderer(128, 128).render(scene, camera, float_color=True, aa="none",
                                      outputs=("color", "ids", "normals", "position"))
    mask = frame.object_ids == 0
    assert 0.08 < mask.mean() < 0.95
    # Framing keeps the model inside the image: nothing touches the border.
    assert not (mask[0].any() or mask[-1].any() or mask[:, 0].any() or mask[:, -1].any())
    inner = erode(mask, 1)
    to_eye = camera.eye - frame.position
    to_eye /= np.linalg.norm(to_eye, axis=-1, keepdims=True)
    material = Material()
    expected = phong(frame.position, frame.normals, to_eye, material.color, material,
                     scene.lights, scene.ambient)
    err = np.abs(frame.color[..., :3] - expected).max(-1)[inner]
    assert np.percentile(err, 99.5) < 2 / 255 and err.max() < 0.05, err.max()
    grey = frame.color[..., :3].mean(axis=2)[inner]
    assert np.ptp(grey) > 0.2  # shaded across the model, from the rig's key and fill
