"""Order-independent transparency: overlapping coloured quads against the analytic "over"
result, within weighted blended OIT's stated error, whatever the draw order."""

import numpy as np
import pytest

from facet.errors import InputError
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.render.raster.transparency import oit_two_layers, over_two_layers, weight
from facet.scene import Material, Mesh, Scene

S = 48
CAMERA = Camera.look_at((0, 0, 5), (0, 0, 0), ortho_height=4.0, near=1, far=9)
BG = np.array([0.2, 0.2, 0.2])
RED, BLUE = np.array([1.0, 0.1, 0.1]), np.array([0.1, 0.2, 1.0])


def quad(x0, x1, y0, y1, z):
    pos = [[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]]
    return Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4)


def scene(order, a_front=0.5, a_back=0.5):
    s = Scene(ambient=0.0, background=(*BG, 1.0))
    layers = {"front": (quad(-1.5, 0.5, -1.0, 1.0, 0.5), RED, a_front),
              "back": (quad(-0.5, 1.5, -1.2, 0.8, -0.5), BLUE, a_back)}
    for name in order:
        mesh, color, a = layers[name]
        s.add(mesh, Material(color=color, opacity=a))
    return s


def window_z(z_world):
    """Window-space depth of a point at world z seen by CAMERA (orthographic)."""
    clip = CAMERA.projection(S, S) @ CAMERA.view @ [0.0, 0.0, z_world, 1.0]
    return (clip[2] / clip[3] + 1) / 2


@pytest.mark.parametrize("order", [("front", "back"), ("back", "front")])
@pytest.mark.parametrize("alphas", [(0.5, 0.5), (0.7, 0.3)])
def test_overlapping_quads(renderer, order, alphas):
    frame = renderer(S, S).render(scene(order, *alphas), CAMERA, shading="unlit")
    img = frame.color[..., :3] / 255.0
    a1, a2 = alphas
    w1, w2 = weight(window_z(0.5)), weight(window_z(-0.5))
    both = img[S // 2 - 2, S // 2]  # x = 0: inside both quads
    model = oit_two_layers(RED, a1, w1, BLUE, a2, w2, BG)
    exact = over_two_layers(RED, a1, BLUE, a2, BG)
    assert np.abs(both - model).max() <= 2 / 255  # the method, as stated
    bound = np.abs(RED - BLUE) * a1 * a2 * (a1 + a2 - a1 * a2) / (a1 + a2)
    assert np.all(np.abs(both - exact) <= bound + 2 / 255)  # its stated error vs "over"
    # Where only one layer covers the pixel, OIT is exact.
    only_front = img[S // 2 - 2, S // 2 - 15]
    only_back = img[S // 2 - 2, S // 2 + 15]
    assert np.allclose(only_front, a1 * RED + (1 - a1) * BG, atol=2 / 255)
    assert np.allclose(only_back, a2 * BLUE + (1 - a2) * BG, atol=2 / 255)
    # Transparent objects leave the exact channels to the (here: no) opaque surfaces.
    assert np.all(frame.object_ids == -1) and np.all(frame.depth == 0)


def test_draw_order_does_not_matter(renderer):
    r = renderer(S, S)
    a = r.render(scene(("front", "back")), CAMERA, shading="unlit").color
    b = r.render(scene(("back", "front")), CAMERA, shading="unlit").color
    assert np.abs(a.astype(int) - b).max() <= 1


def test_opaque_surfaces_hide_what_is_behind_them(renderer):
    s = scene(("front", "back"))
    s.add(quad(-2, 2, -2, 2, 0.0), Material(color=(0, 1, 0)))  # opaque, between the layers
    frame = renderer(S, S, 4).render(s, CAMERA, shading="unlit", aa="msaa:4")
    img = frame.color[..., :3] / 255.0
    both = img[S // 2 - 2, S // 2]
    assert np.allclose(both, 0.5 * RED + 0.5 * np.array([0, 1, 0]), atol=3 / 255)
    assert frame.object_ids[S // 2, S // 2] == 2  # the opaque quad's id
    ss = renderer(S, S).render(s, CAMERA, shading="unlit", aa="ssaa:grid:4")
    assert np.allclose(ss.color[S // 2 - 2, S // 2, :3] / 255.0, both, atol=3 / 255)


def test_opacity_must_be_in_range(tmp_path):
    from facet.errors import SceneError
    from facet.formats import load_scene

    with pytest.raises(InputError, match="opacity must be a number in"):
        Material(opacity=1.5)
    with pytest.raises(InputError, match="opacity"):
        Material(opacity=-0.1)
    path = tmp_path / "s.toml"
    path.write_text("[materials.glass]\nopacity = 2\n")
    with pytest.raises(SceneError, match=r"materials\.glass\.opacity: expected a number in"):
        load_scene(path)
    path.write_text('[materials.glass]\nopacity = 0.4\n[[objects]]\nprimitive = "cube"\n'
                    'material = "glass"\n')
    assert load_scene(path).objects[0].material.opacity == 0.4


@pytest.mark.parametrize("aa", [None, "msaa:4", "ssaa:grid:4"])
def test_transparent_background_gets_straight_alpha(renderer, aa):
    """Over a transparent (alpha 0) background, anti-aliased edges and transparent layers
    keep their own colour in the RGBA image (straight alpha, as PNG means it): coverage goes
    into alpha, not into a fade towards the background's rgb."""
    orange = np.array([1.0, 0.5, 0.0])
    # Slanted edges: partly covered pixels all along them.
    tilted = Camera(CAMERA.view @ T.rotate_z(17.0), ortho_height=4.0, near=1, far=9)
    r = renderer(S, S)
    for color, opacity in ((orange, 1.0), (RED, 0.5)):
        s = Scene(ambient=0.0, background=(0.0, 0.0, 1.0, 0.0))  # blue, fully transparent
        s.add(quad(-1.3, 0.3, -1.1, 0.9, 0.0), Material(color=color, opacity=opacity))
        img = r.render(s, tilted, shading="unlit", aa=aa).color.astype(int)
        a = img[..., 3]
        inside = a == round(255 * opacity)
        assert inside.sum() > 100
        assert np.abs(img[inside][:, :3] - color * 255).max() <= 1
        if aa is not None:
            edge = (a >= 32) & (a < round(255 * opacity) - 8)
            assert edge.sum() > 10
            assert np.abs(img[edge][:, :3] - color * 255).max() <= 5


def test_switching_msaa_keeps_transparency_working(renderer):
    """The OIT pass binds the colour targets' depth buffer: after the targets are replaced
    (another MSAA count) it must use the new one (GL reuses names: a stale framebuffer was
    found by name and drawing failed with GL_INVALID_OPERATION)."""
    r = renderer(S, S)
    pictures = [r.render(scene(("front", "back")), CAMERA, shading="unlit", aa=aa).color
                for aa in ("none", "msaa:4", "msaa:2", "none")]
    assert r.gl_error() == "GL_NO_ERROR"
    assert np.array_equal(pictures[0], pictures[3])
    for img in pictures[1:3]:
        inner = np.abs(img[4:-4, 4:-4].astype(int) - pictures[0][4:-4, 4:-4]).max(axis=2)
        assert (inner > 3).mean() < 0.05  # MSAA changes edges only
