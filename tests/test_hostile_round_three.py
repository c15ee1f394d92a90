"""Hostile input, round three: what the readers gained in the last round (splat files,
Draco in glTF, the guard's reads under a memory limit, an HDR without pixels). Each is one
line and exit 2 (or drawn, where the input is valid), in a child process under a memory
limit and a timeout (tests/hostile.py): a hang or a blow-up fails the test."""

from __future__ import annotations

import base64
import json
import os
import resource
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from hostile import facet, refused

from conftest import ROOT

MODEL = ROOT / "models" / "default.obj"
SPLAT_HEAD = ("ply\nformat binary_little_endian 1.0\nelement vertex {count}\n"
              "{properties}end_header\n")
SPLAT_PROPERTIES = ["x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0",
                    "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]


def _splat_ply(path, count=2, properties=SPLAT_PROPERTIES, body=None):
    head = SPLAT_HEAD.format(count=count, properties="".join(
        f"property float {p}\n" for p in properties))
    values = np.zeros((max(count, 0), len(properties)), np.float32)
    values[:, properties.index("rot_0") if "rot_0" in properties else 0] = 1.0
    path.write_bytes(head.encode() + (values.tobytes() if body is None else body))
    return path


# -- 1. splat files are sniffed through the guard -----------------------------------------
def test_a_fifo_named_as_a_ply_is_refused_not_waited_on(tmp_path):
    fifo = tmp_path / "cloud.ply"
    os.mkfifo(fifo)
    refused(facet("render", fifo, "-o", tmp_path / "o.png", cwd=tmp_path, timeout=30),
            "cloud.ply", "FIFO")
    scene = tmp_path / "scene.toml"
    scene.write_text('[[objects]]\nmesh = "cloud.ply"\n')
    refused(facet("render", scene, "-o", tmp_path / "o.png", cwd=tmp_path, timeout=30),
            "objects[0].mesh", "FIFO")
    refused(facet("info", fifo, cwd=tmp_path, timeout=30), "FIFO")


_AUDIT = textwrap.dedent("""
    import sys
    opened = []
    sys.addaudithook(lambda event, args: opened.append(str(args[0]))
                     if event == "open" and args and isinstance(args[0], (str, bytes)) else None)
    import facet
    try:
        facet.open_scene(sys.argv[1], confine=sys.argv[2])
    except facet.FacetError as exc:
        print("refused:", exc)
    from pathlib import Path
    secret = Path(sys.argv[3]).resolve()
    print("opened the secret" if any(Path(o).resolve() == secret for o in opened
                                     if not o.startswith("/proc/")) else "never opened")
""")


@pytest.mark.parametrize("how", ["relative", "absolute", "link", "scene file"])
def test_confine_refuses_a_ply_outside_before_opening_it(tmp_path, how):
    """Under --confine, a .ply outside the folder is refused before it is opened: an audit
    hook (every ``open`` Python makes) sees no open of it."""
    inside, outside = tmp_path / "inside", tmp_path / "outside"
    inside.mkdir()
    outside.mkdir()
    secret = _splat_ply(outside / "secret.ply")
    name = {"relative": "../outside/secret.ply", "absolute": str(secret)}.get(how)
    if how == "link":
        (inside / "cloud.ply").symlink_to(secret)
        name = "cloud.ply"
    target = inside / (name or "x")
    if how == "scene file":
        target = inside / "scene.toml"
        target.write_text(f'[[objects]]\nmesh = "{secret}"\n')
    run = subprocess.run([sys.executable, "-c", _AUDIT, str(target if how == "scene file"
                          else inside / name), str(inside), str(secret)],
                         env={**os.environ, "PYTHONPATH": str(ROOT / "app")},
                         capture_output=True, text=True, timeout=60, cwd=inside)
    assert "refused:" in run.stdout and "confinement" in run.stdout, run.stdout + run.stderr
    assert "never opened" in run.stdout, run.stdout + run.stderr


# -- 2. splat PLY headers -----------------------------------------------------------------
@pytest.mark.parametrize("case,needle", [("negative count", "count '-3'"),
                                         ("a property twice", "'x' twice")])
def test_hostile_splat_headers_are_one_line(tmp_path, case, needle):
    path = tmp_path / "cloud.ply"
    if case == "negative count":
        _splat_ply(path, count=-3, body=b"")
    else:
        _splat_ply(path, properties=["x", *SPLAT_PROPERTIES])
    refused(facet("render", path, "-o", tmp_path / "o.png", "--size", "16x16"),
            "cloud.ply", needle)
    refused(facet("info", path), "cloud.ply", needle)


def test_a_valid_splat_ply_renders(tmp_path):
    path = _splat_ply(tmp_path / "cloud.ply")
    code, err = facet("render", path, "-o", tmp_path / "o.png", "--size", "16x16")
    assert code == 0, err


# -- 3. Draco primitives that map no position, or hold a point cloud ---------------------
def _draco_gltf(tmp_path, blob: bytes, attributes: dict, mode: int = 4):
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_draco_mesh_compression"],
        "extensionsRequired": ["KHR_draco_mesh_compression"],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": len(blob)}],
        "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": mode,
                                    "extensions": {"KHR_draco_mesh_compression": {
                                        "bufferView": 0, "attributes": attributes}}}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
    path = tmp_path / "draco.gltf"
    path.write_text(json.dumps(doc))
    return path


_TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)


def test_a_draco_primitive_that_maps_no_position_is_one_line(tmp_path):
    import DracoPy

    blob = DracoPy.encode(_TRIANGLE, faces=np.array([[0, 1, 2]], np.uint32))
    path = _draco_gltf(tmp_path, blob, {})
    refused(facet("render", path, "-o", tmp_path / "o.png", "--size", "16x16"),
            "draco.gltf", "POSITION")
    refused(facet("info", path), "POSITION")


def test_a_draco_point_cloud_drawn_as_triangles_is_one_line(tmp_path):
    import DracoPy

    path = _draco_gltf(tmp_path, DracoPy.encode(_TRIANGLE), {"POSITION": 0})
    refused(facet("render", path, "-o", tmp_path / "o.png", "--size", "16x16"),
            "draco.gltf", "point cloud")


def test_a_draco_point_cloud_drawn_as_points_renders(tmp_path):
    import DracoPy

    import facet as api

    path = _draco_gltf(tmp_path, DracoPy.encode(_TRIANGLE), {"POSITION": 0}, mode=0)
    scene = api.open_scene(path)
    assert len(scene.objects) == 1
    np.testing.assert_allclose(np.sort(scene.objects[0].mesh.positions, axis=0),
                               np.sort(_TRIANGLE, axis=0), atol=1e-3)


# -- 4. reads take what a file holds, not the budget ---------------------------------------
_SMALL_READS = textwrap.dedent("""
    import resource, sys
    from pathlib import Path
    from facet.guard import read_bytes, read_text
    used = int(Path("/proc/self/status").read_text().split("VmSize:")[1].split()[0]) * 1024
    limit = used + (512 << 20)  # half a GiB beyond what this process has mapped
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    for _ in range(4):
        assert read_bytes(sys.argv[1]) == b"hello"
        assert read_text(sys.argv[1]) == "hello"
    print("read")
""")


def test_a_small_file_is_read_without_reserving_the_budget(tmp_path):
    """A read reserves what the file holds (fstat), not the 2 GiB file budget: under an
    address-space limit half a GiB above use, small reads succeed."""
    small = tmp_path / "small.txt"
    small.write_bytes(b"hello")
    run = subprocess.run([sys.executable, "-c", _SMALL_READS, str(small)],
                         env={**os.environ, "PYTHONPATH": str(ROOT / "app")},
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and "read" in run.stdout, run.stderr[-2000:]


def _limited(limit: int):
    def set_limit():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    return set_limit


def test_a_large_render_under_a_memory_limit_is_one_line_or_a_picture(tmp_path):
    """--size 8192 under a 1.5 GB address-space limit: drawn, or one line saying the size
    does not fit; never MemoryError."""
    out = tmp_path / "big.png"
    run = subprocess.run([sys.executable, "-m", "facet", "render", str(MODEL), "--size",
                          "8192x8192", "-o", str(out)], capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": str(ROOT / "app")}, timeout=300,
                         preexec_fn=_limited(1_500_000_000), cwd=tmp_path)
    if run.returncode == 0:
        assert out.exists()
    else:
        refused((run.returncode, run.stderr), "8192x8192")


def test_a_sparse_3_gib_shader_include_is_refused_by_its_size(tmp_path):
    include = tmp_path / "big.glsl"
    with open(include, "wb") as f:
        f.truncate(3 << 30)
    shader = tmp_path / "s.frag"
    shader.write_text('#include "big.glsl"\n'
                      "void mainImage(out vec4 c, in vec2 p) { c = vec4(1.0); }\n")
    refused(facet("--budget", "file_bytes=4000000000", "shader", shader, "-o",
                  tmp_path / "o.png", "--size", "8x8"), "big.glsl", "budget")


# -- 5. an HDR environment without pixel data ----------------------------------------------
def test_an_hdr_whose_size_line_has_no_end_is_one_line(tmp_path):
    hdr = tmp_path / "sky.hdr"
    hdr.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8")
    refused(facet("render", MODEL, "--env", hdr, "-o", tmp_path / "o.png", "--size", "8x8"),
            "sky.hdr", "pixel data")
