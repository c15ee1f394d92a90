"""The tracers' programs hold the code of what the scene holds (facet.render.rays.scene
scene_defines): a mesh-only scene's traversal tests triangles alone (llvmpipe runs every
line of a branch whether a lane takes it or not, so unreachable sphere, capsule and shape
tests cost time). One renderer switching between scenes must switch programs with them: a
stale program would lose the points or the shapes of the next scene."""

from pathlib import Path

import numpy as np
import pytest

import facet
from facet.scene.pbr import PbrMaterial

ROOT = Path(__file__).resolve().parents[1]
CAM = facet.Camera.look_at((0, 0.5, 4), (0, 0.3, 0), fov_y=40, near=0.5, far=20)


def _floor():
    scene = facet.Scene(ambient=0.5)
    scene.add(facet.primitives.plane(4.0), PbrMaterial(base_color=(0.5,) * 3, metallic=0.0))
    return scene


def _with(extra):
    scene = _floor()
    scene.add(extra, PbrMaterial(base_color=(0.9, 0.1, 0.1), metallic=0.0),
              facet.transforms.translate((0, 0.4, 0)))
    return scene


@pytest.mark.parametrize("engine", ["path", "trace"])
def test_programs_follow_the_scene_they_draw(engine):
    scenes = {"mesh": _floor(),
              "points": _with(facet.Points([[0.0, 0.0, 0.0]], radius=0.3)),
              "shape": _with(facet.shapes.Sphere(0.3))}
    with facet.Renderer(48, 48) as r:
        red = {}
        for name in ("mesh", "points", "shape", "mesh", "points"):
            frame = r.render(scenes[name], CAM, engine=engine, spp=2, float_color=True)
            c = frame.color[..., :3]
            red[name] = int(((c[..., 0] > 2 * c[..., 1]) & (c[..., 0] > 0.05)).sum())
        assert red["mesh"] == 0 and red["points"] > 30 and red["shape"] > 30


def test_a_mesh_only_scene_leaves_sprites_and_shapes_out():
    with facet.Renderer(16, 16) as r:
        r.render(_floor(), CAM, engine="path", spp=1)
        programs = r._engines["path"].rays.programs
        assert programs and all({"NO_SPRITES", "NO_SHAPES"} <= dict(key[1]).keys()
                                for key in programs)


def test_the_path_tracer_follows_the_lights_of_the_scene_it_draws():
    """NO_DELTA_LIGHTS and NO_EMITTERS leave light sampling out where a frame has no such
    light: the next frame, with a lamp or a glowing panel, must be lit by it."""
    def scene(kind):
        s = facet.Scene()
        s.add(facet.primitives.plane(4.0), PbrMaterial(base_color=(0.6,) * 3, metallic=0.0))
        if kind == "lamp":
            s.lights.append(facet.PointLight((0, 1.5, 0.5), intensity=3.0))
        if kind == "glow":
            s.add(facet.primitives.plane(0.6), PbrMaterial(
                base_color=(0, 0, 0), metallic=0.0, emissive=(1, 1, 1), emissive_strength=20),
                facet.transforms.translate((0, 1.2, 0)) @ facet.transforms.rotate_x(180.0))
        return s

    with facet.Renderer(32, 32) as r:
        means = []
        for kind in ("dark", "lamp", "glow", "dark", "glow", "lamp"):
            frame = r.render(scene(kind), CAM, engine="path", spp=4, float_color=True,
                             lights="scene")
            means.append((kind, float(frame.color[..., :3].mean())))
    for kind, mean in means:
        assert (mean == 0.0) if kind == "dark" else (mean > 0.05), means


@pytest.mark.parametrize("feature", [dict(transmission=1.0, roughness=0.0, thickness=1.0),
                                     dict(clearcoat=1.0, clearcoat_roughness=0.1),
                                     dict(sheen_color=(1.0, 0.5, 0.5), sheen_roughness=0.5)])
def test_material_lobes_follow_the_scene(feature):
    """NO_TRANSMISSION, NO_CLEARCOAT and NO_SHEEN leave out lobes no material has; a scene
    drawn after one without them draws them (the same picture as a fresh renderer's)."""
    def scene(extra):
        s = _floor()
        s.add(facet.primitives.sphere(0.4, segments=24, rings=12),
              PbrMaterial(base_color=(0.8, 0.8, 0.9), metallic=0.0, **extra),
              facet.transforms.translate((0, 0.4, 0)))
        return s

    kw = dict(engine="path", spp=4, float_color=True)
    with facet.Renderer(32, 32) as r:
        r.render(scene({}), CAM, **kw)
        (key,) = {k for k in r._engines["path"].rays.programs  # (not the sky's: ESCAPED)
                  if k[0] == "path" and "ESCAPED" not in dict(k[1])}
        assert {"NO_TRANSMISSION", "NO_CLEARCOAT", "NO_SHEEN"} <= dict(key[1]).keys()
        after = r.render(scene(feature), CAM, **kw).color
    with facet.Renderer(32, 32) as r:
        fresh = r.render(scene(feature), CAM, **kw).color
        plain = r.render(scene({}), CAM, **kw).color
    np.testing.assert_array_equal(after, fresh)
    assert np.abs(fresh - plain).mean() > 1e-3  # (the lobe shows)


