"""The shader lab as people use it: passes with their own channels, Cube A, samplers,
Shadertoy's defaults, glslViewer / Book of Shaders files, JSON exports and TOML projects,
and every error naming the user's file (real GL, headless; facet.lab)."""

import json
import warnings

import numpy as np
import pytest
from PIL import Image

from facet.cli import main
from facet.errors import FacetWarning, InputError, ShaderError
from facet.lab.project import load_project
from facet.lab.shadertoy import DEFAULT_DATE, ShaderToy
from facet.lab.shadertoy_json import load_shadertoy_json
from facet.scene.environment import face_directions


def write(path, text):
    path.write_text(text)
    return path


# -- passes and channels ---------------------------------------------------------------------
FEEDBACK = {
    # A counts frames: its own last frame + 1/64.
    "a": "void mainImage(out vec4 c, in vec2 p) {"
         " c = texelFetch(iChannel0, ivec2(p), 0) + vec4(1.0 / 64.0); }",
    # B reads A on channel 1 (this frame's) and itself on channel 3 (last frame's).
    "b": "void mainImage(out vec4 c, in vec2 p) {"
         " c = 0.5 * texelFetch(iChannel3, ivec2(p), 0) + texelFetch(iChannel1, ivec2(p), 0); }",
    # The image shows B in red and A in green, from channels 2 and 0.
    "image": "void mainImage(out vec4 c, in vec2 p) { c = vec4(texelFetch(iChannel2,"
             " ivec2(p), 0).r, texelFetch(iChannel0, ivec2(p), 0).r, 0.0, 1.0); }",
}
FEEDBACK_CHANNELS = {"a": {0: "buffer-a"}, "b": {1: "buffer-a", 3: "buffer-b"},
                     "image": {0: "buffer-a", 2: "buffer-b"}}


def _feedback_by_hand(frames: int) -> tuple[float, float]:
    a = b = 0.0
    for _ in range(frames):
        a = a + 1 / 64
        b = 0.5 * b + a
    return b, a


def test_each_pass_reads_its_own_channels(tmp_path):
    files = {k: write(tmp_path / f"{k}.frag", v) for k, v in FEEDBACK.items()}
    with ShaderToy(files["image"], buffers={"a": files["a"], "b": files["b"]},
                   pass_channels=FEEDBACK_CHANNELS, size=(4, 4)) as toy:
        out = toy.render(9 / 60)  # frames 0..9: ten frames
    expected = _feedback_by_hand(10)
    np.testing.assert_allclose(out[..., 0], expected[0], atol=1e-5)
    np.testing.assert_allclose(out[..., 1], expected[1], atol=1e-5)


def test_cube_a_renders_a_cube_map_read_face_by_face(tmp_path):
    cube = write(tmp_path / "cube.frag", """
void mainCubemap(out vec4 c, in vec2 fragCoord, in vec3 rayOri, in vec3 rayDir) {
    c = vec4(rayDir * 0.5 + 0.5, 1.0);
}""")
    image = write(tmp_path / "image.frag", """
void mainImage(out vec4 c, in vec2 p) {
    vec3 d = p.x < 2.0 ? vec3(1, 0, 0) : p.x < 4.0 ? vec3(0, -1, 0) : vec3(0, 0, -1);
    c = texture(iChannel0, d);
}""")
    with ShaderToy(image, cube=cube, channels={0: "cube-a"}, size=(6, 2), cube_size=16) as toy:
        out = toy.render(0.0)
        faces = toy.read_cube()
    expected = face_directions(16) * 0.5 + 0.5  # OpenGL's face order and texel layout
    np.testing.assert_allclose(faces[..., :3], expected, atol=1e-5)
    np.testing.assert_allclose(out[0, 0, :3], [1, 0.5, 0.5], atol=0.05)
    np.testing.assert_allclose(out[0, 2, :3], [0.5, 0, 0.5], atol=0.05)
    np.testing.assert_allclose(out[0, 4, :3], [0.5, 0.5, 0], atol=0.05)


CHECKER = np.array([[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [255, 255, 255]]], np.uint8)
# CHECKER's rows as an image: top row red, green; bottom row blue, white.


