"""Full-screen shaders: Shadertoy inputs, multi-pass feedback, channels, user uniforms and
hot reload that never breaks what runs (real GL, headless)."""

import time

import numpy as np
import pytest
from PIL import Image

from facet.errors import InputError, ShaderError
from facet.lab.shadertoy import ShaderToy

W, H = 40, 24


def write(path, text):
    path.write_text(text)
    # Content hashing decides reloads; make sure the file system sees a change too.
    time.sleep(0.01)
    return path


INPUTS = """
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    if (fragCoord.x < 1.0) { fragColor = vec4(iResolution.xy / 100.0, iTime / 10.0, 1.0); }
    else if (fragCoord.x < 2.0) { fragColor = vec4(float(iFrame) / 1000.0, iMouse.xy / 100.0,
                                                   1.0); }
    else if (fragCoord.x < 3.0) { fragColor = vec4(iMouse.zw / 100.0, iTimeDelta, 1.0); }
    else { fragColor = vec4(fragCoord / iResolution.xy, 0.0, 1.0); }
}
"""


def test_shadertoy_inputs(tmp_path):
    path = write(tmp_path / "inputs.frag", INPUTS)
    with ShaderToy(path, size=(W, H)) as st:
        img = st.render(2.5, fps=30, mouse=(12, 7, 3, -4))
    left = img[-1]  # fragCoord origin: bottom-left, i.e. the image's last row
    assert np.allclose(left[0, :3], [W / 100, H / 100, 0.25], atol=1e-6)
    assert np.allclose(left[1, :3], [75 / 1000, 0.12, 0.07], atol=1e-6)  # frame 75 at 30 fps
    assert np.allclose(left[2, :3], [0.03, -0.04, 1 / 30], atol=1e-6)
    # Orientation: fragCoord.y grows upwards, so the top row holds the largest y.
    assert img[0, 10, 1] > 0.9 and img[-1, 10, 1] < 0.1


def test_multipass_feedback(tmp_path):
    """Buffer A adds 1/255 per frame to its own previous frame; the image shows A. After N
    frames (0 .. N-1) the value is N/255."""
    a = write(tmp_path / "a.frag", """
void mainImage(out vec4 c, in vec2 p) {
    c = texelFetch(iChannel0, ivec2(p), 0) + vec4(1.0 / 255.0);
}""")
    image = write(tmp_path / "image.frag", """
void mainImage(out vec4 c, in vec2 p) { c = texture(iChannel0, p / iResolution.xy); }""")
    with ShaderToy(image, buffers={"a": a}, channels={0: "buffer-a"}, size=(8, 8)) as st:
        out = st.render(29 / 60)  # frames 0..29 at 60 fps: 30 frames
        assert np.allclose(out, 30 / 255, atol=1e-5)
        out = st.render(9 / 60)  # earlier time: starts again from frame 0
        assert np.allclose(out, 10 / 255, atol=1e-5)


def test_passes_that_feed_no_later_frame_are_drawn_on_the_frame_shown_only(tmp_path):
    """A headless frame at t runs every frame before it for a buffer that feeds back (A
    reads itself), but buffers that read only this frame's inputs (B: this frame's A; C:
    iTime and iFrame) and the Image pass are drawn once: the picture is the same, the work
    of a slow shader up to 31 times less."""
    a = write(tmp_path / "a.frag", """
void mainImage(out vec4 c, in vec2 p) {
    c = texelFetch(iChannel0, ivec2(p), 0) + vec4(1.0 / 255.0);
}""")
    b = write(tmp_path / "b.frag", """
void mainImage(out vec4 c, in vec2 p) { c = 2.0 * texelFetch(iChannel0, ivec2(p), 0); }""")
    c = write(tmp_path / "c.frag", """
void mainImage(out vec4 c, in vec2 p) { c = vec4(iTime, float(iFrame) / 100.0, 0.0, 1.0); }""")
    image = write(tmp_path / "image.frag", """
void mainImage(out vec4 c, in vec2 p) {
    c = vec4(texelFetch(iChannel0, ivec2(p), 0).x, texelFetch(iChannel1, ivec2(p), 0).xy,
             1.0);
}""")
    with ShaderToy(image, buffers={"a": a, "b": b, "c": c},
                   channels={0: "buffer-b", 1: "buffer-c"},
                   pass_channels={"a": {0: "buffer-a"}, "b": {0: "buffer-a"}},
                   size=(4, 4)) as st:
        out = st.render(1.0, fps=30)  # frames 0..30
        assert st.draws == 31 + 3  # A every frame; B, C and the image once
        assert np.allclose(out[..., 0], 2 * 31 / 255, atol=1e-5)  # A's 31 frames
        assert np.allclose(out[..., 1:3], [1.0, 0.30], atol=1e-5)  # C at frame 30, t = 1
        st.restart()
        st.draws = 0
        for frame in range(31):  # a window's frames: every pass, every frame
            st.step(frame / 30, 1 / 30, fps=30)
        assert st.draws == 31 * 4 and np.allclose(st.read(), out, atol=1e-6)


