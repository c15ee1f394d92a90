"""Grey material-light terms (facet.render.raster.variant.grey_terms): the program that reads one
channel of each product (formed from the material record in glsl/lib/lights.glsl) gives the
very picture of the one that reads three."""

import numpy as np
import pytest

import facet.render.raster.draws as draws
import facet.render.raster.variant as variant
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.render.renderer import Renderer
from facet.scene import DirectionalLight, Material, PointLight, Scene

from conftest import quad_mesh, sphere_mesh

CAMERA = Camera.look_at((1.5, 1, 4), (0, 0, 0), fov_y=40, near=1, far=20)


def _scene(color=(0.6, 0.6, 0.6), light=(1.0, 1.0, 1.0)):
    scene = Scene()
    scene.add(sphere_mesh(), Material(color=color, shininess=20))
    scene.add(quad_mesh(4.0), Material(color=(0.3, 0.3, 0.3)), transform=T.translate((0, 0, -1)))
    scene.add_light(DirectionalLight((-0.3, -0.4, -1), color=light))
    scene.add_light(PointLight((2, 2, 3), color=light, intensity=0.7))
    return scene


def _render(scene, **options):
    with Renderer(64, 48) as r:
        frame = r.render(scene, CAMERA, **options)
        return frame.color, {v.grey for v in r._engines["raster"].forward.programs}


@pytest.mark.parametrize("shading", ["phong", "blinn", "flat", "gouraud"])
@pytest.mark.parametrize("options", [{"msaa": 0}, {"msaa": 4}, {"msaa": 0, "float_color": True}])
def test_grey_terms_give_the_same_picture(monkeypatch, shading, options):
    grey, used = _render(_scene(), shading=shading, **options)
    assert used == {True}  # the grey program drew
    monkeypatch.setattr(draws, "grey_terms", lambda terms: False)
    three, used = _render(_scene(), shading=shading, **options)
    assert used == {False}
    np.testing.assert_array_equal(grey, three)
    assert grey[..., :3].std() > 0.05  # a lit picture, not a blank one


def test_a_coloured_material_or_light_is_not_grey():
    assert _render(_scene(color=(0.6, 0.5, 0.6)))[1] == {False, True}  # the quad is grey
    assert _render(_scene(light=(1.0, 0.9, 0.8)))[1] == {False}
    terms = (None, np.array([0.1, 0.1, 0.1]), np.array([[0.5, 0.5, 0.5], [0.2, 0.2, 0.2]]),
             np.array([[0.3, 0.3, 0.3], [0.3, 0.3, 0.30001]]))
    assert not variant.grey_terms(terms)