@pytest.mark.parametrize("options,u,v,expected", [
    # vflip (default): v = 0 is the image's bottom row (blue, white).
    ("nearest", 0.25, 0.25, [0, 0, 1]),
    ("nearest:noflip", 0.25, 0.25, [1, 0, 0]),
    # Outside [0, 1]: repeat wraps round, clamp holds the edge texel.
    ("nearest:repeat", 1.25, 0.25, [0, 0, 1]),
    ("nearest:clamp", 1.25, 0.25, [1, 1, 1]),
    # Linear filtering halfway between texel centres of the bottom row: the mean.
    ("linear:clamp", 0.5, 0.25, [0.5, 0.5, 1]),
])
def test_sampler_settings(tmp_path, options, u, v, expected):
    Image.fromarray(CHECKER).save(tmp_path / "tex.png")
    image = write(tmp_path / "s.frag", f"""
void mainImage(out vec4 c, in vec2 p) {{ c = texture(iChannel1, vec2({u}, {v})); }}""")
    from facet.lab.project import parse_compact

    _, n, ch = parse_compact(f"1={tmp_path / 'tex.png'}:{options}", "--channel")
    with ShaderToy(image, channels={n: ch}, size=(2, 2)) as toy:
        out = toy.render(0.0)
    np.testing.assert_allclose(out[0, 0, :3], expected, atol=1 / 255)


def test_shadertoy_defaults(tmp_path):
    """HW_PERFORMANCE is 1; a channel given as none is black; buffers clamp (not repeat);
    iDate is the fixed default; the keyboard texture holds the keys' state."""
    a = write(tmp_path / "a.frag",
              "void mainImage(out vec4 c, in vec2 p) { c = vec4(p.x / iResolution.x); }")
    image = write(tmp_path / "image.frag", """
void mainImage(out vec4 c, in vec2 p) {
#if HW_PERFORMANCE == 1
    float hw = 1.0;
#else
    float hw = 0.0;
#endif
    float unset = texture(iChannel2, vec2(0.5)).r + texture(iChannel2, vec2(0.5)).a;
    float edge = texture(iChannel0, vec2(1.3, 0.5)).r;  // past the right edge
    float key = texelFetch(iChannel3, ivec2(65, 0), 0).x;  // 'A' held down
    c = vec4(hw, unset, edge, key);
    if (p.x > 1.0) c = iDate / vec4(4000.0, 12.0, 31.0, 86400.0);
}""")
    with ShaderToy(image, buffers={"a": a}, pass_channels={"image": {0: "buffer-a",
                                                                     2: "none",
                                                                     3: "keyboard"}},
                   size=(8, 2)) as toy:
        out = toy.render(0.0)
        toy.resources.keys[0, 65] = 255
        held = toy.render(0.0)
    assert out[0, 0, 0] == 1.0 and out[0, 0, 1] == 0.0
    assert out[0, 0, 2] == pytest.approx(7.5 / 8, abs=1e-3)  # the last texel, not the first
    assert out[0, 0, 3] == 0.0 and held[0, 0, 3] == 1.0
    d = DEFAULT_DATE
    np.testing.assert_allclose(out[0, 4], [d.year / 4000, (d.month - 1) / 12, d.day / 31, 0],
                               atol=1e-6)


# -- glslViewer / Book of Shaders ------------------------------------------------------------
BOOK = """// The Book of Shaders style
#ifdef GL_ES
precision mediump float;
#endif
uniform vec2 u_resolution;
uniform vec2 u_mouse;
uniform float u_time;

void main() {
    vec2 st = gl_FragCoord.xy / u_resolution.xy;
    gl_FragColor = vec4(st.x, u_time / 10.0, u_mouse.x / 100.0, 1.0);
}
"""
ES3 = """#version 300 es
precision highp float;
uniform vec2 u_resolution;
uniform float u_time;
out vec4 fragColor;
void main() { fragColor = vec4(0.25, gl_FragCoord.y / u_resolution.y, u_time, 1.0); }
"""


