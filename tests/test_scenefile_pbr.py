"""Scene files' metallic-roughness materials: the keys make the same PbrMaterial as Python
does (and so the same picture), texture tables with transforms and uv sets, and mistakes
(Phong keys mixed in, misspellings, values out of range) one line each."""

import numpy as np
import pytest

import facet
from facet.errors import SceneError
from facet.formats.scenefile import load_scene
from facet.scene.pbr import PbrMaterial, texture_transform

GOLD = """
[materials.gold]
base_color = [1.0, 0.77, 0.34]
metallic = 1.0
roughness = 0.3
specular = 0.5
specular_color = [1.0, 0.9, 0.8]
ior = 1.33
emissive = [0.1, 0.0, 0.0]
emissive_strength = 3.0
double_sided = true

[materials.gold.base_color_texture]
image = "checker"
texcoord = 1
wrap = ["clamp", "mirror"]
offset = [0.25, 0.0]
rotation = 90
scale = [2, 2]

[[objects]]
primitive = "sphere"
material = {material}
"""


def _load(tmp_path, text):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return load_scene(path)


def test_a_table_of_pbr_keys_is_a_pbr_material(tmp_path):
    m = _load(tmp_path, GOLD.format(material='"gold"')).objects[0].material
    assert isinstance(m, PbrMaterial)
    np.testing.assert_allclose(m.base_color, (1.0, 0.77, 0.34, 1.0))
    assert (m.metallic, m.roughness, m.specular, m.ior) == (1.0, 0.3, 0.5, 1.33)
    np.testing.assert_allclose(m.emissive * m.emissive_strength, (0.3, 0, 0))
    f0 = ((1.33 - 1) / (1.33 + 1)) ** 2 * np.array([1.0, 0.9, 0.8]) * 0.5
    np.testing.assert_allclose(m.dielectric_f0, f0)
    slot = m.base_color_texture
    assert slot.texcoord == 1 and slot.wrap == ("clamp", "mirror")
    np.testing.assert_allclose(slot.transform, texture_transform((0.25, 0), np.pi / 2, (2, 2)),
                               atol=1e-12)
    assert m.double_sided


def test_inline_tables_too(tmp_path):
    m = _load(tmp_path, GOLD.format(material='{ base_color = [0.2, 0.3, 0.4, 0.5], '
                                    'alpha_mode = "BLEND", specular = 0 }')).objects[0].material
    assert isinstance(m, PbrMaterial) and m.alpha_mode == "BLEND" and m.opacity == 0.5
    assert np.all(m.dielectric_f0 == 0)


def test_the_scene_file_and_python_give_the_same_picture(tmp_path):
    scene = _load(tmp_path, GOLD.format(material='"gold"'))
    same = facet.Scene()
    same.add(facet.primitives.sphere(), scene.objects[0].material)
    python = facet.Scene()
    python.add(facet.primitives.sphere(), PbrMaterial(
        base_color=(1.0, 0.77, 0.34), metallic=1.0, roughness=0.3, specular=0.5,
        specular_color=(1.0, 0.9, 0.8), ior=1.33, emissive=(0.1, 0, 0), emissive_strength=3,
        double_sided=True, base_color_texture=scene.objects[0].material.base_color_texture))
    with facet.Renderer(32, 32) as r:
        for engine in ("raster", "path"):
            a = r.render(same, engine=engine, spp=2).color
            b = r.render(python, engine=engine, spp=2).color
            assert np.array_equal(a, b), engine


@pytest.mark.parametrize("material, message", [
    ('{ base_color = [1, 1, 1], shininess = 8 }', "a Phong key in a metallic-roughness"),
    ('{ color = [1, 1, 1], metalic = 1 }', "did you mean 'metallic'"),
    ('{ base_color = [1, 1, 1], roughness = 2 }', "roughness: expected a number in [0, 1]"),
    ('{ base_color = [1, 1, 1], ior = 0.5 }', "ior: expected a number >= 1 (or 0)"),
    ('{ base_color = [1, 1, 1], alpha_mode = "CUT" }', "expected one of OPAQUE, MASK, BLEND"),
    ('{ base_color_texture = { texcoord = 2, image = "checker" } }', "expected 0 or 1"),
    ('{ base_color_texture = { wrap = "loop", image = "checker" } }', "repeat, clamp, mirror"),
])
def test_mistakes_are_one_line(tmp_path, material, message):
    with pytest.raises(SceneError, match=message.replace("[", r"\[").replace("(", r"\(")
                       .replace(")", r"\)")) as info:
        _load(tmp_path, GOLD.format(material=material))
    assert "\n" not in str(info.value)
