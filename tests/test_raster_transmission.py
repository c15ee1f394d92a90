"""The rasterizer's transmission (facet.render.raster.transmission: the Khronos Sample
Viewer's refraction of a picture of the scene behind): against the equations (thin and
smooth: (1 - F) base times what is behind; a slab: Beer-Lambert over its thickness), against
the path tracer where both are exact (a thin smooth pane at normal incidence), and the
roughness blurring what is seen through. Before it the rasterizer drew such materials
opaque: none of these saw the backdrop."""

import numpy as np
import pytest

import facet
from facet.geometry.camera import Camera
from facet.scene.mesh import Mesh
from facet.scene.pbr import PbrMaterial, TextureSlot
from facet.scene.texture import Texture

SIZE = 48
FRONT = Camera.look_at((0, 0, 3.2), (0, 0, 0), fov_y=40, near=0.5, far=10)


def _quad(size, z, name) -> Mesh:
    h = size / 2
    pos = [[-h, -h, z], [h, -h, z], [h, h, z], [-h, h, z]]
    return Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4,
                [[0, 0], [1, 0], [1, 1], [0, 1]], name=name)


def _stripes(n=64, period=8):
    x = np.arange(n)
    on = ((x // period) % 2).astype(float)
    img = np.zeros((n, n, 4))
    img[..., 0] = 0.2 + 0.6 * on[None, :]
    img[..., 1] = 0.5
    img[..., 2] = 0.8 - 0.6 * on[None, :]
    img[..., 3] = 1
    return Texture((img * 255).round().astype(np.uint8))


def _scene(glass: PbrMaterial, backdrop=None):
    """An unlit backdrop (its colour is what it shows) behind a pane of ``glass``, no
    light and a black sky: what the pane shows is what it lets through."""
    scene = facet.Scene(ambient=0.0)
    back = backdrop or PbrMaterial(base_color=(0.3, 0.6, 0.9, 1), unlit=True)
    scene.add(_quad(4.0, -1.0, "backdrop"), material=back)
    scene.add(_quad(1.2, 0.0, "pane"), material=glass)
    return scene


def _render(scene, engine="raster", **kw):
    with facet.Renderer(SIZE, SIZE) as r:
        return r.render(scene, FRONT, engine=engine, float_color=True, lights="scene",
                        **kw).color[..., :3]


CENTRE = (slice(20, 28), slice(20, 28))


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_a_thin_smooth_pane_passes_one_minus_fresnel_of_the_backdrop_tinted(engine):
    tint = np.array([0.9, 0.7, 0.5])
    glass = PbrMaterial(base_color=(*tint, 1), metallic=0.0, roughness=0.0, transmission=1.0)
    behind = np.array([0.3, 0.6, 0.9])
    seen = _render(_scene(glass), engine, aa="none")[CENTRE].reshape(-1, 3)
    # Facing the camera (N.V ~ 1 in the middle): F = 0.04, the black sky reflects nothing.
    np.testing.assert_allclose(seen, np.broadcast_to((1 - 0.04) * tint * behind, seen.shape),
                               rtol=0.01)


def test_a_slab_absorbs_by_beer_lambert_over_its_thickness():
    glass = PbrMaterial(base_color=(1, 1, 1, 1), metallic=0.0, roughness=0.0,
                        transmission=1.0, thickness=0.5, attenuation_color=(0.5, 0.8, 0.9),
                        attenuation_distance=0.25)
    behind = np.array([0.3, 0.6, 0.9])
    seen = _render(_scene(glass), aa="none")[CENTRE].reshape(-1, 3)
    # 0.5 / 0.25 attenuation distances: the attenuation colour squared.
    expected = (1 - 0.04) * np.array([0.5, 0.8, 0.9]) ** 2 * behind
    np.testing.assert_allclose(seen, np.broadcast_to(expected, seen.shape), rtol=0.01)


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_a_glass_block_absorbs_by_beer_lambert_in_the_tracers(engine):
    """The tracers measure the volume itself: a block 0.5 deep at normal incidence, two
    interfaces of (1 - F), the attenuation colour to the power 0.5 / 0.25 (the Whitted
    tracer drew transmitting materials opaque)."""
    glass = PbrMaterial(base_color=(1, 1, 1, 1), metallic=0.0, roughness=0.0,
                        transmission=1.0, thickness=0.5, attenuation_color=(0.5, 0.8, 0.9),
                        attenuation_distance=0.25)
    scene = facet.Scene(ambient=0.0)
    scene.add(_quad(4.0, -1.0, "backdrop"),
              material=PbrMaterial(base_color=(0.3, 0.6, 0.9, 1), unlit=True))
    scene.add(facet.shapes.Box((1.2, 1.2, 0.5)), material=glass)
    kw = dict(aa="none") if engine == "trace" else dict(spp=64)
    seen = _render(scene, engine, **kw)[CENTRE].reshape(-1, 3).mean(axis=0)
    expected = (1 - 0.04) ** 2 * np.array([0.5, 0.8, 0.9]) ** 2 * np.array([0.3, 0.6, 0.9])
    np.testing.assert_allclose(seen, expected, rtol=0.02)


def test_the_rasterizer_and_the_path_tracer_see_the_same_through_a_thin_pane():
    glass = PbrMaterial(base_color=(0.9, 0.8, 0.6, 1), metallic=0.0, roughness=0.0,
                        transmission=1.0)
    scene = _scene(glass, PbrMaterial(base_color=(1, 1, 1, 1), unlit=True,
                                      base_color_texture=TextureSlot(_stripes())))
    raster = _render(scene, aa="ssaa:jittered:16")  # both average over each pixel
    path = _render(scene, engine="path", spp=64)
    inside = (slice(17, 31), slice(17, 31))  # the pane's middle
    a, b = raster[inside], path[inside]
    assert np.abs(a.mean(axis=(0, 1)) - b.mean(axis=(0, 1))).max() < 0.01
    # column by column (the stripes run vertically), within the path tracer's noise
    np.testing.assert_allclose(a.mean(axis=0), b.mean(axis=0), atol=0.03)


def test_roughness_blurs_what_is_seen_through():
    backdrop = PbrMaterial(base_color=(1, 1, 1, 1), unlit=True,
                           base_color_texture=TextureSlot(_stripes()))
    contrast = []
    for roughness in (0.0, 0.6):
        glass = PbrMaterial(base_color=(1, 1, 1, 1), metallic=0.0, roughness=roughness,
                            transmission=1.0, thickness=0.1)
        seen = _render(_scene(glass, backdrop), aa="none")[CENTRE]
        contrast.append(seen[..., 0].std())
    assert contrast[0] > 0.1 and contrast[1] < 0.5 * contrast[0], contrast


@pytest.mark.parametrize("aa", ["none", "msaa:4", "ssaa:jittered:4"])
def test_no_warning_and_every_antialiasing_mode_sees_through(aa, recwarn):
    glass = PbrMaterial(base_color=(1, 1, 1, 1), metallic=0.0, roughness=0.0,
                        transmission=1.0)
    seen = _render(_scene(glass), aa=aa)[CENTRE].reshape(-1, 3)
    np.testing.assert_allclose(seen.mean(axis=0), 0.96 * np.array([0.3, 0.6, 0.9]), rtol=0.02)
    assert not [w for w in recwarn if "transmission" in str(w.message)]