def test_glslviewer_and_book_of_shaders_files_run(tmp_path):
    book = write(tmp_path / "book.frag", BOOK)
    with ShaderToy(book, size=(4, 2)) as toy:
        out = toy.render(2.0, mouse=(30, 5, 0, 0))
    np.testing.assert_allclose(out[0, :, 0], (np.arange(4) + 0.5) / 4, atol=1e-6)
    np.testing.assert_allclose(out[0, 0, 1:3], [0.2, 0.3], atol=1e-6)
    es3 = write(tmp_path / "es3.frag", ES3)  # its own #version and out: accepted
    with ShaderToy(es3, size=(2, 4)) as toy:
        out = toy.render(0.5)
    np.testing.assert_allclose(out[:, 0, 1], (np.arange(4)[::-1] + 0.5) / 4, atol=1e-6)
    assert out[0, 0, 0] == 0.25 and out[0, 0, 2] == 0.5


# -- errors ----------------------------------------------------------------------------------
@pytest.mark.parametrize("text,message", [
    ("", "toy.frag: error: the file is empty"),
    ("// only a comment\n", "toy.frag: error: the file is empty"),
    ("float f(float x) { return x; }\n", "no mainImage(...) and no main(): is this a "
     "Shadertoy or a glslViewer shader?"),
    ("void mainImage(out vec4 c, in vec2 p) {\n  c = vec4(\n", "toy.frag:"),
    ("void mainImage(out vec4 c, in vec2 p) {\n  c =\u00a0vec4(1);\n}\n",
     "toy.frag:2:6: error: a no-break space (U+00A0)"),
    ("void main() { float x = 1.0; }\n", "has its own main() but neither gl_FragColor"),
    # the preprocessor's errors (Mesa says "preprocessor error"): on the user's line
    ("void mainImage(out vec4 c, in vec2 p) { c = vec4(1); }\n#if 0\nfoo\n",
     "toy.frag:2:6: error: Unterminated #if"),
    ("void mainImage(out vec4 c, in vec2 p) { c = vec4(1); }\n#endif\n",
     "toy.frag:2:1: error: #endif without #if"),
    ("void mainImage(out vec4 c, in vec2 p) { c = vec4(1); }\n/* never closed\n",
     "it ends early: a /* comment with no */"),
])
def test_errors_name_the_users_file(tmp_path, text, message):
    path = write(tmp_path / "toy.frag", text)
    with pytest.raises(ShaderError) as info:
        ShaderToy(path, size=(4, 4))
    assert message in str(info.value)
    assert "host.frag" not in str(info.value) and "viewer.frag" not in str(info.value)


@pytest.mark.parametrize("text", [
    "\ufeffvoid mainImage(out vec4 c, in vec2 p) { c = vec4(0.5); }\n",  # a BOM
    "#version 300 es\nvoid mainImage(out vec4 c, in vec2 p) { c = vec4(0.5); }\n",
    "#define color vec4(0.5)\n#define main_color color\n"
    "void mainImage(out vec4 c, in vec2 p) { c = main_color; }\n",  # wrapper-like names
    # WebGL 1's extensions, core in GLSL 3.3: Mesa refuses #extension after declarations
    "#extension GL_OES_standard_derivatives : enable\n"
    "void mainImage(out vec4 c, in vec2 p) { c = vec4(0.5 + dFdx(p.x) - 1.0); }\n"
    "#extension GL_EXT_shader_texture_lod : enable\n",
    # an old Mac file's bare carriage returns
    "#define HALF \\\r  0.5\rvoid mainImage(out vec4 c, in vec2 p) {\r c = vec4(HALF); }\r",
])
def test_pasted_quirks_run(tmp_path, text):
    path = write(tmp_path / "toy.frag", text)
    with ShaderToy(path, size=(2, 2)) as toy:
        assert np.allclose(toy.render(0.0)[..., :3], 0.5)


def test_errors_come_first_and_name_their_pass(tmp_path):
    """A warning before an error in the file: the error is the first line (the window's
    title); two passes failing alike each say which pass they are."""
    bad = ("void mainImage(out vec4 c, in vec2 p) {\n"
           "  float unused_x;\n  int i = 1.0;\n  c = vec4(unused_x);\n}\n")
    a = write(tmp_path / "a.frag", bad)
    image = write(tmp_path / "image.frag", bad)
    with pytest.raises(ShaderError) as info:
        ShaderToy(image, buffers={"a": a}, size=(4, 4))
    lines = str(info.value).splitlines()
    assert lines[0].startswith("[Buffer A] ") and ": error:" in lines[0]
    assert any(ln.startswith("[Image] ") and ": error:" in ln for ln in lines)
    heads = [ln for ln in lines if ln.startswith("[")]
    first_warning = next((i for i, ln in enumerate(heads) if "warning" in ln), len(heads))
    assert all("error" in ln for ln in heads[:1]) and first_warning >= 1


