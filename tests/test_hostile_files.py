"""Hostile files of every other kind (OBJ side files, scene files, shaders and their
includes, images, manifests, view plans, command-line values): each is one line and exit 2
from a child process under a memory limit, or a correct render where the input is valid;
never a hang, a signal or a traceback (facet.guard, facet.budgets)."""

import json
import os

import pytest

from hostile import facet, png_header, refused

CUBE = """v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
"""


@pytest.fixture
def fifo(tmp_path):
    """A named pipe nobody writes to: a reader that opens it waits for ever (the child's
    timeout then fails the test)."""
    path = tmp_path / "pipe"
    os.mkfifo(path)
    return path


def _ok(result):
    code, err = result
    assert code == 0 and "Traceback" not in err, (code, err[-2000:])


def _render(tmp_path, model, *extra):
    return facet("render", model, "-o", tmp_path / "out.png", "--size", "24x16", *extra,
                 cwd=tmp_path)


def _sparse(path, size=3 << 30):
    with open(path, "wb") as f:
        f.truncate(size)
    return path


# -- OBJ side files ------------------------------------------------------------------------
@pytest.mark.parametrize("line, crlf", [("# mtllib pipe", False), ("mtllib pipe", True),
                                        ("mtllib \\\n pipe", False), ("MTLLIB pipe", False)])
def test_obj_material_libraries_that_are_fifos(tmp_path, fifo, line, crlf):
    text = line + "\n" + CUBE
    (tmp_path / "m.obj").write_bytes((text.replace("\n", "\r\n") if crlf else text).encode())
    code, err = _render(tmp_path, "m.obj")
    assert "Traceback" not in err and code in (0, 2), (code, err)
    if code == 2:
        refused((code, err), "pipe")


def test_obj_texture_that_is_a_fifo_uppercase_map_kd(tmp_path, fifo):
    (tmp_path / "m.mtl").write_text("newmtl a\nKd 1 1 1\nMAP_KD pipe\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nusemtl a\nvt 0 0\nvt 1 0\nvt 1 1\n" +
                                    CUBE.replace("f 1 3 2", "f 1/1 3/2 2/3"))
    code, err = _render(tmp_path, "m.obj")
    assert "Traceback" not in err and code in (0, 2), (code, err)


def test_a_sparse_3_gib_obj_is_refused_by_its_size(tmp_path):
    refused(_render(tmp_path, _sparse(tmp_path / "big.obj")), "GiB", "budget")


# -- scene files ---------------------------------------------------------------------------
def test_a_scene_with_100k_objects_is_one_line(tmp_path):
    (tmp_path / "s.toml").write_text('[[objects]]\nprimitive = "cube"\n' * 100_000)
    refused(_render(tmp_path, "s.toml"), "objects", "budget")


def test_a_long_parent_chain_listed_in_reverse(tmp_path):
    n = 20_000
    text = "".join(f'[[objects]]\nname = "o{i}"\nprimitive = "cube"\nparent = "o{i - 1}"\n'
                   for i in range(n - 1, 0, -1)) + '[[objects]]\nname = "o0"\nprimitive = "cube"\n'
    (tmp_path / "s.toml").write_text(text)
    refused(_render(tmp_path, "s.toml"), "levels deep", "budget")
    # Within the budget (and in reverse order) the chain is fine, in linear time.
    text = "".join(f'[[objects]]\nname = "o{i}"\nprimitive = "sphere"\nparent = "o{i - 1}"\n'
                   "transform = [{translate = [0.001, 0, 0]}]\n" for i in range(500, 0, -1))
    (tmp_path / "s.toml").write_text(text + '[[objects]]\nname = "o0"\nprimitive = "cube"\n')
    _ok(_render(tmp_path, "s.toml"))


# -- shaders -------------------------------------------------------------------------------
FRAG = "void mainImage(out vec4 c, in vec2 p) { c = vec4(p.x / iResolution.x); }\n"


def _shader(tmp_path, source, *extra):
    (tmp_path / "s.frag").write_text(source)
    return facet("shader", "s.frag", "-o", tmp_path / "out.png", "--size", "8x8", *extra,
                 cwd=tmp_path)