def test_common_file_and_image_channel(tmp_path):
    common = write(tmp_path / "common.glsl", "vec3 tint(vec3 c) { return c * 0.5; }\n")
    shader = write(tmp_path / "s.frag", """
void mainImage(out vec4 c, in vec2 p) {
    c = vec4(tint(texture(iChannel1, p / iResolution.xy).rgb), 1.0);
    c.a = iChannelResolution[1].x / 100.0;
}""")
    pixels = np.full((4, 6, 3), 200, np.uint8)
    Image.fromarray(pixels).save(tmp_path / "img.png")
    with ShaderToy(shader, common=common, channels={1: tmp_path / "img.png"},
                   size=(W, H)) as st:
        out = st.render(0.0)
    assert np.allclose(out[..., :3], 100 / 255, atol=1e-3)
    assert np.allclose(out[..., 3], 0.06)


def test_hot_reload_end_to_end(tmp_path):
    """Write, render; rewrite, detect, reload, new pixels; break it (error at the right
    file:line, through a nested include), old pixels stay; fix it, recover."""
    lib = tmp_path / "lib"
    lib.mkdir()
    write(lib / "inner.glsl", "vec3 base() { return vec3(0.2, 0.4, 0.6); }\n")
    write(lib / "outer.glsl", '#include "inner.glsl"\nvec3 shade() { return base(); }\n')
    path = write(tmp_path / "live.frag", '#include "lib/outer.glsl"\n'
                 "void mainImage(out vec4 c, in vec2 p) { c = vec4(shade(), 1.0); }\n")
    with ShaderToy(path, size=(W, H)) as st:
        assert np.allclose(st.render()[5, 5, :3], [0.2, 0.4, 0.6], atol=1e-6)
        assert st.reload().changed is False
        write(lib / "inner.glsl", "vec3 base() { return vec3(0.9, 0.1, 0.0); }\n")
        assert st.changed()
        result = st.reload()
        assert result.success and result.changed
        assert np.allclose(st.render()[5, 5, :3], [0.9, 0.1, 0.0], atol=1e-6)
        write(lib / "inner.glsl", "// broken on line 2\nvec3 base() { return vec3(oops); }\n")
        result = st.reload()
        assert not result.success
        first = result.errors.splitlines()[0]
        assert "lib/inner.glsl:2:" in first and "oops" in first, first
        assert np.allclose(st.render()[5, 5, :3], [0.9, 0.1, 0.0], atol=1e-6)  # kept
        write(lib / "inner.glsl", "vec3 base() { return vec3(0.0, 1.0, 0.0); }\n")
        assert st.reload().success
        assert np.allclose(st.render()[5, 5, :3], [0.0, 1.0, 0.0], atol=1e-6)


def test_user_uniforms_survive_reload(tmp_path):
    path = write(tmp_path / "u.frag", "uniform vec3 u_color;\nuniform int u_steps;\n"
                 "void mainImage(out vec4 c, in vec2 p) { c = vec4(u_color * float(u_steps) "
                 "/ 8.0, 1.0); }\n")
    with ShaderToy(path, size=(8, 8)) as st:
        st.set_uniform("u_color", (1, 0.5, 0))
        st.set_uniform("u_steps", 4)
        assert np.allclose(st.render()[0, 0, :3], [0.5, 0.25, 0])
        write(path, path.read_text().replace("/ 8.0", "/ 4.0"))
        assert st.reload().success
        assert np.allclose(st.render()[0, 0, :3], [1.0, 0.5, 0])
        uniforms = st.active_uniforms()
        assert uniforms == {"u_color": ("vec3", 1, False), "u_steps": ("int", 1, False)}
        with pytest.raises(InputError, match="no user uniform named 'u_colour'.*u_color"):
            st.set_uniform("u_colour", 1)
        with pytest.raises(InputError, match="u_color is vec3: expected 3"):
            st.set_uniform("u_color", (1, 2))
        with pytest.raises(InputError, match="u_steps is int: expected integers"):
            st.set_uniform("u_steps", 2.5)