def test_a_deleted_file_and_an_include_created_later(tmp_path):
    path = write(tmp_path / "toy.frag",
                 "void mainImage(out vec4 c, in vec2 p) { c = vec4(0.25); }\n")
    with ShaderToy(path, size=(2, 2)) as toy:
        write(path, '#include "later.glsl"\n'
                    "void mainImage(out vec4 c, in vec2 p) { c = vec4(later()); }\n")
        result = toy.reload()
        assert not result.success and 'cannot find include "later.glsl"' in result.errors
        assert not toy.changed()
        write(tmp_path / "later.glsl", "float later() { return 0.75; }\n")
        assert toy.changed()  # creating the missing include is a change
        assert toy.reload().success
        assert np.allclose(toy.render(0.0)[..., :3], 0.75)
        path.unlink()
        result = toy.reload(force=True)
        assert not result.success and "toy.frag: no such shader file" in result.errors
        assert np.allclose(toy.render(0.0)[..., :3], 0.75)  # the last good program runs


# -- JSON exports, TOML projects, the command line -------------------------------------------
def _export(tmp_path):
    """A Shadertoy export: two buffers (B reads A and itself) and a texture in the image."""
    Image.fromarray(np.full((2, 2, 3), 128, np.uint8)).save(tmp_path / "grey.png")
    rp = [
        {"type": "buffer", "name": "Buffer A", "code": FEEDBACK["a"],
         "inputs": [{"id": "4dXGR8", "ctype": "buffer", "channel": 0,
                     "src": "/media/previz/buffer00.png",
                     "sampler": {"filter": "linear", "wrap": "clamp", "vflip": "true"}}],
         "outputs": [{"id": "4dXGR8", "channel": 0}]},
        {"type": "buffer", "name": "Buffer B", "code": FEEDBACK["b"],
         "inputs": [{"id": "4dXGR8", "ctype": "buffer", "channel": 1},
                    {"id": "XsXGR8", "ctype": "buffer", "channel": 3}],
         "outputs": [{"id": "XsXGR8", "channel": 0}]},
        {"type": "image", "name": "Image",
         "code": "void mainImage(out vec4 c, in vec2 p) { c = vec4(texelFetch(iChannel2,"
                 " ivec2(p), 0).r, texelFetch(iChannel0, ivec2(p), 0).r,"
                 " texture(iChannel1, vec2(0.5)).r, 1.0); }",
         "inputs": [{"id": "4dXGR8", "ctype": "buffer", "channel": 0},
                    {"id": "XsXGR8", "ctype": "buffer", "channel": 2},
                    {"id": "tex1", "ctype": "texture", "channel": 1,
                     "src": "/media/a/grey.png",
                     "sampler": {"filter": "mipmap", "wrap": "repeat", "vflip": "true"}}],
         "outputs": [{"id": "4dfGRr", "channel": 0}]},
    ]
    path = tmp_path / "export.json"
    path.write_text(json.dumps({"Shader": {"info": {"name": "test"}, "renderpass": rp}}))
    return path