def test_includes_that_are_fifos_devices_or_sparse(tmp_path, fifo):
    refused(_shader(tmp_path, '#include "pipe"\n' + FRAG), "pipe", "named pipe")
    refused(_shader(tmp_path, '#include "/dev/zero"\n' + FRAG), "/dev/zero", "device")
    _sparse(tmp_path / "big.glsl")
    refused(_shader(tmp_path, '#include "big.glsl"\n' + FRAG), "big.glsl", "budget")


def test_an_include_chain_3000_deep(tmp_path):
    for i in range(3000):
        (tmp_path / f"i{i}.glsl").write_text(f'#include "i{i + 1}.glsl"\n')
    (tmp_path / "i3000.glsl").write_text("\n")
    refused(_shader(tmp_path, '#include "i0.glsl"\n' + FRAG), "deep", "budget")


def test_a_5_mb_shader_is_refused_before_the_compiler(tmp_path):
    body = "float f(float x) { return x * 1.0001; }\n"
    refused(_shader(tmp_path, "// " + "x" * (5 << 20) + "\n" + FRAG), "budget")
    refused(_shader(tmp_path, body.replace("f(", "g(") + "\n".join(
        f"float f{i}(float x) {{ return x + {i}.0; }}" for i in range(150_000)) + FRAG),
        "budget")


def test_common_and_list_uniforms_on_fifos(tmp_path, fifo):
    refused(_shader(tmp_path, FRAG, "--common", "pipe"), "pipe", "named pipe")
    refused(facet("shader", "--list-uniforms", "pipe", cwd=tmp_path), "pipe")
    (tmp_path / "p.toml").write_text('common = "pipe"\n[image]\nshader = "s.frag"\n')
    (tmp_path / "s.frag").write_text(FRAG)
    refused(facet("shader", "p.toml", "-o", "o.png", "--size", "8x8", cwd=tmp_path), "pipe")


# -- images and environments ---------------------------------------------------------------
def test_a_13000_square_environment_is_refused_before_decoding(tmp_path):
    (tmp_path / "m.obj").write_text(CUBE)
    (tmp_path / "env.png").write_bytes(png_header(13000, 13000))
    refused(_render(tmp_path, "m.obj", "--env", "env.png"), "env.png", "budget")


def test_render_sizes_beyond_the_pixel_budget(tmp_path):
    (tmp_path / "m.obj").write_text(CUBE)
    refused(facet("render", "m.obj", "--size", "16384x16384", "-o", "o.png", cwd=tmp_path),
            "16384x16384", "megapixels", "--budget pixels")
    refused(facet("shader", "s.frag", "--size", "16384x16384", "-o", "o.png", cwd=tmp_path),
            "megapixels")
    (tmp_path / "m.jsonl").write_text('{"model": "m.obj", "size": [16384, 16384]}\n')
    refused(facet("batch", "m.jsonl", "-o", "ds", cwd=tmp_path), "megapixels")
    assert not (tmp_path / "o.png").exists() and not (tmp_path / "ds").exists()


def test_a_raised_budget_meets_the_gl_and_says_so_in_one_line(tmp_path):
    """Past the budget, on the user's word, a GL that cannot make the framebuffer (here:
    under the test's 3 GiB memory limit) is one line naming the likely cause."""
    (tmp_path / "s.frag").write_text(FRAG)
    refused(facet("--budget", "pixels=300000000", "shader", "s.frag", "--size",
                  "16384x16384", "-o", "o.png", cwd=tmp_path), "out of memory", "--size")


# -- command-line values -------------------------------------------------------------------
def test_empty_outputs_and_absurd_frame_rates(tmp_path):
    (tmp_path / "m.obj").write_text(CUBE)
    (tmp_path / "s.frag").write_text(FRAG)
    refused(facet("render", "m.obj", "-o", "", cwd=tmp_path), "empty output path")
    refused(facet("shader", "s.frag", "-o", "", cwd=tmp_path), "empty output path")
    refused(facet("batch", "m.obj", "-o", "", cwd=tmp_path), "empty output path")
    refused(facet("render", "m.obj", "--turntable", "3", "--fps", "1e-9", "-o", "t.gif",
                  cwd=tmp_path), "--fps")
    refused(facet("shader", "s.frag", "--time", "0:1", "--fps", "1e-9", "-o", "t.gif",
                  cwd=tmp_path), "--fps")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.obj", "s.frag"]


