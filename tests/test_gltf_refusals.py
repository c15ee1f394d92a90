"""glTF files facet cannot read as given get one line that says why, and exit 2 from the
command line (never a traceback, never a library's own warning): a data: URI with broken
base64, a binary glTF of another container version, a glTF 1.0 document, a Git LFS pointer
in place of the file; a texture that cannot be read is named in one warning line (no
Python object text in it) and the model is drawn without it."""

import json
import struct

import numpy as np
import pytest

from facet.cli import main

from gltf_files import GltfBuilder, png, quad

LFS = ("version https://git-lfs.github.com/spec/v1\n"
       "oid sha256:4d7a214614ab2935c943f9e0ff69d22eadbb8f32b1258daaa5e2ca24d17e2393\n"
       "size 12345\n")


def _quad(tmp_path, **material):
    b = GltfBuilder()
    b.node(mesh=quad(b, b.material(**material) if material else None))
    return b


def _bad_base64(tmp_path):
    path = _quad(tmp_path).write_gltf(tmp_path / "m.gltf")
    doc = json.loads(path.read_text())
    doc["buffers"][0]["uri"] = doc["buffers"][0]["uri"][:50] + "!!*" + \
        doc["buffers"][0]["uri"][53:]
    path.write_text(json.dumps(doc))
    return path


def _version_99(tmp_path):
    path = _quad(tmp_path).write_glb(tmp_path / "m.glb")
    data = bytearray(path.read_bytes())
    data[4:8] = struct.pack("<I", 99)
    path.write_bytes(bytes(data))
    return path


def _gltf_1(tmp_path):
    path = _quad(tmp_path).write_gltf(tmp_path / "m.gltf")
    doc = json.loads(path.read_text())
    doc["asset"]["version"] = "1.0"
    path.write_text(json.dumps(doc))
    return path


def _lfs(tmp_path, suffix):
    path = tmp_path / f"m{suffix}"
    path.write_text(LFS)
    return path


CASES = {
    "bad base64": (_bad_base64, "m.gltf: buffer 0: its data: URI is not valid base64"),
    "GLB version 99": (_version_99, "m.glb: binary glTF version 99; facet reads version 2"),
    "glTF 1.0": (_gltf_1, "m.gltf: glTF 1.0; facet reads glTF 2.0"),
    "LFS .glb": (lambda p: _lfs(p, ".glb"), "m.glb: is a Git LFS pointer, not the mesh file "
                 "itself (its repository was cloned without Git LFS: run `git lfs pull` "
                 "there)"),
    "LFS .obj": (lambda p: _lfs(p, ".obj"), "m.obj: is a Git LFS pointer"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_a_file_facet_cannot_read_is_one_line_and_exit_2(tmp_path, capsys, case):
    make, message = CASES[case]
    path = make(tmp_path)
    out = tmp_path / "out.png"
    assert main(["render", str(path), "-o", str(out), "--size", "16x16"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("facet: error: ") and message in err, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "pygltflib" not in err and not out.exists()


@pytest.mark.parametrize("where", ["embedded", "lfs file"])
def test_an_unreadable_texture_is_named_in_one_warning_line(tmp_path, capsys, where):
    b = GltfBuilder()
    if where == "embedded":
        tex = b.texture(b"not a png at all")
    else:
        (tmp_path / "wood.png").write_text(LFS)
        b.doc.setdefault("images", []).append({"uri": "wood.png"})
        b.doc.setdefault("textures", []).append({"source": 0})
        tex = 0
    b.node(mesh=quad(b, b.material(pbrMetallicRoughness={"baseColorTexture": {
        "index": tex}})))
    path = b.write_gltf(tmp_path / "m.gltf")
    out = tmp_path / "out.png"
    assert main(["render", str(path), "-o", str(out), "--size", "16x16", "-q"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("facet: warning: m.gltf: "), err
    assert "object at 0x" not in err[0] and "drawn without it" in err[0]
    if where == "embedded":
        assert "image 0 (embedded): not an image Pillow can read" in err[0]
    else:
        assert "wood.png: is a Git LFS pointer" in err[0]
    assert out.exists()


def test_a_texture_still_reads(tmp_path, capsys):
    """The checks above leave good files alone: a textured quad draws its texture."""
    b = GltfBuilder()
    tex = b.texture(png(np.full((4, 4, 3), (200, 40, 40))))
    b.node(mesh=quad(b, b.material(pbrMetallicRoughness={"baseColorTexture": {
        "index": tex}}, extensions={"KHR_materials_unlit": {}})))
    b.doc["extensionsUsed"] = ["KHR_materials_unlit"]
    path = b.write_glb(tmp_path / "m.glb")
    out = tmp_path / "out.png"
    assert main(["render", str(path), "-o", str(out), "--size", "16x16", "-q"]) == 0
    assert capsys.readouterr().err == ""
    from PIL import Image

    image = np.asarray(Image.open(out)).astype(int)
    assert (np.abs(image[..., :3] - (200, 40, 40)).max(-1) < 8).sum() > 20