def test_a_json_export_runs_like_the_same_shader_given_by_flags(tmp_path):
    export = _export(tmp_path)
    project = load_shadertoy_json(export)
    assert set(project.passes) == {"a", "b", "image"}
    with ShaderToy(project=project, size=(4, 4)) as toy:
        from_json = toy.render(9 / 60)
    expected = _feedback_by_hand(10)
    np.testing.assert_allclose(from_json[..., :2], np.broadcast_to(expected, (4, 4, 2)),
                               atol=1e-5)
    np.testing.assert_allclose(from_json[..., 2], 128 / 255, atol=1e-3)
    # The same passes and channels through the command line's flags.
    files = {k: write(tmp_path / f"{k}.frag", v) for k, v in FEEDBACK.items() if k != "image"}
    image = write(tmp_path / "image.frag", project.passes["image"].code)
    outs = {}
    for name, args in {
        "json": [str(export)],
        "flags": [str(image), "--buffer-a", str(files["a"]), "--buffer-b", str(files["b"]),
                  "--channel", "a:0=buffer-a", "--channel", "b:1=buffer-a",
                  "--channel", "b:3=buffer-b", "--channel", "image:0=buffer-a",
                  "--channel", "image:2=buffer-b",
                  "--channel", f"image:1={tmp_path / 'grey.png'}:mipmap:repeat"],
    }.items():
        out = tmp_path / f"{name}.png"
        assert main(["shader", *args, "--time", str(9 / 60), "--fps", "60", "--size", "4x4",
                     "-o", str(out), "-q"]) == 0
        outs[name] = np.asarray(Image.open(out))
    np.testing.assert_array_equal(outs["json"], outs["flags"])


def test_json_export_problems_are_named(tmp_path):
    export = _export(tmp_path)
    (tmp_path / "grey.png").unlink()
    with pytest.raises(InputError, match=r"channel 1 needs the media file 'grey.png'"):
        load_shadertoy_json(export)
    data = json.loads(export.read_text())
    data["Shader"]["renderpass"][2]["inputs"][2] = {"ctype": "music", "channel": 1}
    export.write_text(json.dumps(data))
    with pytest.warns(FacetWarning, match="not supported, left out: music inputs"):
        project = load_shadertoy_json(export)
    assert project.passes["image"].channels[1].kind == "none"  # black
    (tmp_path / "junk.json").write_text("{}")
    with pytest.raises(InputError, match="not a Shadertoy JSON export"):
        load_shadertoy_json(tmp_path / "junk.json")


def test_a_toml_project(tmp_path):
    for k, v in FEEDBACK.items():
        write(tmp_path / f"{k}.frag", v)
    toml = write(tmp_path / "toy.toml", """
[buffer-a]
shader = "a.frag"
channels = { 0 = "buffer-a" }
[buffer-b]
shader = "b.frag"
channels = { 1 = "buffer-a", 3 = { source = "buffer-b", filter = "nearest" } }
[image]
shader = "image.frag"
channels = { 0 = "buffer-a", 2 = "buffer-b" }
""")
    with ShaderToy(project=load_project(toml), size=(4, 4)) as toy:
        out = toy.render(9 / 60)
    np.testing.assert_allclose(out[0, 0, :2], _feedback_by_hand(10), atol=1e-5)
    write(toml, '[image]\nshader = "image.frag"\nchanels = {}\n')
    with pytest.raises(InputError, match="unknown key 'chanels' .*did you mean 'channels'"):
        load_project(toml)


