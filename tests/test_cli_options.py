"""Command-line behaviour shared by the subcommands: render options from flags and scene files
reach every kind of output (single images, turntables, datasets), negative values, unknown
options, the MSAA policy, and the cameras written beside sequences."""

import json
import re
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from PIL import Image

from facet.cli import main
from facet.geometry.camera import Camera

ROOT = Path(__file__).resolve().parents[1]
SHADOW_SCENE = """
[render]
size = [64, 48]
{extra}
[[objects]]
primitive = "plane"
size = 6
[[objects]]
primitive = "sphere"
radius = 0.6
transform = [{{translate = [0, 0.8, 0]}}]
[[lights]]
type = "directional"
direction = [-0.2, -1, -0.1]
[cameras.c]
type = "perspective"
eye = [0, 4, 4]
target = [0, 0, 0]
"""


def _shadow_scene(tmp_path, extra="msaa = 0"):
    path = tmp_path / "s.toml"
    path.write_text(SHADOW_SCENE.format(extra=extra))
    return path


def _png(path) -> np.ndarray:
    return np.asarray(Image.open(path)).astype(int)


def test_turntables_keep_the_shadows_of_flags_and_scene_files(tmp_path, capsys):
    """`--turntable` renders with the same options as a single image: frame 0 of a
    turntable equals the single render, shadows included, whether they come from
    `--shadows` or from the scene file's [render] table."""
    plain = _shadow_scene(tmp_path)
    assert main(["render", str(plain), "-o", str(tmp_path / "none.png"), "-q"]) == 0
    none = _png(tmp_path / "none.png")
    for name, args in (("flag", [str(plain), "--shadows"]),
                       ("file", [str(_shadow_scene(tmp_path, "msaa = 0\nshadows = true"))])):
        single, frames = tmp_path / f"{name}.png", tmp_path / f"{name}-{{:02d}}.png"
        assert main(["render", *args, "-o", str(single), "-q"]) == 0
        assert main(["render", *args, "--turntable", "4", "-o", str(frames), "-q"]) == 0
        one, first = _png(single), _png(str(frames).format(0))
        assert np.array_equal(one, first), name
        darker = (none - one)[..., :3].max(axis=2) > 40  # the ball's shadow on the plane
        assert darker.sum() > 40, name
    assert main(["render", str(_shadow_scene(tmp_path, "msaa = 0\nshadows = true")),
                 "--no-shadows",
                 "-o", str(tmp_path / "off.png"), "-q"]) == 0
    assert np.array_equal(_png(tmp_path / "off.png"), none)  # a flag beats the file


def test_datasets_use_the_same_options(tmp_path):
    path = _shadow_scene(tmp_path, "shadows = true\naa = \"jittered:4\"")
    assert main(["render", str(path), "-o", str(tmp_path / "one.png"), "-q"]) == 0
    assert main(["render", str(path), "--out-dir", str(tmp_path / "ds"), "-q"]) == 0
    assert np.array_equal(_png(tmp_path / "one.png"), _png(tmp_path / "ds" / "color.png"))
    assert (tmp_path / "ds" / "depth.npy").is_file()  # the default outputs: colour, depth, ids


@pytest.mark.parametrize("flag", ["--target", "--eye", "--up"])
def test_negative_values_need_no_equals_sign(tmp_path, flag):
    values = {"--target": "-0.5,0,0", "--eye": "-1,0.5,3", "--up": "0,-1,0"}[flag]
    out = tmp_path / "n.png"
    assert main(["render", "--size", "40x30", flag, values, "-o", str(out), "-q"]) == 0
    glued = tmp_path / "g.png"
    assert main(["render", "--size", "40x30", f"{flag}={values}", "-o", str(glued), "-q"]) == 0
    assert np.array_equal(_png(out), _png(glued))
    camera = json.loads(out.with_suffix(".json").read_text())
    if flag == "--eye":
        eye = Camera(camera["world_to_camera_opengl"]).eye
        assert np.allclose(eye, [-1, 0.5, 3])


@pytest.mark.parametrize("argv,message", [
    (["render", "--shadow"], "facet render: error: unknown option --shadow; did you mean "
                             "--shadows? (see facet render --help)"),
    (["view", "--sise", "10x10"], "facet view: error: unknown option --sise; did you mean "
                                  "--size? (see facet view --help)"),
    (["shader", "x.frag", "--chanel0", "a.png"], "did you mean --channel0?"),
    (["render", "a.obj", "b.obj"], "facet render: error: unexpected argument 'b.obj'"),
])
def test_unknown_options_get_a_did_you_mean(capsys, argv, message):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1, err


def test_msaa_beyond_the_gl_is_clamped_with_one_warning(tmp_path, capsys):
    from facet.gl.context import create_headless

    ctx = create_headless()
    max_samples = ctx.max_samples
    ctx.release()
    if max_samples >= 8:
        pytest.skip(f"this GL offers {max_samples} samples: nothing to clamp")
    scene = _shadow_scene(tmp_path, "msaa = 8")
    for args in (["--msaa", "8"], [str(scene)]):
        out = tmp_path / "m.png"
        assert main(["render", *args, "--size", "32x24", "-o", str(out), "-q"]) == 0
        err = capsys.readouterr().err.strip().splitlines()
        assert err == [f"facet: warning: msaa:8 is more than {_renderer()} supports (max "
                       f"{max_samples} samples); using msaa:{max_samples}"], err
    with pytest.raises(SystemExit):
        main(["render", "--help"])
    assert "lowered to it with a warning" in " ".join(capsys.readouterr().out.split())