def test_non_ascii_digits_and_unknown_users(tmp_path):
    (tmp_path / "m.obj").write_text(CUBE)
    (tmp_path / "s.frag").write_text(FRAG)
    refused(facet("render", "m.obj", "--size", "١٠٠x١٠٠", "-o", "o.png", cwd=tmp_path),
            "WIDTHxHEIGHT")
    refused(facet("shader", "s.frag", "--channel", "²=noise", "-o", "o.png", cwd=tmp_path),
            "0-3")
    refused(facet("batch", "m.obj", "--views", "sphere:²", "-o", "ds", cwd=tmp_path),
            "--views")
    refused(facet("shader", "s.frag", "--channel", "0=~nosuchuser_facet/x.png", "-o",
                  "o.png", cwd=tmp_path), "nosuchuser_facet")


def test_control_characters_in_paths_are_escaped_in_messages(tmp_path):
    line = refused(facet("render", "a\x1b[31m\rb\nc.obj", cwd=tmp_path))
    assert "\\x1b[31m\\rb\\nc.obj" in line
    assert "\x1b" not in line and "\r" not in line


# -- manifests and view plans --------------------------------------------------------------
def test_manifests_nested_deep_or_with_nul_bytes(tmp_path):
    (tmp_path / "m.obj").write_text(CUBE)
    (tmp_path / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    refused(facet("batch", "deep.json", "-o", "ds", cwd=tmp_path), "levels deep", "budget")
    (tmp_path / "deep.jsonl").write_text('{"model": ' + "[" * 100_000 + "]" * 100_000 + "}\n")
    refused(facet("batch", "deep.jsonl", "-o", "ds", cwd=tmp_path), "levels deep", "budget")
    (tmp_path / "nul.jsonl").write_text(json.dumps({"model": "m\0.obj"}) + "\n")
    refused(facet("batch", "nul.jsonl", "-o", "ds", cwd=tmp_path), "model")
    assert not (tmp_path / "ds").exists()


TRANSFORM = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 3], [0, 0, 0, 1]]


@pytest.mark.parametrize("fields, fragment", [
    ({"fl_x": 0}, "fl_x"), ({"fl_x": 1e-320}, "field of view"),
    ({"camera_angle_x": 1e-300}, "field of view"), ({"fl_x": 50, "w": 0}, "w and h"),
    ({"fl_x": 50, "w": 10**6, "h": 10**6}, "megapixels")])
def test_view_plan_files_with_absurd_cameras(tmp_path, fields, fragment):
    (tmp_path / "m.obj").write_text(CUBE)
    (tmp_path / "t.json").write_text(json.dumps({"w": 32, "h": 24, **fields, "frames": [
        {"file_path": "a", "transform_matrix": TRANSFORM}]}))
    (tmp_path / "m.jsonl").write_text('{"model": "m.obj", "views": {"plan": "cameras", '
                                      '"file": "t.json"}}\n')
    refused(facet("batch", "m.jsonl", "-o", "ds", cwd=tmp_path), fragment)


@pytest.mark.parametrize("views, fragment", [
    ({"plan": "random", "count": 2, "seed": -1}, "seed"),
    ({"plan": "random", "count": 2, "seed": 1.5}, "seed"),
    ({"count": True}, "count"), ({"elevation": float("nan")}, "elevation"),
    ({"elevations": "ab"}, "elevations"), ({"plan": "cameras", "file": 7}, "file")])
def test_view_plans_with_wrong_types(tmp_path, views, fragment):
    (tmp_path / "m.obj").write_text(CUBE)
    (tmp_path / "m.jsonl").write_text(json.dumps({"model": "m.obj", "views": views}) + "\n")
    refused(facet("batch", "m.jsonl", "-o", "ds", cwd=tmp_path), f"views.{fragment}")


def test_a_glob_through_symlink_loops_ends(tmp_path):
    d = tmp_path / "d"
    d.mkdir()
    (d / "m.obj").write_text(CUBE)
    for name, target in (("up", ".."), ("up2", ".."), ("here", ".")):
        (d / name).symlink_to(target)
    _ok(facet("batch", "d/**/*.obj", "-o", "ds", "--views", "1", "--size", "8x8", "-q",
              cwd=tmp_path, timeout=60))
    assert [json.loads(x)["model"] for x in (tmp_path / "ds/index.jsonl").read_text()
            .splitlines()] == ["d/m.obj"]
