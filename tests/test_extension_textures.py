"""The KHR material extensions' texture slots (specular, specular colour, transmission,
thickness, clear coat, its roughness and normal, sheen colour and roughness): read from
glTF and scene files, and drawn by every engine. Against references: a specular texture
of alpha 0 leaves the Lambertian surface the equation gives; under direct light from one
light the path tracer's one bounce, the rasterizer and the Whitted tracer evaluate the same
textured BRDF; the Khronos samples that use them load without a warning."""

import warnings

import numpy as np
import pytest

import facet
from facet.errors import FacetWarning, MeshError
from facet.scene.light import DirectionalLight
from facet.scene.pbr import PbrMaterial, TextureSlot

from conftest import SHARED_GLTF, shared_model
from gltf_files import GltfBuilder, png, quad
from test_path_materials import FRONT, _direct, _image, _quad

LIGHT = (-0.3, -0.4, -1.0)


def _extension_material(**drop) -> PbrMaterial:
    """A dielectric under a clear coat and a sheen, every extension slot textured with a
    pattern of its own."""
    spec = _image(lambda x, y: np.stack([x, y, x, 0.2 + 0.8 * (x > 0.5)], -1))
    tint = _image(lambda x, y: np.stack([1 - 0.6 * y, 0.5 + 0.5 * x, 0.7 + 0 * x,
                                         np.ones_like(x)], -1))
    coat = _image(lambda x, y: np.stack([0.3 + 0.7 * (y > 0.5), 0.2 + 0.8 * x, 0 * x,
                                         np.ones_like(x)], -1))
    bumps = _image(lambda x, y: np.stack([0.5 + 0.35 * np.sin(7 * y), 0.5 + 0.3 * np.cos(6 * x),
                                          np.ones_like(x), np.ones_like(x)], -1))
    cloth = _image(lambda x, y: np.stack([0.2 + 0.8 * x, 0.9 - 0.5 * y, 0.5 + 0 * x,
                                          0.3 + 0.7 * y], -1))
    kw = dict(base_color=(0.5, 0.35, 0.25, 1), metallic=0.0, roughness=0.55, ior=1.7,
              specular_color=(1.5, 1.2, 1.0), clearcoat=0.9, clearcoat_roughness=0.6,
              sheen_color=(0.8, 0.7, 0.9), sheen_roughness=0.7, double_sided=True,
              specular_texture=TextureSlot(spec), specular_color_texture=TextureSlot(tint),
              clearcoat_texture=TextureSlot(coat),
              clearcoat_roughness_texture=TextureSlot(coat, texcoord=1),
              clearcoat_normal_texture=TextureSlot(bumps), clearcoat_normal_scale=0.8,
              sheen_color_texture=TextureSlot(cloth), sheen_roughness_texture=TextureSlot(cloth))
    for key in drop:
        kw.pop(key)
    return PbrMaterial(**kw)


def _lit(material, light=LIGHT):
    scene = facet.Scene(ambient=0.0)
    scene.add(_quad(), material=material)
    scene.add_light(DirectionalLight(direction=light, intensity=0.9))
    return scene


def _inside(picture):
    inside = picture.max(axis=-1) > 0
    inside[[0, -1], :] = inside[:, [0, -1]] = False
    return inside


def test_every_extension_texture_matches_the_rasterizer_under_direct_light():
    scene = _lit(_extension_material())
    path = _direct(scene, "path").color[..., :3]
    raster = _direct(scene, "raster").color[..., :3]
    inside = _inside(raster)
    assert inside.sum() > 900
    diff = np.abs(path[inside] - raster[inside])
    assert diff.mean() < 0.006 and np.percentile(diff, 99) < 0.03, (diff.mean(), diff.max())
    # (the Whitted tracer supersamples a glossy surface's reflection: both over each pixel)
    with facet.Renderer(48, 48) as r:
        kw = dict(float_color=True, aa="ssaa:jittered:16", lights="scene", shading="pbr")
        traced = r.render(scene, FRONT, engine="trace", **kw).color[..., :3]
        raster = r.render(scene, FRONT, engine="raster", **kw).color[..., :3]
    diff = np.abs(traced[inside] - raster[inside])
    assert diff.mean() < 0.006 and np.percentile(diff, 99) < 0.03, (diff.mean(), diff.max())


@pytest.mark.parametrize("slot", ["specular_texture", "specular_color_texture",
                                  "clearcoat_texture", "clearcoat_roughness_texture",
                                  "clearcoat_normal_texture", "sheen_color_texture",
                                  "sheen_roughness_texture"])
@pytest.mark.parametrize("engine", ["raster", "path"])
def test_each_extension_texture_changes_the_picture(engine, slot):
    """The comparison above can fail: each slot left out changes each engine's picture."""
    full = _direct(_lit(_extension_material()), engine).color[..., :3]
    without = _direct(_lit(_extension_material(**{slot: None})), engine).color[..., :3]
    assert np.abs(full - without).mean() > 1e-3


