"""Render options (no GL): the precedence defaults < front < scene file < explicit
arguments, written once in facet.options.render and tested here; that every front hands the
same value to the one parser (and gets the same sentence back) is tests/test_option_fronts.py."""


import numpy as np
import pytest

from facet.errors import InputError, SceneError
from facet.formats import load_scene
from facet.options.render import (
    DEFAULT_AA,
    RenderOptions,
    options_for,
    parse_aa,
    parse_layer,
    parse_option,
)
from facet.scene import Scene


def _scene_file(tmp_path, render_table: str, extra: str = ""):
    path = tmp_path / "s.toml"
    path.write_text(f'[render]\n{render_table}\n[[objects]]\nprimitive = "sphere"\n{extra}')
    return load_scene(path)


def test_precedence_defaults_then_scene_then_explicit_layers(tmp_path):
    scene = _scene_file(tmp_path, 'size = [64, 48]\nshading = "blinn"\naa = "jittered:4"\n'
                        "shadows = true\npcf = 2")
    defaults = RenderOptions()
    # "auto": pbr for glTF materials, phong for the rest (facet.render.materials)
    assert (defaults.size, defaults.shading, str(defaults.aa)) == ((800, 600), "auto",
                                                                   DEFAULT_AA)
    from_scene = options_for(scene)
    assert from_scene.size == (64, 48) and from_scene.shading == "blinn"
    assert str(from_scene.aa) == "ssaa:jittered:4" and from_scene.shadows and from_scene.pcf == 2
    assert from_scene.srgb is defaults.srgb  # what the file leaves out stays the default
    renderer_layer, call_layer = {"shading": "flat", "msaa": 0}, {"shading": "unlit"}
    resolved = options_for(scene, renderer_layer, call_layer)
    assert resolved.shading == "unlit"  # the later explicit layer wins
    assert str(resolved.aa) == "none"  # msaa=0 is aa="none", above the scene's aa
    assert resolved.size == (64, 48) and resolved.shadows  # untouched keys come through
    assert options_for(scene, {"shadows": False}).shadows is False
    assert options_for(scene, {"shading": None}).shading == "blinn"  # None: not given


def test_an_intrinsics_camera_sizes_the_image_below_explicit_sizes(tmp_path):
    camera = ('[cameras.k]\ntype = "intrinsics"\nfx = 50\nfy = 50\ncx = 31.5\ncy = 23.5\n'
              "width = 64\nheight = 48\n")
    scene = _scene_file(tmp_path, "size = [10, 10]", camera)
    assert options_for(scene).size == (64, 48)
    assert options_for(scene, {"size": (20, 30)}).size == (20, 30)


def test_msaa_is_aa_sugar_and_one_layer_may_not_give_both():
    assert str(RenderOptions.build({"msaa": 8}).aa) == "msaa:8"
    assert str(RenderOptions.build({"msaa": 0}).aa) == "none"
    with pytest.raises(InputError, match="give one of aa, msaa and spp, not aa and msaa"):
        parse_layer({"msaa": 4, "aa": "none"})
    assert str(RenderOptions.build({"spp": 9}).aa) == "ssaa:jittered:9"
    with pytest.raises(InputError, match="spp must be an integer >= 1"):
        RenderOptions.build({"spp": 0})
    assert str(RenderOptions.build({"msaa": 4}, {"aa": "grid:4"}).aa) == "ssaa:grid:4"


def test_unknown_option_keys_get_a_did_you_mean(tmp_path):
    with pytest.raises(InputError, match="unknown render option 'shadow'; did you mean "
                                         "'shadows'"):
        parse_option("shadow", True)
    with pytest.raises(SceneError, match="render.shadow: unknown key; did you mean 'shadows'"):
        _scene_file(tmp_path, "shadow = true")


def test_parsed_values_are_typed_once():
    opts = RenderOptions.build({"size": "64x48", "background": 0.5, "aa": "jittered:16",
                                "outputs": "color,depth,color", "aperture": 0.2})
    assert opts.size == (64, 48) and opts.background == (0.5, 0.5, 0.5, 1.0)
    assert opts.aa == parse_aa("ssaa:jittered:16") and opts.aa.supersampled
    assert opts.outputs == ("color", "depth") and opts.aperture == 0.2
    assert RenderOptions.build(opts) == opts  # a resolved object passes through unchanged
    assert opts.merged({"shadows": True}).shadows and not opts.shadows  # frozen: a copy


def test_a_python_scene_carries_options_like_a_scene_file():
    scene = Scene(options={"lights": "scene", "msaa": 0})
    assert options_for(scene).lights == "scene" and str(options_for(scene).aa) == "none"
    with pytest.raises(InputError, match="unknown lights mode"):
        Scene(options={"lights": "none!"})
    assert np.array_equal(Scene().background, [0, 0, 0, 1])


def test_build_takes_options_as_keywords_over_its_layers():
    """The README's `RenderOptions.build(aa=..., ...)`: keywords are the last layer."""
    opts = RenderOptions.build({"shadows": False, "msaa": 2}, aa="jittered:16", shadows=True)
    assert str(opts.aa) == "ssaa:jittered:16" and opts.shadows is True
    assert RenderOptions.build(size="64x48").size == (64, 48)
    with pytest.raises(InputError, match="unknown render option 'shadow'"):
        RenderOptions.build(shadow=True)
