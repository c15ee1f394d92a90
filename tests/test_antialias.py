"""Anti-aliasing by supersampling with the notes' sample patterns: the patterns themselves,
the measured error of each against a 256-sample reference, exact labels, and sub-pixel
objects that only supersampling can see."""

import numpy as np
import pytest

from facet.errors import InputError
from facet.geometry import sampling
from facet.geometry.camera import Camera
from facet.options.render import parse_aa
from facet.render.antialias import jitter_matrix
from facet.scene import Material, Mesh, Scene

S = 64
CAMERA = Camera.look_at((0, 0, 3), (0, 0, 0), ortho_height=2.0, near=1, far=5)


@pytest.mark.parametrize("name", sampling.PATTERNS)
@pytest.mark.parametrize("n", [1, 4, 16, 64])
def test_patterns_cover_the_pixel(name, n):
    p = sampling.pattern(name, n)
    assert p.shape == (n, 2) and p.min() >= -0.5 and p.max() < 0.5
    assert np.array_equal(p, sampling.pattern(name, n))  # deterministic
    if name == "poisson" and n > 1:
        d = np.linalg.norm(p[:, None] - p[None], axis=-1) + np.eye(n)
        assert d.min() >= sampling.poisson_eps(n) * 0.9**3  # eps, relaxed at most thrice
    if name == "jittered":
        rows, cols = sampling._factor(n)
        cells = {(int((y + 0.5) * rows), int((x + 0.5) * cols)) for x, y in p}
        assert len(cells) == n  # one point per cell
    if name == "grid":
        assert np.allclose(np.sort(np.unique(p[:, 0])),
                           (np.arange(int(np.sqrt(n))) + 0.5) / np.sqrt(n) - 0.5)


def test_pattern_arguments():
    with pytest.raises(InputError, match="square number"):
        sampling.pattern("grid", 8)
    with pytest.raises(InputError, match="unknown sample pattern"):
        sampling.pattern("blue-noise", 4)
    with pytest.raises(InputError, match=">= 1"):
        sampling.jittered(0)
    for bad in ("ssaa:jittered:0", "ssaa:jittered:-3", "msaa:3", "fxaa", "jittered:x"):
        with pytest.raises(InputError):
            parse_aa(bad)
    assert parse_aa(f"random:{sampling.MAX_SAMPLES}").samples == sampling.MAX_SAMPLES
    with pytest.raises(InputError, match="at most 4,096"):  # refused, never substituted
        parse_aa("random:100000")
    assert str(parse_aa("jittered:16")) == "ssaa:jittered:16"
    assert parse_aa("msaa:4").kind == "msaa" and parse_aa("none").kind == "none"


def test_jitter_moves_the_image_by_the_offset():
    """A jitter of (dx, dy) pixels (x right, y down) moves every projected point by exactly
    that, for perspective and parallel projections."""
    w, h = 80, 60
    p = np.array([0.3, -0.2, 0.4, 1.0])

    def pixel(m, view):
        c = m @ view @ p
        ndc = c[:3] / c[3]
        return (ndc[0] + 1) / 2 * w - 0.5, (1 - ndc[1]) / 2 * h - 0.5

    for cam in (Camera.look_at((1, 2, 5), (0, 0, 0), fov_y=40),
                Camera.look_at((1, 2, 5), (0, 0, 0), ortho_height=3)):
        x0, y0 = pixel(cam.projection(w, h), cam.view)
        x1, y1 = pixel(jitter_matrix(0.25, -0.4, w, h) @ cam.projection(w, h), cam.view)
        assert np.allclose([x1 - x0, y1 - y0], [0.25, -0.4])


