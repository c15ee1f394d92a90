"""KHR_materials_dispersion: a transmitting volume's index spread over the colours (red,
green, blue at ior -+ (ior - 1) 0.025 dispersion, the Khronos Sample Viewer's spread). A
glass ball over a black-and-white stripe pattern splits its edges into colour fringes in
the path tracer (one colour a path) and the rasterizer (red and blue read apart), none
without dispersion; a dispersive clear ball in a white furnace stays invisible (each
colour's paths keep their energy); the Whitted tracer says in one line that it refracts
at one index; the extension is read from glTF."""

import warnings

import numpy as np
import pytest

import facet
from facet.scene.pbr import PbrMaterial
from facet.scene.texture import Texture

from gltf_files import GltfBuilder, quad

CAM = facet.Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=35, near=0.5, far=20)


def _stripes(dispersion):
    """A glass ball (ior 1.5) before an unlit wall of vertical white stripes."""
    from facet.scene.pbr import TextureSlot

    scene = facet.Scene(ambient=1.0)
    stripes = np.zeros((64, 64, 3), np.uint8)
    stripes[:, ::8] = stripes[:, 1::8] = stripes[:, 2::8] = 255
    scene.add(facet.shapes.Plane((4.0, 4.0)), PbrMaterial(
        base_color=(1, 1, 1), metallic=0.0, specular=0.0, unlit=True,
        base_color_texture=TextureSlot(Texture(stripes))),
        facet.transforms.translate((0, 0, -1.5)) @ facet.transforms.rotate_x(90.0))
    scene.add(facet.shapes.Sphere(0.8), PbrMaterial(
        base_color=(1, 1, 1), metallic=0.0, roughness=0.0, transmission=1.0, thickness=1.6,
        ior=1.5, dispersion=dispersion))
    return scene


def _fringe(image):
    """How far red and blue part inside the ball (mean |R - B| over its disc)."""
    h, w = image.shape[:2]
    y, x = np.mgrid[:h, :w]
    disc = (x - w / 2 + 0.5) ** 2 + (y - h / 2 + 0.5) ** 2 < (0.3 * w) ** 2
    return float(np.abs(image[..., 0] - image[..., 2])[disc].mean())


@pytest.mark.parametrize("engine", ["raster", "path"])
def test_a_dispersive_ball_splits_the_colours(engine):
    def picture(dispersion):
        with facet.Renderer(64, 64) as r:
            return r.render(_stripes(dispersion), CAM, engine=engine,
                            spp=64 if engine == "path" else 4, float_color=True,
                            lights="scene", max_depth=6, seed=3).color[..., :3]

    plain, spread = _fringe(picture(0.0)), _fringe(picture(20.0))
    assert spread > 3 * plain + 0.02, (plain, spread)


def test_a_dispersive_clear_ball_in_a_white_furnace_is_invisible():
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.shapes.Sphere(0.8), PbrMaterial(
        base_color=(1, 1, 1), metallic=0.0, roughness=0.0, transmission=1.0, thickness=1.6,
        ior=1.5, dispersion=20.0))
    with facet.Renderer(32, 32) as r:
        image = r.render(scene, CAM, engine="path", spp=256, max_depth=12, float_color=True,
                         lights="scene", environment={"color": [1.0, 1.0, 1.0]}).color[..., :3]
    np.testing.assert_allclose(image[12:20, 12:20].reshape(-1, 3).mean(0), 1.0, atol=0.03)


def test_the_whitted_tracer_says_it_refracts_at_one_index():
    with facet.Renderer(16, 16) as r, pytest.warns(facet.FacetWarning,
                                                   match="KHR_materials_dispersion"):
        r.render(_stripes(20.0), CAM, engine="trace")


def test_dispersion_is_read_from_gltf(tmp_path):
    b = GltfBuilder()
    b.doc["extensionsUsed"] = ["KHR_materials_dispersion", "KHR_materials_transmission"]
    b.node(mesh=quad(b, b.material(extensions={
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_dispersion": {"dispersion": 0.5}})))
    path = b.write_gltf(tmp_path / "d.gltf")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = facet.load(path).objects[0].material
    assert m.dispersion == 0.5 and m.transmission == 1.0
