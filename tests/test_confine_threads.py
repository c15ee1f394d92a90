"""Confinement holds in every thread (facet.guard): a glTF's images are decoded in a pool of
threads, and a file outside the confinement folder named by one of them (relative, absolute,
or a symbolic link inside that leads out) is never opened, in ``facet render --confine``
and in ``facet batch`` (confined to its manifest's folder by default). Each run is a child
process with an audit hook that reports every open of the outside file."""

from __future__ import annotations

import base64
import json
import subprocess
import sys
import threading

import numpy as np
import pytest
from PIL import Image

from facet.errors import InputError
from facet.guard import carried, check_confined, confined

# Runs the CLI with every open of a path containing "hidden_" said on stderr.
AUDITED = ("import sys\n"
           "def hook(event, args):\n"
           "    if event == 'open' and 'hidden_' in str(args[0]):\n"
           "        print('OPENED', args[0], file=sys.stderr)\n"
           "sys.addaudithook(hook)\n"
           "from facet.cli import main\n"
           "sys.exit(main(sys.argv[1:]))\n")


def _triangle_gltf(images: list[str]) -> dict:
    """A textured triangle whose material uses three textures (three pool jobs)."""
    pos = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    uv = np.array([[0, 0], [1, 0], [0, 1]], np.float32)
    blob = pos.tobytes() + uv.tobytes() + np.array([0, 1, 2], np.uint16).tobytes() + b"\0\0"
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                    "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                "metallicRoughnessTexture": {"index": 1}},
                       "emissiveTexture": {"index": 2}}],
        "textures": [{"source": i} for i in range(len(images))],
        "images": [{"uri": u} for u in images],
        "buffers": [{"uri": "data:application/octet-stream;base64," +
                     base64.b64encode(blob).decode(), "byteLength": len(blob)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                        {"buffer": 0, "byteOffset": 60, "byteLength": 6}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                      {"bufferView": 2, "componentType": 5123, "count": 3,
                       "type": "SCALAR"}]}


@pytest.fixture
def folders(tmp_path):
    inside, outside = tmp_path / "in", tmp_path / "outside"
    inside.mkdir()
    outside.mkdir()
    Image.new("RGBA", (4, 4), (255, 0, 0, 255)).save(outside / "hidden_image.png")
    Image.new("RGBA", (4, 4), (0, 255, 0, 255)).save(inside / "a.png")
    Image.new("RGBA", (4, 4), (0, 0, 255, 255)).save(inside / "b.png")
    (inside / "hidden_image_link.png").symlink_to(outside / "hidden_image.png")
    models = {}
    for kind, uri in (("relative", "../outside/hidden_image.png"),
                      ("absolute", str(outside / "hidden_image.png")),
                      ("link", "hidden_image_link.png")):
        models[kind] = inside / f"{kind}.gltf"
        models[kind].write_text(json.dumps(_triangle_gltf(["a.png", uri, "b.png"])))
    return inside, models


def _run(args):
    return subprocess.run([sys.executable, "-c", AUDITED, *args], capture_output=True,
                          text=True, timeout=240)


@pytest.mark.parametrize("kind", ["relative", "absolute", "link"])
def test_render_confined_never_opens_a_pool_threads_outside_image(folders, kind):
    inside, models = folders
    out = inside / "x.png"
    done = _run(["render", str(models[kind]), "--confine", str(inside), "--size", "16x16",
                 "-o", str(out)])
    assert "OPENED" not in done.stderr, done.stderr
    assert "outside the confinement folder" in done.stderr, done.stderr
    free = _run(["render", str(models[kind]), "--size", "16x16", "-o", str(out), "-q"])
    assert free.returncode == 0 and "OPENED" in free.stderr  # the probe sees opens


def test_batch_confined_to_its_manifest_never_opens_an_outside_image(folders):
    inside, models = folders
    manifest = inside / "dataset.toml"
    manifest.write_text('[defaults]\nsize = [16, 16]\nviews = { plan = "turntable", '
                        'count = 1 }\n' + "".join(f'[[jobs]]\nmodel = "{m.name}"\n'
                                                  for m in models.values()))
    done = _run(["batch", str(manifest), "-o", str(inside.parent / "out"), "-q",
                 "--workers", "1"])
    assert "OPENED" not in done.stderr, done.stderr


def test_a_thread_that_carries_no_confinement_is_held_to_every_one_active(tmp_path):
    """A thread started without the context (a library's pool) cannot read past an active
    confinement: it is held to all of them; a carried function gets its caller's."""
    inside = tmp_path / "in"
    inside.mkdir()
    outcome = {}

    def probe(key, path):
        try:
            check_confined(path)
            outcome[key] = "read"
        except InputError:
            outcome[key] = "refused"

    with confined(inside):
        for key, fn in (("bare", probe), ("carried", carried(probe))):
            t = threading.Thread(target=fn, args=(key, tmp_path / "hidden_image.png"))
            t.start()
            t.join()
        t = threading.Thread(target=carried(probe), args=("inside", inside / "a.png"))
        t.start()
        t.join()
    t = threading.Thread(target=probe, args=("after", tmp_path / "hidden_image.png"))
    t.start()
    t.join()
    assert outcome == {"bare": "refused", "carried": "refused", "inside": "read",
                       "after": "read"}