def _renderer() -> str:
    from facet.gl.context import create_headless

    ctx = create_headless()
    try:
        return ctx.info["GL_RENDERER"]
    finally:
        ctx.release()


@pytest.mark.parametrize("target,json_name", [("spin.gif", "spin.json"),
                                              ("frames/{:04d}.png", "frames/cameras.json"),
                                              ("out/f_{:03d}.png", "out/f_cameras.json")])
def test_sequences_write_every_frames_camera(tmp_path, monkeypatch, capsys, target,
                                             json_name):
    monkeypatch.chdir(tmp_path)
    assert main(["render", "--turntable", "3", "-o", target, "--size", "32x24"]) == 0
    printed = capsys.readouterr().out.split()
    assert printed[-1] == json_name
    frames = json.loads((tmp_path / json_name).read_text())["frames"]
    assert len(frames) == 3 and frames[0]["width"] == 32
    eyes = [Camera(f["world_to_camera_opengl"]).eye for f in frames]
    assert not np.allclose(eyes[0], eyes[1])  # each frame's own camera, 120 degrees apart
    steps = [np.linalg.norm(eyes[i] - eyes[(i + 1) % 3]) for i in range(3)]
    assert np.allclose(steps, steps[0]) and np.allclose([e[1] for e in eyes], eyes[0][1])


def test_shader_help_examples_exist_and_its_size_default_is_true(capsys):
    with pytest.raises(SystemExit):
        main(["shader", "--help"])
    text = capsys.readouterr().out
    named = set(re.findall(r"glsl/examples/(\w+\.frag)", text))
    examples = {p.name for p in (ROOT / "glsl" / "examples").glob("*.frag")}
    assert named and named <= examples, named - examples
    from facet.cli.shader import DEFAULT_SIZE

    assert f"default {DEFAULT_SIZE[0]}x{DEFAULT_SIZE[1]}" in " ".join(text.split())


def test_the_docs_name_real_examples_and_every_viewer_key():
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    for page in pages:
        for name in re.findall(r"glsl/examples/(\w+\.frag)", page.read_text()):
            assert (ROOT / "glsl" / "examples" / name).is_file(), (page.name, name)
    from facet.viewing.keys import KEYMAP

    viewer = (ROOT / "docs" / "guide" / "viewer.md").read_text()
    for key in KEYMAP:
        if len(key) == 1:
            assert f"`{key}`" in viewer, f"the viewer page's key table lacks {key}"


def test_a_gif_turntable_is_not_black(tmp_path):
    out = tmp_path / "t.gif"
    assert main(["render", "--turntable", "3", "-o", str(out), "--size", "32x24", "-q"]) == 0
    frames = iio.imread(out, index=None).astype(int)
    for frame in frames:  # the model is lit in every frame (the rig turns with the camera)
        model = frame.max(axis=-1) > 0
        assert model.mean() > 0.1 and frame[model].mean() > 60


def test_the_ray_tracer_from_flags_scene_files_and_turntables(tmp_path):
    """--engine trace, [render] engine = "trace" and a turntable all reach the tracer: the
    same pixels from the flag and from the file, frame 0 of a traced turntable equal to the
    traced single image, and a picture that differs from the rasterized one (the tracer's
    default shadows)."""
    plain = _shadow_scene(tmp_path)
    single, raster = tmp_path / "t.png", tmp_path / "r.png"
    assert main(["render", str(plain), "--engine", "trace", "--max-depth", "2", "--spp", "4",
                 "-o", str(single), "-q"]) == 0
    assert main(["render", str(plain), "-o", str(raster), "-q"]) == 0
    traced = _png(single)
    assert np.abs(traced - _png(raster)).max() > 40  # shadows by default when tracing
    filed = _shadow_scene(tmp_path, 'engine = "trace"\nmax_depth = 2\naa = "jittered:4"')
    assert main(["render", str(filed), "-o", str(tmp_path / "f.png"), "-q"]) == 0
    assert np.array_equal(_png(tmp_path / "f.png"), traced)
    frames = tmp_path / "tt-{:02d}.png"
    assert main(["render", str(filed), "--turntable", "3", "-o", str(frames), "-q"]) == 0
    assert np.array_equal(_png(str(frames).format(0)), traced)


@pytest.mark.parametrize("args,message", [
    (["--engine", "photon"], "unknown engine 'photon'"),
    (["--engine", "trace", "--max-depth", "-1"], "max_depth: expected an integer in [0, 16]"),
    (["--engine", "trace", "--spp", "0"], "spp must be an integer >= 1"),
    (["--spp", "4", "--aa", "grid:4"], "give one of aa, msaa and spp"),
])
def test_bad_tracer_flags(tmp_path, capsys, args, message):
    try:
        code = main(["render", *args, "-o", str(tmp_path / "x.png")])
    except SystemExit as exc:  # argparse's own usage errors
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "x.png").exists()
