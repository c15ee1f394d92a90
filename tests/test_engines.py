"""The engines behind one door (facet.render.engine): one table of engines, chosen once per
call; what an engine cannot honour is said in one warning line, once, naming it, never
dropped silently; engines agree where both honour the scene."""

import subprocess
import sys
import warnings

import numpy as np
import pytest

from facet.errors import FacetWarning
from facet.geometry.camera import Camera
from facet.options.render import ENGINES
from facet.render.engine import ENGINE_CLASSES, Engine, engine_for
from facet.scene import DirectionalLight, Material, Scene, Texture
from facet.scene.pbr import PbrMaterial, TextureSlot, texture_transform
from facet.scene.shader import UserShader

from conftest import ROOT, bare_env, sphere_mesh

CAMERA = Camera.look_at((0.5, 1.0, 3.5), (0, 0, 0), fov_y=40, near=0.5, far=10)


def test_every_engine_option_has_an_engine():
    assert set(ENGINE_CLASSES) == set(ENGINES)
    for name in ENGINES:
        cls = engine_for(name)
        assert issubclass(cls, Engine) and cls.name == name


def _warnings(renderer, scene, **kw) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        renderer.render(scene, CAMERA, outputs=("color",), **kw)
    return [str(w.message) for w in caught if issubclass(w.category, FacetWarning)]


def _scene(material=None) -> Scene:
    scene = Scene()
    scene.add(sphere_mesh(3), material or Material())
    scene.add_light(DirectionalLight((-1, -1, -1)))
    return scene


def test_the_tracer_names_what_it_does_not_draw_once(renderer):
    from facet.render.renderer import Renderer

    with Renderer(16, 16) as r:  # a fresh renderer: nothing said yet
        first = _warnings(r, _scene(), engine="trace", wireframe=True)
        assert first == ["the ray tracer draws no wireframe overlay"]
        assert _warnings(r, _scene(), engine="trace", wireframe=True) == []  # said once
        assert _warnings(r, _scene(), wireframe=True) == []  # the rasterizer draws it
        shader = UserShader(ROOT / "glsl" / "examples" / "toon.frag")
        said = _warnings(r, _scene(Material(shader=shader)), engine="trace")
        assert len(said) == 1 and "users' mesh shaders" in said[0] and "1 of 1" in said[0]
        checker = Texture.checker()
        gltf = PbrMaterial(metallic=0.0, roughness=0.5, emissive=(0.2, 0, 0),
                           normal_texture=TextureSlot(checker),
                           base_color_texture=TextureSlot(checker, transform=texture_transform(
                               scale=(2, 2))), alpha_mode="MASK")
        # The tracer shades glTF materials by their model, slots and cut-outs included:
        # nothing to say; reflections in metals and transmission it traces too.
        assert _warnings(r, _scene(gltf), engine="trace") == []
        glass = PbrMaterial(metallic=1.0, roughness=0.3, transmission=0.5)
        assert _warnings(r, _scene(glass), engine="trace") == []
        assert _warnings(r, _scene(), max_depth=3) == [
            "max_depth sets the tracers' recursion and bounces; the rasterizer ignores it"]


def test_one_warning_line_on_the_command_line(tmp_path):
    out = subprocess.run([sys.executable, "-m", "facet", "render", "--engine", "trace",
                          "--wireframe", "--size", "24x24", "-o", str(tmp_path / "w.png")],
                         capture_output=True, text=True, cwd=tmp_path, timeout=120,
                         env=bare_env())
    assert out.returncode == 0, out.stderr
    assert out.stderr.splitlines() == [
        "facet: warning: the ray tracer draws no wireframe overlay"]


@pytest.mark.parametrize("shading", ["phong", "flat", "unlit", "normals"])
def test_engines_agree_where_both_honour_the_scene(renderer, shading):
    """Rasterized and traced, a lit sphere without shadows draws the same pixels (the
    tessellation aside: the tracer hits the same triangles)."""
    scene = _scene(Material(color=(0.8, 0.5, 0.3), ks=0.4))
    r = renderer(48, 48)
    kw = dict(shading=shading, shadows=False, aa="none", float_color=True,
              outputs=("color", "ids"))
    raster = r.render(scene, CAMERA, **kw)
    traced = r.render(scene, CAMERA, engine="trace", **kw)
    both = (raster.object_ids == 0) & (traced.object_ids == 0)
    assert both.sum() > 600 and (raster.object_ids != traced.object_ids).mean() < 0.01
    diff = np.abs(raster.color[..., :3] - traced.color[..., :3]).max(-1)[both]
    assert np.percentile(diff, 99) < 2 / 255, np.percentile(diff, 99)


def test_the_tracer_says_it_lights_gltf_materials_by_the_ambient_term():
    from facet.render.renderer import Renderer

    scene = Scene()
    scene.add(sphere_mesh(), PbrMaterial(roughness=0.3))
    with Renderer(16, 16) as r:
        said = _warnings(r, scene, engine="trace", environment="sky")
    assert any("by the ambient term, not by the environment" in x for x in said), said
