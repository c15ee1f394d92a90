"""GLSL sources: include expansion and its line table (no GL), and compile errors mapped to
the right file and line through includes (real GL)."""

import re

import pytest

from facet.errors import ShaderError
from facet.gl.glsl_source import expand, glsl_root


def _write(root, files):
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root


def test_include_expands_once_and_maps_lines(tmp_path):
    _write(tmp_path, {
        "a.frag": '#version 330 core\n#include "lib/b.glsl"\n#include "lib/b.glsl"\n'
                  "void main(){}\n",
        "lib/b.glsl": '// b line 1\n#include "c.glsl"\nfloat b() { return c(); }\n',
        "lib/c.glsl": "float c() { return 1.0; }\n",
    })
    src = expand(tmp_path / "a.frag", {"FOO": 2})
    lines = src.text.splitlines()
    assert lines[0] == "#version 330 core"
    assert lines[1] == "#define FOO 2"
    assert src.text.count("float c()") == 1 and src.text.count("float b()") == 1
    # Every expanded line maps back to its own file and line.
    for i, text in enumerate(lines, start=1):
        path, line = src.locate(i)
        if path == "<defines>":
            continue
        original = (tmp_path / path).read_text().splitlines() if not path.startswith("/") \
            else open(path).read().splitlines()
        assert original[line - 1] == text
    assert src.locate(lines.index("float c() { return 1.0; }") + 1)[1] == 1
    assert src.locate(len(lines))[1] == 4  # "void main(){}" is line 4 of a.frag


def test_include_cycle_shows_the_chain(tmp_path):
    _write(tmp_path, {"a.frag": '#version 330 core\n#include "x.glsl"\n',
                      "x.glsl": '#include "y.glsl"\n', "y.glsl": '\n#include "x.glsl"\n'})
    with pytest.raises(ShaderError, match=r"cycle: .*a\.frag -> .*x\.glsl -> .*y\.glsl -> "
                                          r".*x\.glsl"):
        expand(tmp_path / "a.frag")


def test_missing_include_names_the_including_file_and_line(tmp_path):
    _write(tmp_path, {"a.frag": '#version 330 core\n#include "ok.glsl"\n',
                      "ok.glsl": '// fine\n\n#include "nope.glsl"\n'})
    with pytest.raises(ShaderError, match=r'ok\.glsl:3:11: error: cannot find include '
                                          r'"nope\.glsl"'):
        expand(tmp_path / "a.frag")


def test_version_rules(tmp_path):
    _write(tmp_path, {"a.frag": "void main(){}\n",
                      "b.frag": '#version 330 core\n#include "v.glsl"\n',
                      "v.glsl": "#version 330 core\n"})
    with pytest.raises(ShaderError, match=r"a\.frag:1:1: error: .*#version"):
        expand(tmp_path / "a.frag")
    with pytest.raises(ShaderError, match=r"v\.glsl:1:1: error: #version belongs on line 1"):
        expand(tmp_path / "b.frag")
    with pytest.raises(ShaderError, match="no such shader file"):
        expand(tmp_path / "missing.frag")


def test_bundled_shaders_found_and_library_is_uniform_free():
    root = glsl_root()
    assert (root / "mesh" / "phong.frag").is_file()
    lighting = (root / "lib" / "lighting.glsl").read_text()
    code = "\n".join(line.split("//")[0] for line in lighting.splitlines())
    assert not re.search(r"\buniform\b", code)  # pure functions only (design rule)


def test_compile_error_reported_at_included_file_and_line(tmp_path, renderer):
    from facet.gl.shaders import compile_program

    _write(tmp_path, {
        "s.vert": "#version 330 core\nin vec3 in_position;\n"
                  "void main() { gl_Position = vec4(in_position, 1.0); }\n",
        "s.frag": '#version 330 core\n#include "lib/outer.glsl"\nout vec4 c;\n'
                  "void main() { c = vec4(shade(), 1.0); }\n",
        "lib/outer.glsl": '// outer\n#include "inner.glsl"\nvec3 shade() { return inner(); }\n',
        "lib/inner.glsl": "// inner: the bug is on line 3\n\n"
                          "vec3 inner() { return vec3(undefined_thing); }\n",
    })
    ctx = renderer(16, 16).ctx
    with ctx, pytest.raises(ShaderError) as info:
        compile_program(ctx, tmp_path / "s.vert", tmp_path / "s.frag", {"EXTRA": 1})
    first = str(info.value).splitlines()[0]
    assert re.match(r".*lib/inner\.glsl:3:\d+: error: .*undefined_thing", first), first
    path, line, col, severity, _ = info.value.diagnostics[0]
    assert path.endswith("lib/inner.glsl") and line == 3 and severity == "error"
    # The column points at the offending identifier, and the context shows that line.
    text = (tmp_path / "lib/inner.glsl").read_text().splitlines()[2]
    assert text[col - 1:].startswith("undefined_thing")
    assert "    3 | vec3 inner()" in str(info.value)


def test_link_error_is_reported(tmp_path, renderer):
    from facet.gl.shaders import compile_program

    _write(tmp_path, {
        "s.vert": "#version 330 core\nout vec3 v_x;\nvoid main() { v_x = vec3(1.0); "
                  "gl_Position = vec4(0.0); }\n",
        "s.frag": "#version 330 core\nin vec2 v_x;\nout vec4 c;\nvoid main() { c = vec4(v_x, 0.0, "
                  "1.0); }\n",
    })
    ctx = renderer(16, 16).ctx
    with ctx, pytest.raises(ShaderError, match=r"s\.vert \+ .*s\.frag \(link\): .*v_x"):
        compile_program(ctx, tmp_path / "s.vert", tmp_path / "s.frag")


def test_unknown_uniform_is_an_error(renderer):
    r = renderer(16, 16)
    with r.ctx:
        from facet.render.raster.variant import Variant

        prog = r._engine("raster").forward.program(Variant("unlit"))
        prog.set("u_eye_world", (0.0, 0.0, 1.0))  # declared, maybe optimised away: fine
        with pytest.raises(ShaderError, match="no uniform named 'u_colour'"):
            prog.set("u_colour", (1.0, 0.0, 0.0))


@pytest.mark.parametrize("line", ["c = vec4(foo, 1);", "  c = vec4(foo, 1);",
                                  "\t c =  vec4(1,   foo);"])
def test_mesa_columns_become_real_columns(line):
    """Columns as Mesa 22 reports them for an undeclared `foo` (runs of blanks count once)."""
    from facet.gl.shaders import mesa_column

    def mesa_col(text, index):  # Mesa's count: 1-based, each blank run one column
        import re as _re
        return len(_re.sub(r"[ \t]+", " ", text[:index])) + 1

    index = line.index("foo")
    assert mesa_column(line, mesa_col(line, index)) == index + 1
