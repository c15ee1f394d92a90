"""Pixels whose eye rays miss the scene's bounds (facet.render.rays.scene scene_rect): the
tracers draw them by a program that traces nothing (ESCAPED) and the rest by the whole
program over a rectangle; the exact channels leave them cleared. The pictures must be the
ones a single program draws over every pixel, bit for bit: in both tracers, with a sky,
samples stacked in one draw, moving objects, a lens, points and an unbounded plane."""

import numpy as np
import pytest

import facet
from facet.render.rays.scene import RayScene

from conftest import both_ways


def _scene(case: str) -> facet.Scene:
    scene = facet.Scene()
    scene.add(facet.primitives.cube(0.4), facet.PbrMaterial(base_color=(0.8, 0.3, 0.2)),
              facet.transforms.translate((0.3, 0.0, 0.0)),
              transform_end=facet.transforms.translate((0.5, 0.1, 0.0))
              if case == "moving" else None)
    scene.add(facet.shapes.Sphere(0.25), facet.PbrMaterial(base_color=(0.9,) * 3,
                                                           metallic=1.0, roughness=0.1),
              facet.transforms.translate((-0.4, 0.1, 0.0)))
    scene.add_light(facet.DirectionalLight((-0.3, -1.0, -0.4)))
    if case == "points":
        rng = np.random.default_rng(3)
        scene.add(facet.Points(rng.uniform(-0.2, 0.2, (50, 3)) + [0, 0.5, 0], radius=0.02))
    if case == "plane":  # unbounded: every pixel may see it (no rectangle)
        scene.add(facet.shapes.Plane(), facet.PbrMaterial(base_color=(0.5,) * 3),
                  facet.transforms.translate((0.0, -0.3, 0.0)))
    return scene


@pytest.mark.parametrize("engine", ["trace", "path"])
@pytest.mark.parametrize("case", ["still", "points", "moving", "lens", "plane"])
def test_escaped_pixels_draw_as_one_program_draws_them(engine, case):
    scene = _scene(case)
    camera = facet.Camera.look_at((0.4, 0.6, 3.0), (0.0, 0.0, 0.0), fov_y=35)
    kw = dict(engine=engine, spp=4, float_color=True, environment=facet.Environment.sky(),
              outputs=("color", "depth", "ids", "normals"))
    if case == "lens":
        kw.update(aperture=0.15, focus=3.0)

    def render():
        with facet.Renderer(64, 48) as r:
            f = r.render(scene, camera, **kw)
            return f.color, f.depth, f.object_ids, f.normals

    a, b = both_ways(RayScene, "use_rects", render)
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)
    if case != "plane":  # (most of the picture is sky: the rectangle mattered)
        assert (a[2] >= 0).mean() < 0.5


def test_the_rectangle_holds_every_pixel_a_ray_through_the_box_leaves():
    """scene_rect: the box's corners projected, a pixel wider all round; none (every pixel)
    for an unbounded scene, a corner behind the eye or a box over the whole picture; empty
    for an empty box."""
    from facet.render.rays.scene import scene_rect

    camera = facet.Camera.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=40)
    view = camera.projection(200, 100) @ camera.view
    box = np.array([[-0.3, -0.2, -0.1], [0.5, 0.4, 0.2]])
    x, y, w, h = scene_rect(box, [view], 200, 100)
    corners = np.array([[box[i, 0], box[j, 1], box[k, 2], 1.0]
                        for i in (0, 1) for j in (0, 1) for k in (0, 1)]) @ view.T
    px = (corners[:, :2] / corners[:, 3:] + 1.0) / 2.0 * [200, 100]
    assert x <= px[:, 0].min() - 1 and x + w >= px[:, 0].max() + 1
    assert y <= px[:, 1].min() - 1 and y + h >= px[:, 1].max() + 1
    assert w < 200 and h < 100 and w * h < 0.5 * 200 * 100
    second = facet.Camera.look_at((0.5, 0.0, 4.0), (0.5, 0.0, 0.0), fov_y=40)
    x2, _, w2, _ = scene_rect(box, [view, second.projection(200, 100) @ second.view], 200, 100)
    assert x2 <= x and x2 + w2 >= x + w and w2 > w  # (samples stacked: the union)
    assert scene_rect(None, [view], 200, 100) is None
    assert scene_rect(np.array([[-1, -1, 3.5], [1, 1, 5.0]]), [view], 200, 100) is None
    assert scene_rect(np.array([[-9, -9, -1], [9, 9, 1]]), [view], 200, 100) is None
    empty = np.array([[np.inf] * 3, [-np.inf] * 3])
    assert scene_rect(empty, [view], 200, 100) == (0, 0, 0, 0)


def test_the_rectangle_stays_within_a_strip_being_drawn():
    """A long sample is drawn in strips, each under its scissor (facet.render.sequence):
    the rectangle's draws stay inside the strip and leave its scissor as they found it
    (they once drew the whole rectangle in every strip and then cleared the scissor)."""
    from types import SimpleNamespace

    import moderngl

    from facet.gl.context import create_headless

    ctx = create_headless()
    try:
        target = ctx.texture((40, 30), 4)
        fbo = ctx.framebuffer([target])
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        program = ctx.program(
            vertex_shader="#version 330\nvoid main() { vec2 p = vec2(gl_VertexID & 1, "
                          "gl_VertexID >> 1) * 4.0 - 1.0; gl_Position = vec4(p, 0, 1); }",
            fragment_shader="#version 330\nout vec4 c; void main() { c = vec4(1.0); }")
        vao = ctx.vertex_array(program, [])
        white = SimpleNamespace(draw=lambda textures: vao.render(moderngl.TRIANGLES, 3))
        strip = (0, 10, 40, 10)
        ctx.scissor = strip
        RayScene._scissored(SimpleNamespace(ctx=ctx), white, None, (5, 5, 20, 20), 30)
        assert tuple(ctx.scissor) == strip
        ctx.scissor = None
        drawn = np.frombuffer(fbo.read(components=1), np.uint8).reshape(30, 40) > 0
        expected = np.zeros((30, 40), bool)
        expected[10:20, 5:25] = True  # (rows from the bottom: GL's window y)
        np.testing.assert_array_equal(drawn, expected)
    finally:
        ctx.release()