def test_bad_shaders(tmp_path):
    with pytest.raises(InputError, match="no such shader"):
        ShaderToy(tmp_path / "none.frag")
    bad = write(tmp_path / "bad.frag", "void mainImage(out vec4 c, in vec2 p) {\n  c = 1;\n}\n")
    with pytest.raises(ShaderError, match=r"bad\.frag:2:\d+: error"):
        ShaderToy(bad, size=(8, 8))
    binary = tmp_path / "blob.frag"
    binary.write_bytes(b"\xff\xfe\x00binary")
    with pytest.raises(ShaderError, match="not a text file"):
        ShaderToy(binary, size=(8, 8))
    cyc = write(tmp_path / "cyc.frag", '#include "cyc2.glsl"\n')
    write(tmp_path / "cyc2.glsl", '#include "cyc.frag"\n')
    with pytest.raises(ShaderError, match="cycle"):
        ShaderToy(cyc, size=(8, 8))
    ok = write(tmp_path / "ok.frag", "void mainImage(out vec4 c, in vec2 p) { c = vec4(1); }\n")
    with pytest.raises(InputError, match="cannot read the texture image"):
        write(tmp_path / "notimage.png", "text")
        ShaderToy(ok, channels={0: tmp_path / "notimage.png"}, size=(8, 8))


WAVE = """
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec2 uv = fragCoord / iResolution.xy;
    fragColor = vec4(uv, 0.5 + 0.5 * sin(iTime), 1.0);
}
"""


def test_cli_frames_and_sequences(tmp_path, capsys):
    import imageio.v3 as iio

    from facet.cli import main

    shader = write(tmp_path / "wave.frag", WAVE)
    assert main(["shader", str(shader), "--time", "1.5", "--size", "32x16", "-o",
                 str(tmp_path / "f.png")]) == 0
    img = np.asarray(Image.open(tmp_path / "f.png"))
    assert img.shape == (16, 32, 3)
    assert abs(int(img[0, 0, 2]) - round((0.5 + 0.5 * np.sin(1.5)) * 255)) <= 1
    assert img[0, -1, 0] > 240 and img[0, -1, 1] > 240  # top-right: uv = (1, 1)
    for out in ("w.gif", "w.mp4", "seq/{:03d}.png"):
        assert main(["shader", str(shader), "--time", "0:1", "--fps", "8", "--size", "32x16",
                     "-q", "-o", str(tmp_path / out)]) == 0
    frames = iio.imread(tmp_path / "w.gif", index=None)
    assert frames.shape == (8, 16, 32, 3)
    assert len(list((tmp_path / "seq").glob("*.png"))) == 8
    assert iio.imread(tmp_path / "w.mp4", index=None).shape[0] == 8
    # Deterministic: the same range renders the same frames.
    assert main(["shader", str(shader), "--time", "0:1", "--fps", "8", "--size", "32x16",
                 "-q", "-o", str(tmp_path / "again.gif")]) == 0
    assert np.array_equal(iio.imread(tmp_path / "again.gif", index=None), frames)
    capsys.readouterr()
    uni = write(tmp_path / "u.frag", "uniform vec3 u_tint;\nvoid mainImage(out vec4 c, in vec2 "
                "p) { c = vec4(u_tint * iTime, 1.0); }\n")
    assert main(["shader", "--list-uniforms", str(uni)]) == 0
    listing = capsys.readouterr().out
    assert "u_tint" in listing and "user" in listing and "iTime" in listing


@pytest.mark.parametrize("args,message", [
    (["{dir}/none.frag", "-o", "{dir}/x.png"], "no such shader"),
    (["{dir}/wave.frag", "--uniform", "u_nope=1", "-o", "{dir}/x.png"],
     "no user uniform named 'u_nope'"),
    (["{dir}/wave.frag", "--uniform", "broken", "-o", "{dir}/x.png"], "expected NAME=VALUE"),
    (["{dir}/wave.frag", "--time", "4:1", "-o", "{dir}/x.gif"], "--time '4:1'"),
    (["{dir}/wave.frag", "--time", "0:1", "-o", "{dir}/x.avi"], "written as .gif, .mp4"),
    (["{dir}/wave.frag", "--channel0", "{dir}/none.png", "-o", "{dir}/x.png"],
     "no such texture file"),
    (["{dir}/wave.frag", "--channel0", "buffer-b", "-o", "{dir}/x.png"], "no buffer-b"),
    (["{dir}/broken.frag", "-o", "{dir}/x.png"], "broken.frag:2:"),
])
def test_cli_bad_input(tmp_path, capsys, args, message):
    from facet.cli import main

    write(tmp_path / "wave.frag", WAVE)
    write(tmp_path / "broken.frag", "void mainImage(out vec4 c, in vec2 p) {\n  c = nope;\n}\n")
    code = main(["shader", *[a.format(dir=tmp_path) for a in args]])
    err = capsys.readouterr().err
    assert code == 2 and message in err and "Traceback" not in err
    assert not list(tmp_path.glob("x.*"))
