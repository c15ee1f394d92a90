"""Planar mirrors (the issue's bonus): the reflection of a sphere in a mirror floor lands
where the mirror image of the geometry projects, the mirror mixes it in by reflectivity,
nothing behind the mirror shows in it, and mistakes are reported."""

import numpy as np
import pytest

from facet.errors import InputError
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.scene import Material, Scene
from facet.scene.primitives import cube, plane, sphere

W, H = 96, 72
GREY, RED = np.array([0.5, 0.5, 0.5]), np.array([1.0, 0.1, 0.1])
CENTRE = (0.3, 0.7, -0.2)
CAMERAS = [Camera.look_at((0.4, 2.0, 4.0), (0, 0, 0), fov_y=45, near=0.5, far=20),
           Camera.look_at((0.4, 2.0, 4.0), (0, 0, 0), ortho_height=3.5, near=0.5, far=20)]


def _floor_scene(reflectivity=1.0):
    s = Scene(ambient=0.0, background=(0, 0, 0, 1))
    s.add(plane(8), Material(color=GREY, reflectivity=reflectivity, mirror=True))
    s.add(sphere(0.5), Material(color=RED), T.translate(CENTRE))
    return s


@pytest.mark.parametrize("camera", CAMERAS, ids=["perspective", "orthographic"])
def test_reflection_is_where_the_mirror_image_projects(renderer, camera):
    """In the floor, red appears exactly where a sphere mirrored in y = 0 would project
    (IoU >= 0.95 over the floor's pixels); an unlit reflectivity-1 mirror shows it as is."""
    r = renderer(W, H)
    frame = r.render(_floor_scene(), camera, shading="unlit", outputs=("color", "ids"))
    floor = frame.object_ids == 0
    seen = floor & (np.abs(frame.color[..., :3].astype(int) - RED * 255).max(axis=2) <= 2)
    twin = Scene(ambient=0.0)
    twin.add(sphere(0.5), Material(color=RED), T.compose(T.translate(CENTRE),
                                                         T.scale((1, -1, 1))))
    expected = floor & (r.render(twin, camera, shading="unlit", outputs=("ids",))
                        .object_ids == 0)
    assert expected.sum() > 100
    iou = (seen & expected).sum() / (seen | expected).sum()
    assert iou >= 0.95, iou
    # Elsewhere the floor mirrors the black background.
    assert frame.color[floor & ~expected & ~seen][:, :3].max() <= 2


def test_reflectivity_mixes_own_shading_and_reflection(renderer):
    camera = CAMERAS[0]
    frame = renderer(W, H).render(_floor_scene(0.4), camera, shading="unlit",
                                  outputs=("color", "ids"))
    floor = frame.object_ids == 0
    img = frame.color[..., :3].astype(float) / 255
    in_red = floor & (img[..., 0] > 0.5)
    assert in_red.sum() > 50
    assert np.abs(img[in_red] - (0.6 * GREY + 0.4 * RED)).max() <= 2 / 255
    plain = floor & (img[..., 0] < 0.4)
    assert np.abs(img[plain] - 0.6 * GREY).max() <= 2 / 255


def test_nothing_behind_the_mirror_is_reflected(renderer):
    """A green cube under the floor would appear above it in the mirrored view: the
    reflection pass discards what lies behind the mirror's plane."""
    s = _floor_scene()
    s.add(cube(0.8), Material(color=(0.1, 1.0, 0.1)), T.translate((-0.8, -1.0, 0.5)))
    img = renderer(W, H).render(s, CAMERAS[0], shading="unlit").color[..., :3].astype(int)
    assert not ((img[..., 1] > 100) & (img[..., 0] < 100)).any()
    s.objects[0].material = Material(color=GREY)  # no mirror: the sphere is all that shows
    assert (img[..., 0] > 200).sum() > (renderer(W, H).render(s, CAMERAS[0],
                                                             shading="unlit").color[..., 0]
                                        > 200).sum()


def test_mirror_reflections_are_consistent_across_aa_paths(renderer):
    """The reflection rides along with supersampling (same jitter per sample) and with the
    aux outputs drawn in the colour pass: the mirror region agrees with the plain render."""
    camera = CAMERAS[0]
    r = renderer(W, H)
    plain = r.render(_floor_scene(), camera, shading="unlit", outputs=("color", "normals"))
    ss = r.render(_floor_scene(), camera, shading="unlit", aa="ssaa:grid:4",
                  outputs=("color",))
    inner = np.abs(plain.color[..., :3].astype(int) - ss.color[..., :3]).max(axis=2)
    assert (inner > 40).mean() < 0.03  # only edges differ


def test_objects_with_their_own_shader_are_reflected(renderer):
    """A material with a user's GLSL (which declares no clip plane) shows in the mirror."""
    from facet.scene.shader import UserShader

    from conftest import ROOT

    s = _floor_scene()
    s.objects[1].material = Material(shader=UserShader(ROOT / "glsl/examples/normals.frag"))
    r = renderer(W, H)
    frame = r.render(s, CAMERAS[0], shading="unlit", outputs=("color", "ids"))
    floor = frame.object_ids == 0
    seen = floor & (frame.color[..., :3].max(axis=2) > 20)
    twin = Scene(ambient=0.0)
    twin.add(sphere(0.5), Material(color=RED), T.compose(T.translate(CENTRE),
                                                         T.scale((1, -1, 1))))
    expected = floor & (r.render(twin, CAMERAS[0], outputs=("ids",)).object_ids == 0)
    assert expected.sum() > 100
    iou = (seen & expected).sum() / (seen | expected).sum()
    assert iou >= 0.95, iou  # the reflection is there, where the mirror image projects


def test_mirror_mistakes():
    with pytest.raises(InputError, match="mirror material needs reflectivity > 0"):
        Material(mirror=True)
    with pytest.raises(InputError, match="mirror must be true or false"):
        Material(mirror="yes", reflectivity=1)
    s = Scene()
    s.add(sphere(0.5), Material(reflectivity=1, mirror=True), name="ball")
    from facet.render.renderer import Renderer

    with Renderer(16, 16) as r, pytest.raises(InputError, match="ball: a mirror must be flat"):
        r.render(s)


def test_mirror_in_a_scene_file(tmp_path):
    from facet.formats.scenefile import load_scene

    path = tmp_path / "m.toml"
    path.write_text('[[objects]]\nprimitive = "plane"\nsize = 4\n'
                    'material = {reflectivity = 0.8, mirror = true}\n')
    assert load_scene(path).objects[0].material.mirror
    path.write_text('[[objects]]\nprimitive = "plane"\nmaterial = {mirror = true}\n')
    with pytest.raises(InputError, match=r"objects\[0\]\.material\.mirror: a mirror needs"):
        load_scene(path)
