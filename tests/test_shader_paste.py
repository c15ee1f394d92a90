"""What people paste into the shader lab runs as it runs where they found it (real GL,
headless): Shadertoy's code-golf entry points made by macros, branches Shadertoy never
takes, uniform arrays the compiler shortens, exports whose passes are named "Buf A",
textures from --media, glslViewer's buffers, WebGL's zero-initialised variables; a channel
read with nothing bound is said in one warning line; what animates is known."""

import json
import warnings

import numpy as np
import pytest
from PIL import Image

from facet.cli import main
from facet.errors import FacetWarning, ShaderError
from facet.lab.shadertoy import ShaderToy
from facet.lab.shadertoy_json import load_shadertoy_json

W, H = 16, 8


def _run(tmp_path, text, name="s.frag", **kw):
    path = tmp_path / name
    path.write_text(text)
    with ShaderToy(path, size=(W, H), **kw) as st:
        return st.render(1.0)


@pytest.mark.parametrize("text", [
    # code golf: no function at all, the wrapper's call goes through the macro
    "#define mainImage(O,u) O = vec4((u) / iResolution.xy, .5, 1)\n",
    "void f(out vec4 O, vec2 u) { O = vec4(u / iResolution.xy, .5, 1.); }\n"
    "#define mainImage(O,u) f(O,u)\n",
    "#define M mainImage\nvoid M(out vec4 O, vec2 u) { O = vec4(u / iResolution.xy, .5, 1.); }\n",
    # a main() in branches Shadertoy never takes (GRIMOIRE, #if 0)
    "#ifdef GRIMOIRE\nout vec4 o;\nvoid main() { o = vec4(1.0); }\n#endif\n"
    "#if 0\nvoid main() {}\n#endif\n"
    "void mainImage(out vec4 O, in vec2 u) { O = vec4(u / iResolution.xy, .5, 1.); }\n",
])
def test_entry_points_are_found_after_the_preprocessor(tmp_path, text):
    img = _run(tmp_path, text)
    x = (np.arange(W) + 0.5) / W
    assert np.allclose(img[H // 2, :, 0], x, atol=1e-5) and np.allclose(img[..., 2], 0.5)


@pytest.mark.parametrize("text", [
    "void mainImage(out vec4 O, in vec2 u) { O = vec4(u.x / 16.0, 0.0, 0.5, 1.0); }\n"
    "void main() { vec4 c; mainImage(c, gl_FragCoord.xy); }\n",
    "void mainImage(out vec4 O, in vec2 u) { O = vec4(u.x / 16.0, 0.0, 0.5, 1.0); }\n"
    "#ifdef GL_ES\nvoid main(void) { vec4 c; mainImage(c, gl_FragCoord.xy); }\n#endif\n",
])
def test_a_main_next_to_main_image_is_renamed_as_shadertoy_does(tmp_path, text):
    """A pass that defines main() as well as mainImage() (buffer passes exported with a
    main that calls mainImage): Shadertoy's compiler takes it (its wrapper renames the
    file's main), so facet does too, and draws what mainImage draws."""
    img = _run(tmp_path, text)
    x = (np.arange(W) + 0.5) / W
    assert np.allclose(img[H // 2, :, 0], x * W / 16.0, atol=1e-5) and \
        np.allclose(img[..., 2], 0.5)


def test_uniform_arrays_the_compiler_shortened(tmp_path):
    """Reading iChannelResolution[0] (the compiler keeps one element of four) and
    iChannelTime[0] crashed with "pack expected 3 items"."""
    Image.fromarray(np.zeros((8, 24, 3), np.uint8)).save(tmp_path / "t.png")
    img = _run(tmp_path, "void mainImage(out vec4 O, in vec2 u) { O = vec4("
                         "iChannelResolution[0].xy / 100.0, iChannelTime[0], 1.0); }\n",
               channels={0: tmp_path / "t.png"})
    assert np.allclose(img[0, 0, :3], [0.24, 0.08, 1.0], atol=1e-6)


def test_webgl_zero_initialises_what_is_declared_without_a_value(tmp_path):
    img = _run(tmp_path, "void mainImage(out vec4 O, in vec2 u) {\n  vec3 color;\n  float k;\n"
                         "  for (int i = 0; i < 4; i++) { color += vec3(0.1, 0.2, 0.05); "
                         "k += 0.1; }\n  O = vec4(color + k, 1.0);\n}\n")
    assert np.allclose(img[H // 2, W // 2, :3], [0.8, 1.2, 0.6], atol=1e-5)


GRADIENT = "O = vec4(u / iResolution.xy, .5, 1.);"


@pytest.mark.parametrize("text", [
    # KDE shader wallpaper: a mainImage() overload over the globals its header declares
    "void mainImage(out vec4 O, in vec2 u) { " + GRADIENT + " }\n"
    "void mainImage() {\n  vec4 color = vec4(0.0);\n  mainImage(color, fragCoord);\n"
    "  fragColor = color;\n}\n",
    # only the overload: facet fills fragCoord and takes fragColor
    "void mainImage() { vec2 u = fragCoord; vec4 O; " + GRADIENT + " fragColor = O; }\n",
    "void mainImage(void) { fragColor = vec4(fragCoord / iResolution.xy, .5, 1.); }\n",
])
def test_the_kde_wallpaper_dialect_runs(tmp_path, text):
    """Shaders shared from KDE's shader wallpaper (Abstract_Liquid, Slug_Ring of the
    corpus) define ``void mainImage()`` over global fragCoord / fragColor: they failed
    to compile ("variable of type error")."""
    img = _run(tmp_path, text)
    x = (np.arange(W) + 0.5) / W
    assert np.allclose(img[H // 2, :, 0], x, atol=1e-5) and np.allclose(img[..., 2], 0.5)


def test_the_kde_wallpapers_desktop_inputs_are_an_empty_desktop(tmp_path):
    """iWindowCount, iWindowRects, iVirtualDesktopCount, iMousePrev ... (plasma_windows of
    the corpus failed: undeclared): declared when used, a desktop of no windows, one
    virtual desktop, the cursor where iMouse is."""
    path = tmp_path / "s.frag"
    path.write_text("void mainImage(out vec4 O, in vec2 u) {\n  float lit = 0.0;\n"
                    "  for (int i = 0; i < iWindowCount; i++) lit += iWindowRects[i].z;\n"
                    "  O = vec4(lit + float(iScreenCount), float(iVirtualDesktopCount), "
                    "iMousePrev.x / 10.0 + iVirtualDesktopAnim, 1.0);\n}\n")
    with ShaderToy(path, size=(W, H)) as st:
        img = st.render(1.0, mouse=(5.0, 3.0, 0.0, 0.0))
    assert np.allclose(img[0, 0], [0.0, 1.0, 0.5, 1.0], atol=1e-6)


def test_a_desktop_input_the_shader_or_its_common_file_declares_is_not_declared_again(
        tmp_path):
    own = "uniform int iWindowCount;\nvoid mainImage(out vec4 O, in vec2 u) { " \
          "O = vec4(float(iWindowCount + iVirtualDesktop), 0.25, 0.0, 1.0); }\n"
    assert np.allclose(_run(tmp_path, own)[0, 0], [0.0, 0.25, 0.0, 1.0])
    (tmp_path / "common.glsl").write_text("uniform int iWindowCount;\n"
                                          "float windows() { return float(iWindowCount); }\n")
    img = _run(tmp_path, "void mainImage(out vec4 O, in vec2 u) { "
                         "O = vec4(windows() + float(iWindowCount), 0.5, 0.0, 1.0); }\n",
               common=tmp_path / "common.glsl")
    assert np.allclose(img[0, 0], [0.0, 0.5, 0.0, 1.0])


def _export(tmp_path, names, media_file="noise.png"):
    """A Shadertoy export: Buffer A (named names[0]) keeps adding 1/255, Image shows it
    and a texture."""
    passes = [
        {"name": names[0], "type": "buffer", "outputs": [{"id": "4dXGR8", "channel": 0}],
         "inputs": [{"id": "4dXGR8", "channel": 0, "type": "buffer", "src": ""}],
         "code": "void mainImage(out vec4 c, in vec2 p) { c = texelFetch(iChannel0, "
                 "ivec2(p), 0) + vec4(1.0 / 255.0); }"},
        {"name": names[1], "type": "image", "outputs": [{"id": "4sXGR8", "channel": 0}],
         "inputs": [{"id": "4dXGR8", "channel": 0, "type": "buffer", "src": ""},
                    {"id": "XsX3Rn", "channel": 1, "type": "texture",
                     "src": f"/media/a/{media_file}"}],
         "code": "void mainImage(out vec4 c, in vec2 p) { c = vec4(texelFetch(iChannel0, "
                 "ivec2(p), 0).r, texture(iChannel1, vec2(0.5)).g, 0.0, 1.0); }"},
    ]
    path = tmp_path / "export.json"
    path.write_text(json.dumps({"Shader": {"info": {"name": "t"}, "renderpass": passes}}))
    return path


@pytest.mark.parametrize("names", [("Buf A", "Image"), ("Buffer A", "Image"), ("", "")])
def test_exports_map_passes_by_type_and_output_id(tmp_path, names):
    media = tmp_path / "textures"
    media.mkdir()
    Image.fromarray(np.full((4, 4, 3), (0, 200, 0), np.uint8)).save(media / "noise.png")
    path = _export(tmp_path, names)
    project = load_shadertoy_json(path, media)
    assert set(project.passes) == {"a", "image"}
    with ShaderToy(project=project, size=(W, H)) as st:  # reloads re-read it with media
        img = st.render(9 / 60)  # frames 0..9
        assert st.reload(force=True).success
    assert np.allclose(img[0, 0, :2], [10 / 255, 200 / 255], atol=1e-3)
    out = tmp_path / "f.png"
    assert main(["shader", str(path), "--media", str(media), "--time", "0", "--size",
                 f"{W}x{H}", "-o", str(out), "-q"]) == 0
    assert np.asarray(Image.open(out))[0, 0, 1] == 200


GLSLVIEWER = """
#ifdef GL_ES
precision mediump float;
#endif
uniform vec2 u_resolution;
uniform float u_time;
uniform sampler2D u_buffer0;
uniform sampler2D u_doubleBuffer0;

void main() {
    vec2 st = gl_FragCoord.xy / u_resolution;
#if defined(BUFFER_0)
    gl_FragColor = vec4(0.25, 0.0, 0.0, 1.0);
#elif defined(DOUBLE_BUFFER_0)
    gl_FragColor = texture2D(u_doubleBuffer0, st) + vec4(0.0, 1.0 / 255.0, 0.0, 0.0);
#else
    gl_FragColor = vec4(texture2D(u_buffer0, st).r, texture2D(u_doubleBuffer0, st).g,
                        0.5, 1.0);
#endif
}
"""


def test_glslviewer_buffers_and_double_buffers(tmp_path):
    path = tmp_path / "multi.frag"
    path.write_text(GLSLVIEWER)
    with ShaderToy(path, size=(W, H)) as st:
        assert [p.name for p in st.project.ordered()] == ["BUFFER_0", "DOUBLE_BUFFER_0",
                                                         "Image"]
        img = st.render(4 / 60)  # frames 0..4: the double buffer adds 1/255 five times
    assert np.allclose(img[H // 2, W // 2, :3], [0.25, 5 / 255, 0.5], atol=1e-4)


def test_a_channel_read_with_nothing_bound_reads_noise_and_says_so(tmp_path, capsys):
    """Most pasted shaders that read an unset iChannel want Shadertoy's noise texture:
    they get facet's (the same every run; mean 1/2, spread over the bytes), with one
    warning line; `none` asks for black, an image for itself, without a word."""
    text = "void mainImage(out vec4 O, in vec2 u) { O = texelFetch(iChannel2, ivec2(u) % 4, 0); }\n"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        noise, again = _run(tmp_path, text), _run(tmp_path, text)
    said = [str(w.message) for w in caught if issubclass(w.category, FacetWarning)]
    assert len(said) == 2 and said[0].endswith("s.frag reads iChannel2, which nothing is "
                                               "bound to: it reads facet's noise texture "
                                               "(Shadertoy's RGBA Noise Medium stand-in); "
                                               "give --channel2 SOURCE, or none for black")
    assert np.array_equal(noise, again) and abs(noise.mean() - 0.5) < 0.15
    assert noise[..., 0].std() > 0.2
    Image.fromarray(np.full((4, 4, 3), 51, np.uint8)).save(tmp_path / "t.png")
    for channel, value in (("none", 0.0), (tmp_path / "t.png", 0.2)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            img = _run(tmp_path, text, channels={2: channel})
        assert not [w for w in caught if issubclass(w.category, FacetWarning)]
        assert np.allclose(img[..., :3], value, atol=1e-3)
    out = tmp_path / "o.png"
    assert main(["shader", str(tmp_path / "s.frag"), "--size", "8x8", "-o", str(out)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("facet: warning: ") and "iChannel2" in err[0]


@pytest.mark.parametrize("text,animated,mouse", [
    ("void mainImage(out vec4 O, in vec2 u) { O = vec4(u.x); }", False, False),
    ("void mainImage(out vec4 O, in vec2 u) { O = vec4(sin(iTime)); }", True, False),
    ("void mainImage(out vec4 O, in vec2 u) { O = vec4(iMouse.x); }", False, True),
    ("uniform vec2 u_resolution;\nuniform float u_time;\n"
     "void main() { gl_FragColor = vec4(u_time); }", True, False),
])
def test_what_animates_is_known(tmp_path, text, animated, mouse):
    path = tmp_path / "s.frag"
    path.write_text(text + "\n")
    with ShaderToy(path, size=(W, H)) as st:
        assert (st.animated, st.reads_mouse) == (animated, mouse)


def test_feedback_buffers_animate(tmp_path):
    a = tmp_path / "a.frag"
    a.write_text("void mainImage(out vec4 c, in vec2 p) { c = texture(iChannel0, p) + 0.1; }\n")
    image = tmp_path / "i.frag"
    image.write_text("void mainImage(out vec4 c, in vec2 p) { c = texture(iChannel0, p); }\n")
    with ShaderToy(image, buffers={"a": a}, channels={0: "buffer-a"}, size=(W, H)) as st:
        assert st.animated and not st.reads_mouse


def test_a_channel_sampled_with_a_direction_is_bound_as_a_cube_map(tmp_path):
    """A channel nothing was given for that the code samples with a vec3 (a cube map in
    the original shader): bound as a (black) cube map, with one warning line naming it;
    before, facet bound its 2D noise texture and the compiler refused texture(sampler2D,
    vec3). A channel the user gave as an image stays an error (their choice)."""
    import warnings

    from facet.errors import FacetWarning

    text = ("void mainImage(out vec4 O, in vec2 u) {\n"
            "    vec3 d = normalize(vec3(u / 8.0 - 1.0, 1.0));\n"
            "    O = vec4(texture(iChannel2, d).rgb + vec3(0.25, 0.5, 0.75), 1.0);\n}\n")
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        img = _run(tmp_path, text)
    lines = [str(w.message) for w in said if issubclass(w.category, FacetWarning)]
    assert len(lines) == 1 and "iChannel2" in lines[0] and "cube" in lines[0], lines
    np.testing.assert_allclose(img[..., :3], np.broadcast_to([0.25, 0.5, 0.75], img[..., :3].shape),
                               atol=1e-5)  # black + that
    Image.fromarray(np.zeros((4, 4, 3), np.uint8)).save(tmp_path / "t.png")
    with pytest.raises(ShaderError, match=r"texture\(sampler2D, vec3\)"):
        _run(tmp_path, text, channels={2: str(tmp_path / "t.png")})
