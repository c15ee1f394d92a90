"""Distributed effects by accumulation (notes §2.11): depth of field against the circle of
confusion formula, and motion blur as a streak of the travelled length."""

import numpy as np
import pytest

from facet.errors import InputError
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.geometry.lens import circle_of_confusion, concentric_disk, interpolate_transform
from facet.scene import Material, Scene

from conftest import sphere_mesh

W = H = 96
DOT = 0.02  # radius of the bright dots, scene units


def _dots(*centres, ends=None):
    scene = Scene(ambient=0.0, background=(0, 0, 0))
    for i, c in enumerate(centres):
        scene.add(sphere_mesh(2, DOT), Material(color=(1, 1, 1)), T.translate(c),
                  transform_end=None if ends is None else T.translate(ends[i]))
    return scene


def _spread(img: np.ndarray, threshold=2) -> float:
    """Diameter in pixels of the lit region (from its area, as a disc)."""
    return 2.0 * np.sqrt((img > threshold).sum() / np.pi)


def test_concentric_disk_stays_in_the_unit_disk():
    pts = concentric_disk(np.random.default_rng(0).random((500, 2)) - 0.5)
    r = np.linalg.norm(pts, axis=1)
    assert r.max() <= 1 + 1e-12 and r.mean() > 0.6  # fills the disc, not just its middle


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_depth_of_field_follows_the_circle_of_confusion(renderer, engine):
    """A dot on the focus plane stays sharp; dots nearer and farther spread over the circle of
    confusion c = A f_px |d - f| / (d f) (within 25% and 1.5 px)."""
    camera = Camera.look_at((0, 0, 0), (0, 0, -1), fov_y=30, near=0.5, far=50)
    camera.aperture, camera.focus_distance = 0.25, 4.0
    r = renderer(W, H)
    sharp = r.render(_dots((0, 0, -4.0)), camera, aa="ssaa:jittered:64", shading="unlit",
                     engine=engine)
    assert _spread(sharp.color[..., 0]) < 4  # about the dot's own size (~2 px)
    for depth in (2.5, 7.0):
        frame = r.render(_dots((0, 0, -depth)), camera, aa="ssaa:jittered:64",
                         shading="unlit", engine=engine)
        c = circle_of_confusion(camera, depth, H)
        spread = _spread(frame.color[..., 0])
        assert c > 4 and abs(spread - c) < 0.25 * c + 1.5, (depth, spread, c)
        if depth < 4:  # big enough (1.4 px) to cover a pixel centre through the pinhole
            # Labels and depth stay the pinhole's (lens centre), exact.
            assert set(np.unique(frame.object_ids)) == {-1, 0}
            assert (frame.depth > 0).sum() == (frame.object_ids == 0).sum()


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_motion_blur_streak(renderer, engine):
    """A dot moving 0.5 units sideways during the shutter leaves a streak as long as its
    path in the image (plus its size), of even, dimmer intensity."""
    camera = Camera.look_at((0, 0, 3), (0, 0, 0), ortho_height=2.0, near=1, far=5)
    scene = _dots((-0.25, 0, 0), ends=[(0.25, 0, 0)])
    # 256 samples: a pixel of the path is covered by ~1/20 of them, and fewer would leave
    # the count (in steps of 1/N) too coarse to call the streak even.
    frame = renderer(W, H).render(scene, camera, aa="ssaa:jittered:256", shading="unlit",
                                  engine=engine)
    row = frame.color[H // 2, :, 0].astype(int)
    lit = np.nonzero(row > 2)[0]
    path_px = 0.5 / 2.0 * W  # 0.5 units of a 2-unit-wide view
    assert abs((lit.max() - lit.min() + 1) - (path_px + 2 * DOT / 2.0 * W)) <= 3
    middle = row[lit.min() + 3: lit.max() - 3]
    assert middle.max() < 200 and middle.std() < 0.25 * middle.mean()  # smeared evenly


def test_interpolate_transform_and_bad_lens():
    a = T.compose(T.rotate_y(0), T.translate((0, 0, 0)))
    b = T.compose(T.scale(2), T.rotate_y(90), T.translate((4, 0, 0)))
    mid = interpolate_transform(a, b, 0.5)
    assert np.allclose(mid[:3, 3], (2, 0, 0))
    assert np.allclose(mid[:3, :3], T.compose(T.scale(1.5), T.rotate_y(45))[:3, :3])
    camera = Camera.look_at((0, 0, 3), (0, 0, 0))
    camera.aperture = 0.1
    scene = _dots((0, 0, 0))
    from facet.render.renderer import Renderer

    with Renderer(8, 8) as r:
        with pytest.raises(InputError, match="needs a focus distance"):
            r.render(scene, camera)
        camera.aperture = -1
        with pytest.raises(InputError, match="aperture must be"):
            r.render(scene, camera)


def test_cli_and_scene_file_lens(tmp_path, capsys):
    from facet.cli import main
    from facet.errors import SceneError
    from facet.formats import load_scene

    out = tmp_path / "d.png"
    assert main(["render", "--aperture", "0.2", "--focus", "5", "--size", "32x24", "-q",
                 "-o", str(out)]) == 0 and out.exists()
    for args, message in ((["--aperture", "0.2"], "needs a focus distance"),
                          (["--focus", "3"], "a focus distance needs an aperture")):
        assert main(["render", *args, "-o", str(tmp_path / "x.png")]) == 2
        assert message in capsys.readouterr().err
    scene = tmp_path / "s.toml"
    scene.write_text('[[objects]]\nprimitive = "sphere"\n[cameras.c]\ntype = "perspective"\n'
                     "eye = [0, 0, 4]\naperture = 0.1\nfocus_distance = 4\n")
    assert load_scene(scene).camera().aperture == 0.1
    scene.write_text(scene.read_text().replace("focus_distance = 4\n", ""))
    with pytest.raises(SceneError, match="cameras.c: an aperture needs a focus distance"):
        load_scene(scene)


def test_motion_blur_in_a_scene_file(tmp_path):
    """`transform_end` (steps, like `transform`) is the pose at shutter close; children move
    with their parents; objects without it in a still hierarchy are not blurred."""
    from facet.formats.scenefile import load_scene

    path = tmp_path / "blur.toml"
    path.write_text("""
[[objects]]
name = "cart"
transform = [{translate = [0, 0, 0]}]
transform_end = [{translate = [1, 0, 0]}]

[[objects]]
name = "wheel"
parent = "cart"
primitive = "sphere"
transform = [{translate = [0, 1, 0]}]

[[objects]]
name = "post"
primitive = "cube"
""")
    scene = load_scene(path)
    wheel, post = scene.objects
    assert np.allclose(wheel.transform, T.translate((0, 1, 0)))
    assert np.allclose(wheel.transform_end, T.translate((1, 1, 0)))
    assert post.transform_end is None
    path.write_text('[[objects]]\nprimitive = "cube"\ntransform_end = {scale = 0}\n')
    with pytest.raises(InputError, match=r"objects\[0\]\.transform_end: expected a list"):
        load_scene(path)