def bars(widths=(0.03, 0.012, 0.05, 0.02, 0.008), angles=(7, 23, 41, 66, 83)):
    """Thin slanted white bars on black: the aliasing test scene."""
    scene = Scene(ambient=0.0)
    for i, (angle, width) in enumerate(zip(angles, widths, strict=True)):
        a = np.radians(angle)
        d, n = np.array([np.cos(a), np.sin(a), 0]), np.array([-np.sin(a), np.cos(a), 0])
        c = np.array([-0.6 + 0.3 * i, 0.1 * (i % 2), 0])
        pos = [c - d - n * width, c + d - n * width, c + d + n * width, c - d + n * width]
        scene.add(Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4), Material(color=(1, 1, 1)))
    return scene


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_measured_errors_follow_the_notes(engine):
    """Mean error against a 256-sample grid reference at N = 4, 16, 64: jittered and Poisson
    beat random at equal N, and every pattern beats one centre sample (rasterized, and
    traced: rays through the same points of each pixel)."""
    from facet.render.renderer import Renderer

    scene = bars()
    errors = {}
    with Renderer(S, S, float_color=True) as r:
        def img(aa):
            return r.render(scene, CAMERA, shading="unlit", aa=aa, outputs=("color",),
                            engine=engine).color

        ref = img("ssaa:grid:256")[..., 0]
        centre = np.abs(img("none")[..., 0] - ref).mean()
        for n in (4, 16, 64):
            for name in sampling.PATTERNS:
                errors[name, n] = np.abs(img(f"ssaa:{name}:{n}")[..., 0] - ref).mean()
    for n in (4, 16, 64):
        assert errors["jittered", n] < errors["random", n]
        assert errors["poisson", n] < errors["random", n]
        for name in sampling.PATTERNS:
            assert errors[name, n] < centre
    for name in sampling.PATTERNS:  # more samples, less error
        assert errors[name, 64] < errors[name, 4]


def test_labels_stay_exact_and_sub_pixel_lines_show(renderer):
    """Depth and ids are the centre sample's whatever the colour's supersampling; a line
    0.3 px wide between pixel centres is missed by one sample per pixel and found by 16."""
    r = renderer(S, S)
    scene = bars()
    plain = r.render(scene, CAMERA, shading="unlit")
    ss = r.render(scene, CAMERA, shading="unlit", aa="ssaa:jittered:16")
    assert np.array_equal(plain.object_ids, ss.object_ids)
    assert np.array_equal(plain.depth, ss.depth)
    assert len(np.unique(ss.color[..., 0])) > 10 > len(np.unique(plain.color[..., 0]))
    # A vertical line 0.3 px wide centred between pixel columns 31 and 32 (x = 0 in world).
    px = 2.0 / S
    line = Scene(ambient=0.0)
    pos = [[-0.15 * px, -0.8, 0], [0.15 * px, -0.8, 0], [0.15 * px, 0.8, 0],
           [-0.15 * px, 0.8, 0]]
    line.add(Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4), Material(color=(1, 1, 1)))
    missed = r.render(line, CAMERA, shading="unlit").color[..., 0]
    found = r.render(line, CAMERA, shading="unlit", aa="ssaa:jittered:16").color[..., 0]
    assert missed.max() == 0
    # Every pixel uses the same 16 offsets, so the coverage is exactly the share of offsets
    # that fall within 0.15 px of the boundary (the right edge of 31, the left of 32).
    offsets = sampling.pattern("jittered", 16)[:, 0]
    expected = (np.sum(offsets >= 0.35) + np.sum(offsets < -0.35)) / 16
    column = found[8:-8, 31:33].sum(axis=1) / 255.0  # coverage split over the two columns
    assert expected > 0 and np.allclose(column, expected, atol=1.5 / 255)


def test_cli_aa(tmp_path, capsys):
    from PIL import Image

    from facet.cli import main

    out = tmp_path / "a.png"
    assert main(["render", "--aa", "jittered:16", "--size", "48x36", "-q", "-o", str(out)]) == 0
    smooth = np.asarray(Image.open(out))
    assert main(["render", "--aa", "none", "--size", "48x36", "-q", "-o", str(out)]) == 0
    sharp = np.asarray(Image.open(out))
    assert len(np.unique(smooth.reshape(-1, 3), axis=0)) > len(np.unique(sharp.reshape(-1, 3),
                                                                        axis=0))
    for args, message in ((["--aa", "ssaa:grid:7"], "square number"),
                          (["--aa", "none", "--msaa", "4"], "give one of aa, msaa and spp"),
                          (["--aa", "supersample"], "expected none, msaa:N")):
        assert main(["render", *args, "-o", str(tmp_path / "x.png")]) == 2
        assert message in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()
    (tmp_path / "s.toml").write_text('[render]\naa = "poisson:8"\n[[objects]]\n'
                                     'primitive = "sphere"\n')
    from facet.formats import load_scene

    assert str(load_scene(tmp_path / "s.toml").options["aa"]) == "ssaa:poisson:8"
