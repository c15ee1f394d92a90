"""What the differential harness (tests/test_differential.py) caught in the tracers' surfaces,
each as a test of its own against the rasterizer:

* vertex colours (glTF's COLOR_0 is linear) are blended in linear light across a triangle,
  not blended encoded and decoded after;
* the exact channels see the nearest opaque surface: a BLEND material is transparent
  whatever its factor's alpha, a MASK cut-out is cut in every shading model;
* a minified texture is read at the mip level of the pixel's ray cone (filtered as the
  rasterizer's mipmaps filter it), not point-sampled into noise.
"""

from __future__ import annotations

import numpy as np
import pytest

import facet
from facet.scene import primitives

CAM = facet.Camera.look_at((0, 0, 3), (0, 0, 0), fov_y=40)


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_vertex_colours_blend_in_linear_light(renderer, engine):
    """A triangle whose corners are red, green and blue, unlit metallic-roughness: its
    centre is the linear mean of the three (1/3 each, linear) in the tracers as in the
    rasterizer (within 2/255). (Old code: the tracers blended the encoded colours and
    decoded the mean: 0.09 each instead of 0.33.)"""
    mesh = facet.Mesh([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], [[0, 1, 2]],
                      colors=[[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])
    scene = facet.Scene(ambient=0.0)
    scene.add(mesh, facet.PbrMaterial(unlit=True))
    r = renderer(33, 33)
    opts = dict(aa="none", float_color=True, outputs=("color",))
    raster = r.render(scene, CAM, **opts).color
    traced = r.render(scene, CAM, engine=engine, **opts).color
    row, col = 16 + 3, 16  # the centroid (0, -1/3) lies a few pixels below the centre
    assert np.abs(raster[row, col, :3] - 1 / 3).max() < 0.1  # near the centroid: linear
    assert np.abs(raster[row, col, :3] - traced[row, col, :3]).max() <= 2 / 255


def _front_and_back(front_material):
    T = facet.transforms
    scene = facet.Scene()
    scene.add(primitives.plane(2.0), facet.Material(color=(0.2, 0.4, 0.8)),
              T.compose(T.rotate_x(90), T.translate((0, 0, -0.5))))
    scene.add(primitives.plane(2.0), front_material, T.rotate_x(90))
    return scene


@pytest.mark.parametrize("engine", ["trace", "path"])
@pytest.mark.parametrize("case", ["blend", "mask unlit"])
def test_the_exact_channels_see_the_nearest_opaque_surface(renderer, engine, case):
    """A BLEND quad (its factor's alpha 1) before an opaque one: every engine's ids show
    the opaque one, as the rasterizer's transparent pass leaves BLEND out of the exact
    channels; a MASK quad whose image cuts its left half, drawn with shading = "unlit":
    the tracers cut it as the rasterizer does. (Old code: the tracers took a BLEND
    material of alpha 1 for opaque, and read cut-outs only under the metallic-roughness
    shading.)"""
    if case == "blend":
        material = facet.PbrMaterial(alpha_mode="BLEND")
        opts = {}
    else:
        pixels = np.full((4, 4, 4), 255, np.uint8)
        pixels[:, :2, 3] = 0
        material = facet.PbrMaterial(alpha_mode="MASK", base_color_texture=facet.TextureSlot(
            facet.Texture(pixels), filter=("nearest", "nearest")))
        opts = {"shading": "unlit"}
    scene = _front_and_back(material)
    r = renderer(32, 32)
    ids = {e: r.render(scene, CAM, engine=e, aa="none", outputs=("ids",), **opts).object_ids
           for e in ("raster", engine)}
    assert (ids["raster"] == 0).sum() > 100  # the opaque one shows
    assert (ids["raster"] != ids[engine]).mean() < 0.02


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_a_minified_texture_is_filtered_not_aliased(renderer, engine):
    """A floor of 256 x 256 black and white squares seen at a grazing angle, one ray per
    pixel: far away its squares are smaller than a pixel, and the tracers read the mip
    level of the pixel's cone, as grey as the rasterizer's mipmaps (the far rows' standard
    deviation within 0.05 of the rasterizer's, not the 0.3 of point-sampled noise). (Old
    code: level 0, salt and pepper.)"""
    pixels = np.zeros((512, 512, 3), np.uint8)
    y, x = np.mgrid[:512, :512]
    pixels[((x // 2) + (y // 2)) % 2 == 0] = 255
    floor = facet.PbrMaterial(metallic=0.0, roughness=1.0, unlit=True,
                              base_color_texture=facet.TextureSlot(facet.Texture(pixels)))
    scene = facet.Scene()
    scene.add(primitives.plane(20.0), floor)
    cam = facet.Camera.look_at((0, 1.0, 6), (0, 0, -4), fov_y=40)
    r = renderer(48, 48)
    opts = dict(aa="none", float_color=True, outputs=("color",))
    far = slice(18, 26)  # rows of the floor's far part
    raster = r.render(scene, cam, **opts).color[far, :, 0]
    traced = r.render(scene, cam, engine=engine, **opts).color[far, :, 0]
    assert traced.std() <= raster.std() + 0.05, (traced.std(), raster.std())


def test_texture_layers_are_converted_once_and_read_back_as_uploaded(renderer):
    """The tracers' texture array keeps each converted layer while it is requested: a
    request set that loses one image converts none again (the feature harness strips one
    texture at a time), and the array read back from GL is the same either way (colour
    layers decoded to linear float16, data layers as bytes / 255, rows flipped)."""
    from facet.image.colorspace import srgb_to_linear
    from facet.render.rays import layers, pack
    from facet.scene.texture import Texture

    rng = np.random.default_rng(3)
    a, b = (Texture(rng.integers(0, 256, (16, 16, 4), dtype=np.uint8)) for _ in range(2))
    ctx = renderer(8, 8).ctx
    cache: dict = {}
    with ctx:
        first = layers.texture_array(ctx, [(a, pack.LINEAR), (b, pack.DATA)], False, cache)
        kept = {k: v[1] for k, v in cache.items()}
        second = layers.texture_array(ctx, [(b, pack.DATA)], False, cache)
        assert [v[1] for v in cache.values()] == [kept[k] for k in cache]  # the same arrays
        got = np.frombuffer(first.read(), np.float16).reshape(2, 16, 16, 4)[:, ::-1]
        assert np.allclose(got[0, ..., :3], srgb_to_linear(a.pixels[..., :3] / 255.0),
                           atol=1e-3)
        assert np.allclose(got[1], b.pixels / 255.0, atol=1e-3)
        assert np.array_equal(np.frombuffer(second.read(), np.uint8).reshape(16, 16, 4),
                              b.pixels[::-1])
        first.release()
        second.release()
