"""Bad input from careless scripts: special files (FIFOs hang a reader; devices flood it),
decompression bombs, TOML nested past the parser, and frame patterns that read attributes
or ask for absurd widths. Each is one clear error (exit 2 from the command line), never a
hang or a traceback (facet.guard)."""

import os

import pytest

import facet
from facet.cli import main
from facet.errors import FacetError, InputError, MeshError
from facet.image.sequence import check_sequence_path
from facet.scene.texture import Texture
from hostile import png_header


@pytest.fixture
def fifo(tmp_path):
    path = tmp_path / "pipe"
    os.mkfifo(path)
    return path


def test_special_files_are_refused_not_read(tmp_path, fifo):
    for call, what in ((lambda: facet.Mesh.load(fifo.with_suffix(".obj")), "mesh"),
                       (lambda: Texture.load(fifo), "texture"),
                       (lambda: facet.load_scene(fifo), "scene")):
        named = fifo.with_suffix(".obj") if what == "mesh" else fifo
        if what == "mesh":
            os.mkfifo(named)
        with pytest.raises(FacetError, match=r"is a named pipe \(FIFO\)"):
            call()
    with pytest.raises(InputError, match="is a device"):
        Texture.load("/dev/zero")


def test_side_files_that_are_pipes(tmp_path, fifo):
    obj = tmp_path / "m.obj"
    obj.write_text(f"mtllib {fifo.name}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(MeshError, match="pipe.*named pipe"):
        facet.Mesh.load(obj)
    from gltf_files import GltfBuilder, quad

    b = GltfBuilder()
    quad(b)
    b.node(mesh=0)
    path = b.write_gltf(tmp_path / "p.gltf", "buffer.bin")
    (tmp_path / "buffer.bin").unlink()
    os.mkfifo(tmp_path / "buffer.bin")
    with pytest.raises(MeshError, match="buffer.bin: is a named pipe"):
        facet.open_scene(path)


def test_a_decompression_bomb_is_an_error(tmp_path):
    bomb = tmp_path / "bomb.png"
    bomb.write_bytes(png_header(100_000, 100_000))
    with pytest.raises(InputError, match=r"100000x100000\)? is larger than facet's budget|"
                                         r"larger than facet's budget"):
        Texture.load(bomb)


def test_deep_toml_and_bad_frame_patterns_are_one_line(tmp_path, capsys):
    deep = tmp_path / "deep.toml"
    deep.write_text("a = " + "[" * 20000 + "]" * 20000 + "\n")
    assert main(["render", str(deep), "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "nested too deeply" in err[0]
    for pattern in ("{.nope}.png", "{[0]}.png", "{:99999999999}.png", "{x}.png",
                    "{}{}.png"):
        with pytest.raises(InputError, match="a frame pattern takes one number"):
            check_sequence_path(str(tmp_path / pattern))
        assert main(["render", "--turntable", "2", "-o", str(tmp_path / pattern)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "frame pattern" in err[0]
    assert check_sequence_path(str(tmp_path / "{:06d}.png")) == "pattern"


def test_command_line_special_files(tmp_path, fifo, capsys):
    for args in (["render", str(fifo), "-o", str(tmp_path / "x.png")],
                 ["render", "--texture", str(fifo), "-o", str(tmp_path / "x.png")],
                 ["shader", str(fifo), "-o", str(tmp_path / "x.png")]):
        assert main(args) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and ("named pipe" in err[0] or "unknown mesh format" in err[0])


def test_sequences_share_one_frame_cap(tmp_path, capsys):
    from facet.render.turntable import MAX_FRAMES

    shader = tmp_path / "s.frag"
    shader.write_text("void mainImage(out vec4 c, in vec2 p) { c = vec4(1.0); }\n")
    out = tmp_path / "t.gif"
    assert main(["shader", str(shader), "--time", "0:1e9", "--fps", "240", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"at most {MAX_FRAMES:,}" in err and not out.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temp file
    assert main(["render", "--turntable", str(MAX_FRAMES + 1), "-o", str(out)]) == 2
    assert f"1..{MAX_FRAMES}" in capsys.readouterr().err


@pytest.mark.parametrize("text,message", [
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2/1 3/2 0/3\n",
     "m.obj:6: a face refers to vertex 0, but OBJ counts vertices from 1"),
    ("v 0 0 0\nv 1e38 0 0\nv 0 1 0\nf 1 2 3\n", "1 vertices lie beyond 1e+18"),
    ("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n", "all 1 triangles have zero area"),
])
def test_meshes_that_would_draw_wrong_are_errors(tmp_path, capsys, text, message):
    obj = tmp_path / "m.obj"
    obj.write_text(text)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # and nothing from numpy on the way
        with pytest.raises(MeshError, match=message.replace("+", r"\+")):
            facet.Mesh.load(obj)
    assert main(["render", str(obj), "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and not (tmp_path / "x.png").exists()


def test_a_truncated_ply_is_an_error(tmp_path):
    import trimesh

    full = tmp_path / "full.ply"
    trimesh.creation.icosphere(subdivisions=2).export(full)
    data = full.read_bytes()
    (tmp_path / "cut.ply").write_bytes(data[: len(data) * 2 // 3])
    with pytest.raises(MeshError, match="cut.ply: cannot read the file .*truncated"):
        facet.Mesh.load(tmp_path / "cut.ply")


def test_messages_name_the_users_paths_and_escape_control_characters(tmp_path, capsys):
    binary = tmp_path / "b.obj"
    binary.write_bytes(b"\xff\xfe\x00\x00garbage")
    assert main(["render", str(binary), "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    # Without charset_normalizer installed trimesh fails on the encoding; with it, it
    # finds no geometry: either way one sentence, no missing-module message.
    assert "cannot read the file" in err and "charset" not in err and "module" not in err
    assert main(["render", "--size", "16x16", "-o", "/proc/facet-test.png"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("facet: error: /proc/facet-test.png:") and ".tmp" not in err
    odd = tmp_path / "a\tb\nc.png"
    assert main(["render", "--size", "16x16", "-o", str(odd)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == str(odd).replace("\t", "\\t").replace("\n", "\\n")
    assert odd.is_file()


def test_confinement_refuses_paths_outside_the_folder(tmp_path, capsys):
    """--confine DIR (and facet.guard.confined in Python): a scene naming a mesh outside,
    a symbolic link pointing out, a shader including /etc/passwd: refused, and nothing of a
    non-GLSL file's content is quoted."""
    inside = tmp_path / "inside"
    inside.mkdir()
    outside = tmp_path / "elsewhere.obj"
    outside.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    scene = inside / "s.toml"
    scene.write_text(f'[[objects]]\nmesh = "{outside}"\n')
    (inside / "link.obj").symlink_to(outside)
    linked = inside / "l.toml"
    linked.write_text('[[objects]]\nmesh = "link.obj"\n')
    for path in (scene, linked):
        assert main(["render", str(path), "--confine", str(inside), "-o",
                     str(inside / "x.png")]) == 2
        err = capsys.readouterr().err
        assert "outside the confinement folder" in err and len(err.splitlines()) == 1
        assert main(["render", str(path), "-o", str(inside / "x.png"), "-q"]) == 0  # free
    shader = inside / "s.frag"
    shader.write_text('#include "/etc/passwd"\nvoid mainImage(out vec4 c, in vec2 p) '
                      "{ c = vec4(1); }\n")
    assert main(["shader", str(shader), "--confine", str(inside), "-o",
                 str(inside / "y.png")]) == 2
    err = capsys.readouterr().err
    assert "outside the confinement folder" in err and "root:" not in err
    assert main(["shader", str(shader), "-o", str(inside / "y.png")]) == 2  # not confined
    err = capsys.readouterr().err
    assert "passwd" in err and "root:" not in err  # named, never quoted


def test_confine_in_python(tmp_path):
    outside = tmp_path / "m.obj"
    outside.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    inside = tmp_path / "in"
    inside.mkdir()
    (inside / "s.toml").write_text(f'[[objects]]\nmesh = "{outside}"\n')
    with pytest.raises(FacetError, match="outside the confinement folder"):
        facet.open_scene(inside / "s.toml", confine=inside)
    assert len(facet.open_scene(inside / "s.toml").objects) == 1


def test_an_ascii_ply_shorter_than_its_header(tmp_path):
    ply = tmp_path / "short.ply"
    ply.write_text("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                   "property float y\nproperty float z\nelement face 3\n"
                   "property list uchar int vertex_indices\nend_header\n"
                   "0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n")
    with pytest.raises(MeshError, match="promises 3 face elements but the file holds 1"):
        facet.Mesh.load(ply)
