"""Each engine's capability table (facet.render.capabilities): options keep "not given"
until the engine decides (a path tracer told max_depth = 5 traces five bounces, not its
default eight), what an engine leaves out is named in a warning line made from its row, and
nothing builds a rasterizer to show another engine."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import facet
from facet.scene import primitives

ROOT = Path(__file__).resolve().parents[1]


def _mirror_room():
    """Two facing mirrors with a lit ball between them: each bounce shows another image."""
    T = facet.transforms
    scene = facet.Scene(ambient=0.0, background=(0, 0, 0))
    mirror = facet.PbrMaterial(base_color=(0.95, 0.95, 0.95, 1), metallic=1.0, roughness=0.0)
    scene.add(primitives.plane(4.0), mirror, T.compose(T.rotate_z(-90), T.translate((-1, 0, 0))))
    scene.add(primitives.plane(4.0), mirror, T.compose(T.rotate_z(90), T.translate((1, 0, 0))))
    scene.add(primitives.sphere(0.3), facet.PbrMaterial(emissive=(1, 0.5, 0.2), metallic=0.0))
    return scene


def test_a_path_tracer_told_five_bounces_traces_five(renderer):
    """max_depth = 5 given to the path tracer is five bounces, not its default eight: the
    picture differs from the default's, which equals max_depth = 8 given. (Old code: 5 was
    taken for "not given", and the picture was byte-identical to 8's.)"""
    r = renderer(48, 32)
    cam = facet.Camera.look_at((0.3, 0.0, 1.2), (-1, 0, 0), fov_y=60)
    scene = _mirror_room()
    opts = dict(engine="path", aa="ssaa:grid:1", outputs=("color",), float_color=True)
    eight = r.render(scene, cam, max_depth=8, **opts).color
    eight = r.render(scene, cam, max_depth=8, **opts).color  # (not the first: see below)
    five = r.render(scene, cam, max_depth=5, **opts).color
    default = r.render(scene, cam, **opts).color
    np.testing.assert_array_equal(default, eight)
    assert np.abs(five - eight).max() > 0.05


def test_the_engines_decide_what_was_not_given():
    """None until decided: the rasterizer casts no shadows and takes no bounces, the
    tracers cast shadows, the Whitted tracer recurses 5 deep and the path tracer bounces 8
    times; given values stay."""
    from facet.render.capabilities import CAPABILITIES, decided

    opts = facet.RenderOptions.build()
    assert opts.shadows is None and opts.max_depth is None and opts.pcf is None
    raster, trace, path = (decided(opts.merged({"engine": e})) for e in CAPABILITIES)
    assert (raster.shadows, trace.shadows, path.shadows) == (False, True, True)
    assert (trace.max_depth, path.max_depth, raster.pcf) == (5, 8, 1)
    given = decided(opts.merged({"engine": "path", "max_depth": 5, "shadows": False}))
    assert (given.max_depth, given.shadows) == (5, False)


def test_a_feature_an_engine_leaves_out_is_named_in_its_warning():
    """Every feature a row says its engine leaves out, when a scene uses it, is one warning
    line naming it; a feature the engine draws is not named. The rasterizer warns about
    max_depth whenever it is given (5 too: the old check compared with the default). No
    engine names occlusionTexture: the rasterizer and the ray tracer draw it; the path
    tracer's bounces find the occlusion it stands for (a warning on every textured glTF
    model was noise)."""
    from facet.render.capabilities import material_features

    pixels = np.full((4, 4, 4), 128, np.uint8)
    occluded = facet.PbrMaterial(occlusion_texture=facet.TextureSlot(facet.Texture(pixels)))
    assert "occlusionTexture" in material_features(occluded)
    scene = facet.Scene()
    scene.add(primitives.sphere(0.5), occluded)
    scene.add(primitives.cube(0.5), facet.Material(reflectivity=0.5))
    cam = facet.Camera.look_at((0, 0, 3), (0, 0, 0), fov_y=40)
    for engine, named, unnamed in (("path", ["Phong reflectivity"], ["occlusionTexture"]),
                                   ("trace", [], ["occlusionTexture", "Phong reflectivity"]),
                                   ("raster", ["max_depth"], ["occlusionTexture"])):
        with warnings.catch_warnings(record=True) as caught, facet.Renderer(16, 16) as r:
            warnings.simplefilter("always")
            r.render(scene, cam, engine=engine, outputs=("color",),
                     **({"max_depth": 5} if engine == "raster" else {}))
        lines = [str(w.message) for w in caught if issubclass(w.category, facet.FacetWarning)]
        for word in named:
            assert sum(word in line for line in lines) == 1, (engine, word, lines)
        for word in unnamed:
            assert not any(word in line for line in lines), (engine, word, lines)


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_nothing_builds_a_rasterizer_to_show_another_engine(engine):
    """A renderer and a viewer session showing a tracer make that engine alone (the old
    renderer and viewer built the rasterizer too, to ask it about users' shaders); the
    session's status line names the engine the options gave (the old one read only the
    keys: a flag or a scene file's engine showed as raster)."""
    from facet.viewing.session import Session

    scene = facet.Scene()
    scene.add(primitives.sphere(0.5), facet.Material())
    with facet.Renderer(16, 16) as r:
        r.render(scene, facet.Camera.look_at((0, 0, 3), (0, 0, 0)), engine=engine)
        assert set(r._engines) == {engine}
    with Session(str(ROOT / "models" / "default.obj"), size=(32, 24),
                 options={"engine": engine}) as s:
        assert s.frame() is not None
        assert set(s.renderer._engines) == {engine}
        assert f"engine {engine}" in s.status()


def test_the_first_path_traced_picture_of_a_scene_is_its_picture():
    """The same call twice gives the same picture, the first time too. (Old code: the
    emitters were counted while binding, after the count was handed to the shader: a new
    scene's first picture sampled the last scene's number of emitters, here none, and came
    out a different, noisier estimate.)"""
    cam = facet.Camera.look_at((0.3, 0.0, 1.2), (-1, 0, 0), fov_y=60)
    scene = _mirror_room()
    opts = dict(engine="path", aa="ssaa:grid:1", outputs=("color",), float_color=True)
    with facet.Renderer(48, 32) as r:  # a new one: its path tracer has drawn nothing yet
        first, second = (r.render(scene, cam, **opts).color for _ in range(2))
    np.testing.assert_array_equal(first, second)
