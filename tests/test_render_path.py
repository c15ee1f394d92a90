"""The one render path over real EGL: a call never changes what the next one sees, a scene
without lights gets the default rig from every front, the options a scene carries apply
from Python too, and colour finishing matches the equations of facet.image.colorspace."""

import numpy as np
import pytest

from facet.formats import load_scene
from facet.geometry.camera import Camera
from facet.image.colorspace import linear_to_srgb, srgb_to_linear
from facet.render.renderer import Renderer
from facet.scene import DirectionalLight, Material, Scene, primitives
from facet.scene.light import camera_rig

from conftest import sphere_mesh
from reference import erode, sphere_reference

S = 48
CAMERA = Camera.look_at((0, 0.4, 4), (0, 0, 0), fov_y=40, near=1, far=10)


def _ball_scene(**kwargs):
    scene = Scene(**kwargs)
    scene.add(sphere_mesh(4), Material(color=(0.9, 0.5, 0.2)))
    scene.add(primitives.plane(4), Material(color=(0.8, 0.8, 0.8)),
              np.array([[1, 0, 0, 0], [0, 1, 0, -1], [0, 0, 1, 0], [0, 0, 0, 1]], float))
    return scene


def test_a_render_call_changes_nothing_for_the_next(renderer):
    """msaa / aa / shadows / shading / srgb / background given to one call do not leak into
    the next: the plain call afterwards equals the plain call of a fresh renderer."""
    scene = _ball_scene()
    scene.add_light(DirectionalLight((-0.4, -1, -0.5)))
    with Renderer(S, S, msaa=0) as fresh:
        expected = fresh.render(scene, CAMERA)
    r = renderer(S, S)
    for kwargs in (dict(aa="msaa:4"), dict(aa="ssaa:jittered:4"), dict(shadows=True),
                   dict(shading="flat"), dict(srgb=True), dict(background=(1, 1, 1, 0)),
                   dict(outputs=("color", "normals")), dict(wireframe=True)):
        changed = r.render(scene, CAMERA, **kwargs)
        if "outputs" in kwargs:
            assert changed.normals is not None
        else:
            assert not np.array_equal(changed.color, expected.color), kwargs  # it did change
        after = r.render(scene, CAMERA)
        assert np.array_equal(after.color, expected.color), kwargs
        assert np.array_equal(after.object_ids, expected.object_ids), kwargs
        assert after.normals is None


def test_a_scene_without_lights_gets_the_camera_rig_from_python(renderer):
    """Python, like `facet render`, lights a lightless scene with the key + fill rig placed
    from the camera; lights="scene" opts out (only ambient is left)."""
    r = renderer(S, S)
    plain = _ball_scene()
    rigged = _ball_scene()
    for light in camera_rig(CAMERA.view):
        rigged.add_light(light)
    default = r.render(plain, CAMERA).color
    assert np.array_equal(default, r.render(rigged, CAMERA).color)
    dark = r.render(plain, CAMERA, lights="scene").color
    ambient_only = r.render(_ball_scene(options={"lights": "scene"}), CAMERA).color
    assert np.array_equal(dark, ambient_only)
    ball = r.render(plain, CAMERA).object_ids == 0
    assert default[..., :3][ball].mean() > 2.5 * dark[..., :3][ball].mean()
    # The exact value where the ball faces the camera: ambient 0.1 * C only.
    centre = dark[S // 2, S // 2, :3] / 255
    assert np.allclose(centre, 0.1 * np.array([0.9, 0.5, 0.2]), atol=1 / 255)
    # "camera": the rig even when the scene has lights of its own.
    lit = _ball_scene()
    lit.add_light(DirectionalLight((1, 0, 0)))
    assert np.array_equal(r.render(lit, CAMERA, lights="camera").color, default)


def test_load_scene_without_lights_renders_lit(tmp_path, renderer):
    path = tmp_path / "s.toml"
    path.write_text('[[objects]]\nprimitive = "sphere"\n[cameras.c]\ntype = "perspective"\n'
                    "eye = [0, 0.4, 4]\ntarget = [0, 0, 0]\n")
    scene = load_scene(path)
    assert scene.lights == []
    frame = renderer(S, S).render(scene)  # the scene's camera, the default lights
    lit = frame.color[..., :3][frame.object_ids == 0]
    assert lit.mean() > 100


def test_the_scene_options_apply_from_python(tmp_path):
    """A Renderer with no size renders at the scene file's size, with its settings, through
    its camera; explicit keywords win."""
    path = tmp_path / "s.toml"
    path.write_text('[render]\nsize = [40, 30]\nshading = "normals"\nmsaa = 0\n'
                    '[[objects]]\nprimitive = "sphere"\n[cameras.c]\ntype = "perspective"\n'
                    "eye = [0, 0, 4]\ntarget = [0, 0, 0]\n")
    scene = load_scene(path)
    with Renderer() as r:
        frame = r.render(scene)
        assert frame.color.shape == (30, 40, 4)
        # normals shading: the centre faces the camera, n ~ (0, 0, 1) -> (0.5, 0.5, 1) (the
        # primitive's facets tilt its interpolated normals a little)
        assert np.allclose(frame.color[15, 20, :3], [128, 128, 255], atol=10)
        assert r.render(scene, size=(20, 10)).color.shape == (10, 20, 4)
        phong = r.render(scene, shading="phong", lights="scene").color
        assert not np.allclose(phong[15, 20, :3], [128, 128, 255], atol=30)


@pytest.mark.parametrize("aa", ["none", "msaa:4", "ssaa:grid:4"])
def test_colour_finishing_matches_the_equations(renderer, aa):
    """sRGB encoding and straight alpha, done by the finishing pass on the GPU, against
    numpy: an exact sphere under one light, interior pixels within 2/255. Float colour is
    linear light (the rule for every engine: encoding is for 8-bit output); 8-bit colour is
    encoded."""
    scene = Scene(ambient=0.1, background=(0.2, 0.4, 0.6, 0.0))
    material = Material(color=(0.8, 0.3, 0.2))
    scene.add(sphere_mesh(6), material)
    light = DirectionalLight((-0.3, -0.4, -1.0))
    scene.add_light(light)
    r = renderer(S, S)
    frame = r.render(scene, CAMERA, aa=aa, srgb=True, float_color=True)
    eight = r.render(scene, CAMERA, aa=aa, srgb=True).color
    # sRGB mode: the inputs are sRGB-encoded; the equation runs on their linear values.
    linear = Material(color=srgb_to_linear(material.color))
    ref, mask, _ = sphere_reference(CAMERA, S, S, (0, 0, 0), 1.0, linear, [light],
                                    srgb_to_linear(0.1))
    inner = erode(mask, 2)
    assert np.abs(frame.color[..., :3] - ref)[inner].max() <= 2 / 255
    assert np.abs(eight[..., :3] / 255 - linear_to_srgb(ref))[inner].max() <= 2.5 / 255
    assert np.all(frame.color[..., 3][inner] == 1.0)
    empty = ~erode(~mask, 2)
    # Nothing covers these: alpha 0 and the background's own (straight) colour.
    assert np.all(frame.color[..., 3][~empty] == 0)
    # (the background's colour is sRGB-encoded input: linear in float colour, as given in
    # 8-bit colour)
    assert np.allclose(frame.color[..., :3][~empty], srgb_to_linear([0.2, 0.4, 0.6]),
                       atol=2 / 255)
    assert np.allclose(eight[..., :3][~empty] / 255, [0.2, 0.4, 0.6], atol=2 / 255)