def test_an_outside_buffer_or_image_reads_the_same_whether_it_exists_or_not(folders):
    """A confined glTF cannot probe which files exist outside: a missing outside buffer or
    texture gets the sentence an existing one gets (the path aside)."""
    inside, _ = folders
    doc = _triangle_gltf(["a.png", "../outside/hidden_image.png", "b.png"])
    there, gone = dict(doc), dict(doc)
    gone["images"] = [{"uri": u} for u in ("a.png", "../outside/nothing.png", "b.png")]
    said = []
    for name, d in (("there", there), ("gone", gone)):
        (inside / f"{name}.gltf").write_text(json.dumps(d))
        done = _run(["render", str(inside / f"{name}.gltf"), "--confine", str(inside),
                     "--size", "8x8", "-o", str(inside / "x.png"), "-q"])
        said.append(done.stderr.replace("hidden_image", "X").replace("nothing", "X")
                    .replace(f"{name}.gltf", "M"))
    assert said[0] == said[1] and "outside the confinement folder" in said[0], said
    said = []
    for name, uri in (("buf_there", "../outside/hidden_image.png"),
                      ("buf_gone", "../outside/nothing.bin")):
        d = dict(doc, buffers=[{"uri": uri, "byteLength": 68}])
        (inside / f"{name}.gltf").write_text(json.dumps(d))
        done = _run(["render", str(inside / f"{name}.gltf"), "--confine", str(inside),
                     "-o", str(inside / "x.png")])
        said.append((done.returncode, done.stderr.replace("hidden_image.png", "X")
                     .replace("nothing.bin", "X").replace("buf_there", "B")
                     .replace("buf_gone", "B")))
    assert said[0] == said[1] and said[0][0] == 2, said
    assert "outside the confinement folder" in said[0][1]


def test_a_projects_common_file_outside_is_refused_before_it_is_opened(tmp_path):
    """A shader project naming a common file outside the folder: refused, never opened
    (the hot-reload watcher hashed it before the check)."""
    inside = tmp_path / "in"
    inside.mkdir()
    (tmp_path / "hidden_common.glsl").write_text("float f() { return 1.0; }\n")
    (inside / "image.glsl").write_text("void mainImage(out vec4 c, in vec2 p) "
                                       "{ c = vec4(1.0); }\n")
    (inside / "project.toml").write_text('common = "../hidden_common.glsl"\n'
                                         '[image]\nshader = "image.glsl"\n')
    done = _run(["shader", str(inside / "project.toml"), "--confine", str(inside), "-o",
                 str(inside / "x.png")])
    assert done.returncode == 2 and "OPENED" not in done.stderr, done.stderr
    assert "outside the confinement folder" in done.stderr


def test_a_batch_jobs_default_cameras_file_outside_is_refused_before_it_is_read(
        folders, tmp_path):
    """A manifest's default views file outside its folder: refused before it is opened
    (it was parsed at manifest time, "no image size...", and refused only later)."""
    inside, models = folders
    (tmp_path / "hidden_cameras.json").write_text('{"frames": []}')
    manifest = inside / "dataset.toml"
    manifest.write_text('[defaults]\nsize = [16, 16]\nviews = { file = '
                        '"../hidden_cameras.json" }\n[[jobs]]\nmodel = "relative.gltf"\n')
    done = _run(["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"])
    assert done.returncode == 2 and "OPENED" not in done.stderr, done.stderr
    assert "outside the confinement folder" in done.stderr and "image size" not in \
        done.stderr, done.stderr


def test_the_guarded_opener_checks_the_file_it_opened(tmp_path, monkeypatch):
    """facet.guard.read_bytes: a file swapped for a FIFO between the check and the open is
    refused without waiting (opened non-blocking, checked again on the open file), and a
    link swapped in to lead out is not followed (the resolved path is opened)."""
    import os

    from facet import guard

    inside = tmp_path / "in"
    inside.mkdir()
    path = inside / "model.obj"
    path.write_text("v 0 0 0\n")
    assert guard.read_bytes(path) == b"v 0 0 0\n"
    checked = guard.regular_file

    def then_swapped(p, *args, **kwargs):  # the check passes, then the file changes
        out = checked(p, *args, **kwargs)
        os.unlink(p)
        os.mkfifo(p)
        return out

    monkeypatch.setattr(guard, "regular_file", then_swapped)
    with pytest.raises(InputError, match="changed while it was read"):
        guard.read_bytes(path)
    (tmp_path / "hidden.obj").write_text("secret\n")
    os.unlink(path)
    path.write_text("v 0 0 0\n")

    def then_linked(p, *args, **kwargs):
        out = checked(p, *args, **kwargs)
        os.unlink(p)
        os.symlink(tmp_path / "hidden.obj", p)
        return out

    monkeypatch.setattr(guard, "regular_file", then_linked)
    with confined(inside), pytest.raises(InputError, match="outside the confinement"):
        guard.read_bytes(path)
