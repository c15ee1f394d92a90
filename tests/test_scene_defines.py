"""The tracers' programs hold the code of what the scene holds (facet.render.rays.scene
scene_defines): a mesh-only scene's traversal tests triangles alone (llvmpipe runs every
line of a branch whether a lane takes it or not, so unreachable sphere, capsule and shape
tests cost time). One renderer switching between scenes must switch programs with them: a
stale program would lose the points or the shapes of the next scene."""

import numpy as np
import pytest

import facet
from facet.scene.pbr import PbrMaterial

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
        (key,) = {k for k in r._engines["path"].rays.programs if k[0] == "path"}
        assert {"NO_TRANSMISSION", "NO_CLEARCOAT", "NO_SHEEN"} <= dict(key[1]).keys()
        after = r.render(scene(feature), CAM, **kw).color
    with facet.Renderer(32, 32) as r:
        fresh = r.render(scene(feature), CAM, **kw).color
        plain = r.render(scene({}), CAM, **kw).color
    np.testing.assert_array_equal(after, fresh)
    assert np.abs(fresh - plain).mean() > 1e-3  # (the lobe shows)