def test_dates_are_fixed_headless_and_nan_pixels_are_reported(tmp_path, capsys):
    clock = write(tmp_path / "clock.frag",
                  "void mainImage(out vec4 c, in vec2 p) { c = vec4(fract(iDate.w / 7.0)); }")
    outs = []
    for i in range(2):
        out = tmp_path / f"c{i}.png"
        assert main(["shader", str(clock), "--time", "1", "--size", "4x4", "-o", str(out),
                     "-q"]) == 0
        outs.append(np.asarray(Image.open(out)))
    np.testing.assert_array_equal(outs[0], outs[1])
    out = tmp_path / "d.png"
    assert main(["shader", str(clock), "--date", "2024-05-01T00:00:03.5", "--size", "4x4",
                 "-o", str(out), "-q"]) == 0
    assert abs(int(np.asarray(Image.open(out))[0, 0, 0]) - round(0.5 * 255)) <= 1
    assert main(["shader", str(clock), "--date", "May 1st", "-o", str(out)]) == 2
    assert "--date 'May 1st'" in capsys.readouterr().err
    nan = write(tmp_path / "nan.frag", "void mainImage(out vec4 c, in vec2 p) {"
                " c = p.x < 2.0 ? vec4(sqrt(-p.x - 1.0)) : vec4(0.5); }")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no numpy warning leaks
        assert main(["shader", str(nan), "--size", "4x4", "-o", str(out)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "8 pixels are NaN or infinite" in err[0]
    assert (np.asarray(Image.open(out))[:, :2] == 0).all()


def test_a_cube_map_texture_channel(tmp_path):
    """A folder of six faces (px nx py ny pz nz, each one colour) as a cube channel: each
    axis direction samples its face."""
    colours = {"px": (255, 0, 0), "nx": (0, 255, 255), "py": (0, 255, 0),
               "ny": (255, 0, 255), "pz": (0, 0, 255), "nz": (255, 255, 0)}
    folder = tmp_path / "faces"
    folder.mkdir()
    for name, rgb in colours.items():
        Image.fromarray(np.full((4, 4, 3), rgb, np.uint8)).save(folder / f"{name}.png")
    image = write(tmp_path / "s.frag", """
void mainImage(out vec4 c, in vec2 p) {
    vec3 dirs[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0),
                           vec3(0, 0, 1), vec3(0, 0, -1));
    c = texture(iChannel3, dirs[int(p.x)]);
}""")
    with ShaderToy(image, channels={3: f"cube:{folder}"}, size=(6, 1)) as toy:
        out = toy.render(0.0)
    expected = np.array(list(colours.values())) / 255.0
    np.testing.assert_allclose(out[0, :, :3], expected, atol=1e-3)


# -- volumes (sampler3D) -----------------------------------------------------------------------
VOLUME_READER = """
void mainImage(out vec4 c, in vec2 p) {
    ivec3 t = ivec3(int(p.x), int(p.y), 1);  // texel (x, y, 1) of a 4 x 2 x 3 volume
    vec4 fetched = texelFetch(iChannel0, t, 0);
    vec4 sampled = texture(iChannel0, (vec3(t) + 0.5) / iChannelResolution[0]);
    c = p.y < 1.0 ? vec4(fetched.rgb, iChannelResolution[0].z / 10.0) : sampled;
}"""


def _volume(tmp_path, channels, dtype=np.uint8):
    from facet.lab.volumes import write_volume

    rng = np.random.default_rng(3)
    texels = rng.integers(0, 256, (3, 2, 4, channels)).astype(dtype)  # z, y, x, c
    if dtype == np.float32:
        texels /= 255
    write_volume(tmp_path / "v.bin", texels)
    return tmp_path / "v.bin", texels


@pytest.mark.parametrize("channels,dtype", [(4, np.uint8), (1, np.uint8), (3, np.float32)])
def test_a_volume_channel_is_a_sampler3d_holding_the_files_texels(tmp_path, channels, dtype):
    """Shadertoy's .bin volumes: x fastest, then y, then z; one-channel volumes read (r, 0,
    0, 1) as R8 textures do on Shadertoy; iChannelResolution holds the depth."""
    path, texels = _volume(tmp_path, channels, dtype)
    shader = write(tmp_path / "vol.frag", VOLUME_READER)
    from facet.lab.project import channel

    volume = channel(f"volume:{path}", "test", filter="nearest")
    with ShaderToy(shader, channels={0: volume}, size=(4, 2)) as toy:
        img = toy.render(0.0)[::-1]  # row 0: fragCoord.y = 0.5
    scale = 255.0 if dtype == np.uint8 else 1.0
    rgba = np.zeros((2, 4, 4))  # texels (x, y, 1) as GL reads them: missing g, b 0, a 1
    rgba[..., 3] = 1.0
    rgba[..., :channels] = texels[1] / scale
    np.testing.assert_allclose(img[0, :, :3], rgba[0, :, :3], atol=1e-6)  # texelFetch
    np.testing.assert_allclose(img[0, :, 3], 0.3, atol=1e-6)  # iChannelResolution[0].z
    np.testing.assert_allclose(img[1], rgba[1], atol=1e-6)  # texture() at texel centres


def test_an_exports_volume_inputs_read_the_file_or_facets_stand_in(tmp_path):
    """ctype volume: the media file when it is there; Shadertoy's built-in noise volumes by
    their ids, with one warning line that facet's numbers differ; a wrong file is one error."""
    grey_id = "27012b4eadd0c3ce12498b867058e4f717ce79e5c91b6b2b1f3a2c0c1c6e8a9"
    path, texels = _volume(tmp_path, 4)
    code = ("void mainImage(out vec4 c, in vec2 p) { c = vec4(texelFetch(iChannel0, "
            "ivec3(0), 0).r, texelFetch(iChannel1, ivec3(0), 0).gba); }")
    rp = [{"type": "image", "name": "Image", "code": code,
           "inputs": [{"id": "v1", "ctype": "volume", "channel": 0,
                       "src": f"/media/a/{grey_id}.bin",
                       "sampler": {"filter": "mipmap", "wrap": "repeat", "vflip": "true"}},
                      {"id": "v2", "ctype": "volume", "channel": 1, "src": "/media/a/v.bin"}],
           "outputs": [{"id": "4dfGRr", "channel": 0}]}]
    export = tmp_path / "export.json"
    export.write_text(json.dumps({"Shader": {"renderpass": rp}}))
    with pytest.warns(FacetWarning) as caught:
        project = load_shadertoy_json(export)
    lines = [str(w.message) for w in caught]
    assert len(lines) == 1 and "Image channel 0 is Shadertoy's grey noise volume" in lines[0]
    from facet.lab.volumes import noise_volume

    with ShaderToy(project=project, size=(1, 1)) as toy:
        pixel = toy.render(0.0)[0, 0]
    np.testing.assert_allclose(pixel, [noise_volume("grey")[0, 0, 0, 0] / 255,
                                       *texels[0, 0, 0, 1:] / 255], atol=1e-6)
    (tmp_path / "v.bin").write_bytes((tmp_path / "v.bin").read_bytes()[:-1])  # cut short
    with pytest.raises(InputError, match=r"v\.bin: its header says 4 x 2 x 3 x 4 texels "
                                         r"\(96 bytes\) but it holds 95"):
        with pytest.warns(FacetWarning, match="stand-in"):
            project = load_shadertoy_json(export)
        with ShaderToy(project=project, size=(1, 1)):
            pass
    rp[0]["inputs"][1]["src"] = "/media/a/other.bin"
    export.write_text(json.dumps({"Shader": {"renderpass": rp}}))
    with pytest.raises(InputError, match=r"inputs\[1\]\.src: channel 1: a volume input needs "
                                         r"the media file 'other\.bin'"):
        load_shadertoy_json(export)


def test_volume_files_from_the_command_line(tmp_path, capsys):
    path, _ = _volume(tmp_path, 1)
    shader = write(tmp_path / "vol.frag", VOLUME_READER)
    out = tmp_path / "v.png"
    assert main(["shader", str(shader), "--channel", f"image:0=volume:{path}:nearest",
                 "--size", "4x2", "-o", str(out), "-q"]) == 0
    _, texels = _volume(tmp_path, 1)
    sampled = np.asarray(Image.open(out))[0, :, 0].astype(int)  # top row: fragCoord.y 1.5
    np.testing.assert_allclose(sampled, texels[1, 1, :, 0], atol=1)  # the file's texels
    (tmp_path / "bad.bin").write_bytes(b"PNG" + bytes(40))
    assert main(["shader", str(shader), "--channel0", f"volume:{tmp_path / 'bad.bin'}",
                 "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "bad.bin: not a Shadertoy volume file" in err and "Traceback" not in err
    assert not (tmp_path / "x.png").exists()
    assert main(["shader", str(shader), "--channel0", "grey-noise3d", "--size", "4x2",
                 "-o", str(out), "-q"]) == 0


def test_an_export_whose_code_has_bare_carriage_returns_runs(tmp_path):
    """Code in an export keeps the newlines it was typed with: an old Mac's bare CRs are
    newlines, as in a file read as text (they were one line: no mainImage was found)."""
    code = "#define HALF \\\r  0.5\rvoid mainImage(out vec4 c, in vec2 p) {\r c = vec4(HALF); }\r"
    rp = [{"type": "image", "name": "Image", "code": code, "inputs": [],
           "outputs": [{"id": "4dfGRr", "channel": 0}]}]
    export = write(tmp_path / "cr.json", json.dumps({"Shader": {"renderpass": rp}}))
    with ShaderToy(project=load_shadertoy_json(export), size=(2, 2)) as toy:
        assert np.allclose(toy.render(0.0)[..., :3], 0.5)