def _shapes(*kinds):
    scene = facet.Scene(ambient=0.5)
    scene.add(facet.shapes.Plane((4.0, 4.0)), PbrMaterial(base_color=(0.5,) * 3, metallic=0.0))
    made = {"sphere": facet.shapes.Sphere(0.3), "cone": facet.shapes.Cone(0.3, 0.6),
            "box": facet.shapes.Box((0.5, 0.5, 0.5)), "mesh": facet.primitives.cube(0.5)}
    for i, kind in enumerate(kinds):
        scene.add(made[kind], PbrMaterial(base_color=(0.9, 0.1, 0.1), metallic=0.0),
                  facet.transforms.translate((0.7 * i - 0.5, 0.35, 0)))
    return scene


@pytest.mark.parametrize("engine", ["path", "trace"])
def test_shape_kinds_follow_the_scene(engine):
    """NO_MESHES and NO_KIND_* leave out mesh traversal and the tests of shape kinds no
    object has (a Cornell box of shapes paid for the cone's and cylinder's test at every
    candidate): each next scene draws what it holds, as a fresh renderer does."""
    kw = dict(engine=engine, spp=2, float_color=True)
    order = [("sphere",), ("cone",), ("box", "mesh"), ("sphere",), ("mesh",), ("cone",)]
    with facet.Renderer(32, 32) as r:
        seen = [r.render(_shapes(*kinds), CAM, **kw).color for kinds in order]
        keys = {k for k in r._engines[engine].rays.programs if k[0] == engine}
    defines = [dict(k[1]).keys() for k in keys]
    assert any({"NO_MESHES", "NO_KIND_CONE", "NO_KIND_BOX"} <= d for d in defines)
    assert any("NO_KIND_SPHERE" in d and "NO_MESHES" not in d for d in defines)
    for kinds, picture in zip(order, seen, strict=True):
        with facet.Renderer(32, 32) as r:
            np.testing.assert_array_equal(picture, r.render(_shapes(*kinds), CAM, **kw).color)
        red = (picture[..., 0] > 2 * picture[..., 1]) & (picture[..., 0] > 0.05)
        assert red.sum() > 20 * len(kinds), kinds


def test_area_lights_are_shapes_to_the_path_tracer():
    """An area light's rectangle is an analytic plane: the Cornell box of shapes and an
    area light traces with no mesh code."""
    scene = facet.load(ROOT / "models" / "cornell.toml")
    with facet.Renderer(16, 16) as r:
        r.render(scene, engine="path", spp=1)
        keys = [k for k in r._engines["path"].rays.programs if k[0] == "path"]
    assert keys and all("NO_MESHES" in dict(k[1]) for k in keys)


def test_the_emitters_follow_emitting_shapes():
    """The emitters' table is made again when an emitting shape changes (it was keyed by
    the meshes alone: a scene of shapes that lost an object failed to draw, one whose lamp
    grew kept sampling the small lamp's area)."""
    def scene(size, extra):
        s = facet.Scene(ambient=0.0)
        s.add(facet.shapes.Plane((4.0, 4.0)), PbrMaterial(base_color=(0.6,) * 3, metallic=0.0))
        s.add(facet.shapes.Plane((size, size)), PbrMaterial(
            base_color=(0, 0, 0), metallic=0.0, emissive=(1, 1, 1), emissive_strength=10.0),
            facet.transforms.translate((0, 1.2, 0)) @ facet.transforms.rotate_x(180.0))
        if extra:
            s.add(facet.shapes.Sphere(0.2), PbrMaterial(base_color=(0.5,) * 3, metallic=0.0),
                  facet.transforms.translate((0.8, 0.2, 0)))
        return s

    kw = dict(engine="path", spp=8, float_color=True, lights="scene")
    with facet.Renderer(32, 32) as r:
        r.render(scene(0.4, True), CAM, **kw)
        after = r.render(scene(0.8, False), CAM, **kw).color
    with facet.Renderer(32, 32) as r:
        fresh = r.render(scene(0.8, False), CAM, **kw).color
    np.testing.assert_array_equal(after, fresh)