def test_a_specular_texture_of_alpha_zero_leaves_lambert():
    """KHR_materials_specular: where the specular texture's alpha is 0 the dielectric has no
    specular lobe, so the surface is Lambertian: base I (N.L) under a light of intensity I;
    where it is 1, the lobe is back (the picture differs)."""
    off = _image(lambda x, y: np.stack([x, x, x, 1.0 * (x > 0.5)], -1))
    base = np.array([0.6, 0.4, 0.2])
    mat = PbrMaterial(base_color=(*base, 1), metallic=0.0, roughness=0.3,
                      specular_texture=TextureSlot(off, wrap=("clamp", "clamp")))
    light = np.array([0.2, -0.1, -1.0])
    lambert = base * 0.9 * (-light / np.linalg.norm(light))[2]
    for engine in ("raster", "path"):
        color = _direct(_lit(mat, light=light), engine).color[..., :3]
        inside = _inside(color)
        left, right = inside.copy(), inside.copy()
        left[:, 24 - 4:] = False
        right[:, :24 + 4] = False
        np.testing.assert_allclose(color[left], np.broadcast_to(lambert, color[left].shape),
                                   rtol=0.01, err_msg=engine)
        assert np.abs(color[right] - lambert).max(axis=-1).mean() > 0.005, engine


def test_gltf_extension_textures_become_slots(tmp_path):
    b = GltfBuilder()
    image = np.full((2, 2, 4), 200, np.uint8)
    tex = b.texture(png(image))
    info = {"index": tex}
    mat = b.material(extensions={
        "KHR_materials_specular": {"specularTexture": info, "specularColorTexture": info},
        "KHR_materials_transmission": {"transmissionFactor": 1.0, "transmissionTexture": info},
        "KHR_materials_volume": {"thicknessFactor": 0.5, "thicknessTexture": info},
        "KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatTexture": info,
                                    "clearcoatRoughnessTexture": {"index": tex, "texCoord": 1},
                                    "clearcoatNormalTexture": {"index": tex, "scale": -0.5}},
        "KHR_materials_sheen": {"sheenColorTexture": info, "sheenRoughnessTexture": info}})
    quad(b, mat)
    b.node(mesh=0)
    b.doc["extensionsUsed"] = ["KHR_materials_specular", "KHR_materials_transmission",
                               "KHR_materials_volume", "KHR_materials_clearcoat",
                               "KHR_materials_sheen"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", FacetWarning)
        m = facet.open_scene(b.write_glb(tmp_path / "m.glb")).objects[0].material
    assert set(m.slots) == {"specular", "specular_color", "transmission", "thickness",
                            "clearcoat", "clearcoat_roughness", "clearcoat_normal",
                            "sheen_color", "sheen_roughness"}
    assert m.clearcoat_roughness_texture.texcoord == 1 and m.clearcoat_normal_scale == 0.5
    assert m.specular_texture.texture is m.sheen_color_texture.texture  # decoded once


@pytest.mark.parametrize("info, message", [
    ({"index": 7}, "index"),
    ({"index": "0"}, "index"),
    ({"index": 0, "texCoord": -1}, "texCoord"),
    ([0], "expected an object"),
])
def test_a_bad_extension_texture_is_one_error(tmp_path, info, message):
    b = GltfBuilder()
    b.texture(png(np.zeros((2, 2, 4), np.uint8)))
    mat = b.material(extensions={"KHR_materials_clearcoat": {"clearcoatTexture": info}})
    quad(b, mat)
    b.node(mesh=0)
    b.doc["extensionsUsed"] = ["KHR_materials_clearcoat"]
    with pytest.raises(MeshError, match=f"KHR_materials_clearcoat.clearcoatTexture.*{message}"):
        facet.open_scene(b.write_glb(tmp_path / "bad.glb"))


def test_scene_files_take_the_extension_slots(tmp_path):
    from PIL import Image

    Image.fromarray(np.full((4, 4, 4), 128, np.uint8)).save(tmp_path / "coat.png")
    (tmp_path / "s.toml").write_text(
        '[materials.coat]\nbase_color = [0.5, 0.5, 0.5]\nclearcoat = 1.0\n'
        'clearcoat_texture = "coat.png"\nclearcoat_normal_scale = 0.5\n'
        'sheen_color_texture = {image = "coat.png", texcoord = 1}\n'
        '[[objects]]\nprimitive = "sphere"\nmaterial = "coat"\n')
    m = facet.open_scene(tmp_path / "s.toml").objects[0].material
    assert set(m.slots) == {"clearcoat", "sheen_color"}
    assert m.sheen_color_texture.texcoord == 1 and m.clearcoat_normal_scale == 0.5


@pytest.mark.parametrize("name, slots", [
    ("ClearCoatTest", {"clearcoat", "clearcoat_roughness", "clearcoat_normal"}),
    ("SpecularTest", {"specular", "specular_color"}),
    ("AttenuationTest", {"thickness"}),
])
def test_khronos_samples_bring_their_extension_textures(name, slots):
    path = shared_model(f"{name}/{name}.glb", SHARED_GLTF)
    with warnings.catch_warnings():
        warnings.simplefilter("error", FacetWarning)
        scene = facet.open_scene(path)
    found = set().union(*(set(o.material.slots) for o in scene.objects))
    assert slots <= found
