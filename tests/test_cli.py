"""The command line: round trips to PNG and depth .npy, and every bad input -> one line on
stderr, exit status 2, no traceback, no output file."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

from facet.cli import main
from facet.geometry.camera import Camera
from facet.render.renderer import Renderer
from facet.scene import DirectionalLight, Material, Mesh, PointLight, Scene, SpotLight

from reference import erode, sphere_reference

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def sphere_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("cli") / "sphere.ply"
    trimesh.creation.icosphere(subdivisions=5).export(path)
    return path


def test_round_trip_png_and_depth(tmp_path, sphere_file, capsys):
    out, depth, ids = tmp_path / "s.png", tmp_path / "d.npy", tmp_path / "i.npy"
    code = main(["render", str(sphere_file), "-o", str(out), "--size", "64x48", "--eye",
                 "0,0,4", "--depth", str(depth), "--ids", str(ids), "--color", "1,0,0",
                 "--light", "dir:0,0,-1", "--msaa", "0", "--background", "0,0,1"])
    assert code == 0
    assert capsys.readouterr().out.split() == [str(out), str(depth), str(ids),
                                               str(tmp_path / "s.json")]
    img = np.asarray(Image.open(out))
    assert img.shape == (48, 64, 3)
    d, i = np.load(depth), np.load(ids)
    assert d.dtype == np.float32 and i.dtype == np.int32
    hit = i == 0
    # Near the centre the sphere's front point is 3 units from the eye, lit head-on: with the
    # default material (ka 1, kd 0.8, ks 0.3) and ambient 0.1, red saturates and green/blue
    # show the white highlight; compare with the exact sphere's shading pixel by pixel.
    assert hit[24, 32] and abs(d[24, 32] - 3.0) < 0.01
    camera = Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=40)
    lights = [DirectionalLight((0, 0, -1))]
    ref, mask, ref_depth = sphere_reference(camera, 64, 48, (0, 0, 0), 1.0,
                                            Material(color=(1, 0, 0)), lights, 0.1)
    inner = erode(mask, 2)
    assert np.abs(img / 255.0 - ref)[inner].max() <= 3 / 255
    assert np.abs(d - ref_depth)[inner].max() < 1e-3
    assert np.all(img[~hit] == [0, 0, 255]) and np.all(d[~hit] == 0)
    assert not list(tmp_path.glob(".*tmp"))  # no temporary files left behind
    umask = os.umask(0)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask  # not mkstemp's private 0600


@pytest.mark.parametrize("extra,lights,shading", [
    (["--ortho", "--shading", "flat"], None, "flat"),
    (["--light", "point:0,2,4:1,1,1:2"], [PointLight((0, 2, 4), intensity=2)], "phong"),
    (["--light", "spot:0,0,4:0,0,-1:1,1,0:1:25", "--shading", "blinn"],
     [SpotLight((0, 0, 4), (0, 0, -1), (1, 1, 0), 1.0, inner_angle=20, outer_angle=25)],
     "blinn"),
    (["--shading", "normals", "--fov", "60", "--target", "0.1,0,0"], None, "normals"),
])
def test_ortho_shading_and_light_kinds(tmp_path, sphere_file, extra, lights, shading):
    """Each flag reaches the render: the CLI's image equals the Python API's render through
    the camera the CLI wrote beside it, with the lights and shading the flags name (the
    default rig when none), and differs from the plain default render."""
    out = tmp_path / "x.png"
    assert main(["render", str(sphere_file), "-o", str(out), "--size", "32x32", "-q",
                 "--msaa", "0", *extra]) == 0
    img = np.asarray(Image.open(out))
    info = json.loads(out.with_suffix(".json").read_text())
    kw = {"ortho_height": info["ortho_height"]} if info["model"] == "orthographic" else \
        {"fov_y": info["fov_y"]}
    camera = Camera(info["world_to_camera_opengl"], near=info["near"], far=info["far"], **kw)
    scene = Scene()
    scene.add(Mesh.load(sphere_file))
    lit = scene.view(lights=lights or [])
    with Renderer(32, 32, msaa=0) as r:
        api = r.render(lit, camera, shading=shading).color[..., :3]
        plain = r.render(scene, camera).color[..., :3]  # the default rig and shading
    assert np.abs(img.astype(int) - api).max() <= 1, extra
    assert np.abs(img.astype(int) - plain).max() > 6, extra  # the flags changed something


def test_default_model_and_python_m(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    res = subprocess.run([sys.executable, "-m", "facet", "render", "-o", "knot.png", "--size",
                          "96x64"], cwd=tmp_path, capture_output=True, text=True, env=env)
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["knot.png", "knot.json"]
    img = np.asarray(Image.open(tmp_path / "knot.png"))
    orange = (img[..., 0] > 120) & (img[..., 2] < img[..., 0] * 0.6)
    assert orange.mean() > 0.1  # the bundled orange torus knot


def test_help_documents_every_option(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["render", "--help"])
    assert exc.value.code == 0
    text = capsys.readouterr().out
    for flag in ("--size", "--eye", "--target", "--up", "--fov", "--ortho", "--light",
                 "--color", "--shading", "--depth", "--background", "--msaa", "-o"):
        assert flag in text
    assert "row 0 at the top" in text and "where the light travels" in text


def test_info(capsys):
    """`facet info` prints, one per line, what a headless context here reports: the same
    keys in order and the same values as the context itself, a GL of at least 3.3; then
    the budgets (budget.NAME lines: tests/test_budgets.py)."""
    import re

    from facet.gl.context import create_headless, describe

    assert main(["info"]) == 0
    rows = [line.split(None, 1) for line in capsys.readouterr().out.strip().splitlines()
            if not line.startswith("budget.")]
    ctx = create_headless()
    try:
        expected = describe(ctx)
    finally:
        ctx.release()
    assert [k for k, _ in rows] == list(expected)
    assert {k: v for k, v in rows} == {k: str(v) for k, v in expected.items()}
    info = dict(rows)
    assert info["backend"] in ("egl", "osmesa")
    major, minor = map(int, re.match(r"(\d+)\.(\d+)", info["version"]).groups())
    assert (major, minor) >= (3, 3) and int(info["max_texture_size"]) >= 2048


BAD = {
    "missing file": (["{tmp}/nope.obj"], "nope.obj: no such file"),
    "directory": (["{tmp}"], "is a directory"),
    "unknown extension": (["{tmp}/mesh.abc"], "unknown mesh format"),
    "garbage mesh": (["{tmp}/garbage.stl"], "cannot read the file"),
    "empty mesh": (["{tmp}/empty.obj"], "0 faces"),
    "nan vertices": (["{tmp}/nan.obj"], "NaN or infinite"),
    "size zero": (["{sphere}", "--size", "0x10"], "width and height must be >= 1"),
    "size too big": (["{sphere}", "--size", "100000x8"], "image width must be between 1 and"),
    "size malformed": (["{sphere}", "--size", "big"], "size: expected two integers [width, "
                       "height] in pixels (WIDTHxHEIGHT), got 'big'"),
    "eye malformed": (["{sphere}", "--eye", "1,2"], "expected 3 comma-separated numbers"),
    "eye nan": (["{sphere}", "--eye", "nan,0,1"], "expected 3 comma-separated numbers"),
    "light kind": (["{sphere}", "--light", "laser:0,0,1"], "light 'laser:0,0,1': expected"),
    "light vector": (["{sphere}", "--light", "dir:0,0"], "expected 3 comma-separated"),
    "light zero": (["{sphere}", "--light", "dir:0,0,0"], "must not be the zero vector"),
    "colour range": (["{sphere}", "--color", "2,0,0"], "must be in [0, 1]"),
    "shading": (["{sphere}", "--shading", "toon"], "unknown shading model 'toon'"),
    "msaa": (["{sphere}", "--msaa", "3"], "msaa must be one of 0, 2, 4, 8, got 3"),
    "output ext": (["{sphere}", "-o", "{tmp}/out.jpgx"], "unsupported image format"),
    "depth ext": (["{sphere}", "--depth", "{tmp}/d.txt"], "written as .npy"),
    "eye equals target": (["{sphere}", "--eye", "0,0,0", "--target", "0,0,0"],
                          "same point"),
    "fov": (["{sphere}", "--fov", "200"], "--fov must be in"),
}


@pytest.mark.parametrize("case", BAD)
def test_bad_input(tmp_path, sphere_file, capsys, case):
    (tmp_path / "mesh.abc").write_text("1 2 3\n")
    (tmp_path / "garbage.stl").write_bytes(b"solid x\nthis is not stl at all\n" * 3)
    (tmp_path / "empty.obj").write_text("v 0 0 0\n")
    (tmp_path / "nan.obj").write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    args, message = BAD[case]
    args = [a.format(tmp=tmp_path, sphere=sphere_file) for a in args]
    if "-o" not in args:
        args += ["-o", str(tmp_path / "out.png")]
    try:
        code = main(["render", *args])
    except SystemExit as exc:  # argparse usage errors
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2
    assert message in err, err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err
    assert not list(tmp_path.glob("out*")) and not list(tmp_path.glob("*.npy"))
    assert not list(tmp_path.glob("*.json"))
    assert not list(tmp_path.glob(".*tmp"))


def test_console_script_and_no_traceback_from_a_real_process(tmp_path):
    """The installed `facet` entry point, run as a user would, on a bad file."""
    exe = Path(sys.executable).parent / "facet"
    if not exe.exists():
        pytest.skip("facet console script not installed in this environment")
    res = subprocess.run([str(exe), "render", str(tmp_path / "none.obj"), "-o",
                          str(tmp_path / "o.png")], capture_output=True, text=True)
    assert res.returncode == 2
    assert res.stderr.startswith("facet: error: ") and "Traceback" not in res.stderr
    assert not (tmp_path / "o.png").exists()


def test_out_dir_writes_every_channel(tmp_path, sphere_file, capsys):
    out = tmp_path / "renders"
    code = main(["render", str(sphere_file), "--size", "48x40", "--eye", "0,0,4",
                 "--outputs", "color,depth,ids,normals,position,uv", "--out-dir", str(out),
                 "--png16", "--normals-space", "camera"])
    assert code == 0
    names = {Path(p).name for p in capsys.readouterr().out.split()}
    assert names == {"color.png", "depth.npy", "depth.png", "depth_mm.png", "ids.npy",
                     "ids.png", "normals.npy", "normals.png", "position.npy", "uv.npy",
                     "uv.png", "camera.json"}
    from facet.image.png import decode_png

    depth, ids = np.load(out / "depth.npy"), np.load(out / "ids.npy")
    hit = ids == 0
    mm = decode_png((out / "depth_mm.png").read_bytes())
    assert np.array_equal(mm[hit], np.rint(depth[hit] * 1000).astype(np.uint16))
    assert np.all(mm[~hit] == 0)
    n = np.load(out / "normals.npy")
    assert n.shape == (40, 48, 3) and n[20, 24, 2] > 0.99  # camera space: facing us
    n16 = decode_png((out / "normals.png").read_bytes())
    assert n16.dtype == np.uint16 and abs(int(n16[20, 24, 2]) - 65535) < 400
    preview = np.asarray(Image.open(out / "depth.png").convert("RGB"))
    assert preview.shape == (40, 48, 3) and np.all(preview[~hit] == 0)
    assert len(np.unique(preview[hit].reshape(-1, 3), axis=0)) > 5  # a visible ramp
    info = json.loads((out / "camera.json").read_text())
    assert info["width"] == 48 and info["height"] == 40 and len(info["K"]) == 3
    pos = np.load(out / "position.npy")
    assert np.allclose(np.linalg.norm(pos[hit], axis=1), 1, atol=0.01)


def test_bits_and_dithering_from_the_cli(tmp_path, sphere_file):
    """Each quantisation flag gives what facet.image.quantize computes from the same render
    at 16 bits (the float colour), and keeps several levels (not a blank image)."""
    from facet.image import quantize
    from facet.image.png import decode_png

    base = ["render", str(sphere_file), "--size", "32x32", "-q", "--msaa", "0"]
    assert main([*base, "-o", str(tmp_path / "f.png"), "--bits", "16"]) == 0
    exact = decode_png((tmp_path / "f.png").read_bytes())
    assert exact.dtype == np.uint16 and exact.shape == (32, 32, 3)
    rgb = exact / 65535.0
    for extra, expected in (
        (["--bits", "3", "--dither", "bayer4"],
         quantize.reduce_bits(rgb, (3,), "bayer4", grey=True)),
        (["--bits", "5,6,5", "--dither", "floyd-steinberg"],
         quantize.reduce_bits(rgb, (5, 6, 5), "floyd-steinberg")),
        (["--palette", "6"], quantize.palette(rgb, 6, "median-cut", "none")),
    ):
        out = tmp_path / "q.png"
        assert main([*base, "-o", str(out), *extra]) == 0
        image = np.asarray(Image.open(out))
        assert image.shape == expected.shape, extra
        # The 16-bit file rounds the float colour: a rare pixel may dither the other way.
        assert (image == expected).mean() > 0.98, extra
        assert len(np.unique(image.reshape(len(image), 32, -1)[..., 0])) >= 3, extra


@pytest.mark.parametrize("args,message", [
    (["--outputs", "color,albedo", "--out-dir", "{tmp}/r"], "unknown output channel 'albedo'"),
    (["--outputs", "depth"], "--outputs needs --out-dir"),
    (["--out-dir", "{tmp}/r", "-o", "{tmp}/x.png"], "leave out -o"),
    (["--bits", "12"], "each 1..8"),
    (["--palette", "1"], "choose 2..256"),
])
def test_bad_output_options(tmp_path, sphere_file, capsys, args, message):
    args = [a.format(tmp=tmp_path) for a in args]
    code = main(["render", str(sphere_file), *args])
    err = capsys.readouterr().err
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "r").exists() and not list(tmp_path.glob("*.png"))


def test_list_uniforms_keeps_its_columns(tmp_path, capsys):
    """--list-uniforms: the kind column starts at one place on every line, array types
    included (a uniform array pushed its line's kind two places right)."""
    shader = tmp_path / "u.frag"
    shader.write_text("uniform float u_gain[4];\nuniform vec3 u_tint;\n"
                      "void mainImage(out vec4 c, in vec2 p) {\n"
                      "    c = vec4(u_tint * u_gain[1] + u_gain[3], 1.0) + iTime;\n}\n")
    assert main(["shader", str(shader), "--list-uniforms"]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if line.strip()]
    starts = {max(line.find("user (--uniform)"), line.find("filled by facet")) for line in lines}
    assert len(lines) >= 3 and len(starts) == 1, lines


def test_help_says_what_facet_is(capsys):
    """`facet --help` names the three engines and shaders (it said "meshes with Phong
    shading", which facet outgrew)."""
    with pytest.raises(SystemExit):
        main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "Phong shading" not in text
    assert "path tracer" in text and "ray tracer" in text and "shaders" in text
