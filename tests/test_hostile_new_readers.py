"""The readers added since the validating layer, behind it: hostile PCD headers and data,
OBJ line indices beyond any count, pictures too large for their format, sample counts
beyond facet's limit, HDR / EXR environments that lie about their size, are not regular
files, exceed the file budget or hold radiance that would overflow a float picture. Each is
one line and exit 2 (never a traceback, never a silent substitution), through the command
line in this process."""

from __future__ import annotations

import json
import os
import struct

import numpy as np
import pytest

from facet.cli import main

from conftest import ROOT

MODEL = str(ROOT / "models" / "default.obj")
PCD_HEAD = "VERSION .7\nFIELDS {fields}\nSIZE 4 4 4\nTYPE F F F\nCOUNT {count}\nWIDTH 2\n" \
           "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {points}\nDATA {mode}\n"
PCD = {  # name: (fields, count, points, data)
    "count of letters": ("x y z", "a b c", "2", "0 0 0\n1 1 1\n"),
    "negative count": ("x y z", "-1 1 1", "2", "0 0 0\n1 1 1\n"),
    "fewer counts than fields": ("x y z", "1 1", "2", "0 0 0\n1 1 1\n"),
    "count 2 for x": ("x y z", "2 1 1", "2", "0 0 0 0\n1 1 1 1\n"),
    "a field twice": ("x x z", "1 1 1", "2", "0 0 0\n1 1 1\n"),
    "negative points": ("x y z", "1 1 1", "-2", "0 0 0\n1 1 1\n"),
    "letters in the data": ("x y z", "1 1 1", "2", "0 a 0\n1 1 1\n"),
}


def _one_line_error(capsys, args, *needles) -> str:
    assert main(args) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err
    return err


@pytest.mark.parametrize("case", sorted(PCD))
def test_hostile_pcd_headers_and_data_are_one_line(tmp_path, capsys, case):
    fields, count, points, data = PCD[case]
    path = tmp_path / "cloud.pcd"
    path.write_text(PCD_HEAD.format(fields=fields, count=count, points=points,
                                    mode="ascii") + data)
    _one_line_error(capsys, ["render", str(path), "-o", str(tmp_path / "o.png"), "--size",
                             "16x16"], "cloud.pcd")


def test_a_binary_pcd_with_count_2_for_x_is_one_line(tmp_path, capsys):
    path = tmp_path / "cloud.pcd"
    head = PCD_HEAD.format(fields="x y z", count="2 1 1", points="2", mode="binary")
    path.write_bytes(head.encode() + struct.pack("8f", *range(8)))
    _one_line_error(capsys, ["render", str(path), "-o", str(tmp_path / "o.png")], "COUNT")


def test_an_obj_line_index_beyond_any_count_is_one_line(tmp_path, capsys):
    path = tmp_path / "lines.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nl 1 100000000000000000000000\n")
    _one_line_error(capsys, ["render", str(path), "-o", str(tmp_path / "o.png")],
                    "'l' line")


def test_a_picture_too_wide_for_webp_is_refused_before_rendering(tmp_path, capsys):
    out = tmp_path / "wide.webp"
    _one_line_error(capsys, ["render", MODEL, "-o", str(out), "--size", "16384x8"],
                    "16,383")
    assert not out.exists()


def test_samples_beyond_the_limit_are_an_error_not_a_cap(tmp_path, capsys):
    out = tmp_path / "o.png"
    _one_line_error(capsys, ["render", MODEL, "-o", str(out), "--size", "8x8", "--spp",
                             "2147483648"], "at most 4,096")
    assert not out.exists()


def _hdr(path, width, height, body=b""):
    path.write_bytes(f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n"
                     .encode() + body)
    return path


def test_hostile_hdr_environments_are_one_line_before_any_allocation(tmp_path, capsys):
    out = str(tmp_path / "o.png")
    env = {"a header of 32768 x 32768": _hdr(tmp_path / "huge.hdr", 32768, 32768,
                                             b"\x02\x02\x80\x00"),
           "no pixel data": _hdr(tmp_path / "empty.hdr", 8, 4)}
    (tmp_path / "zero.hdr").symlink_to("/dev/zero")
    env["a link to /dev/zero"] = tmp_path / "zero.hdr"
    os.mkfifo(tmp_path / "fifo.hdr")
    env["a FIFO"] = tmp_path / "fifo.hdr"
    os.mkfifo(tmp_path / "fifo.exr")
    env["a FIFO as .exr"] = tmp_path / "fifo.exr"
    sparse = _hdr(tmp_path / "sparse.hdr", 8, 4)
    with open(sparse, "r+b") as f:
        f.truncate(3 << 30)  # 3 GiB, sparse: beyond the 2 GiB file budget
    env["a 3 GiB file"] = sparse
    for what, path in env.items():
        err = _one_line_error(capsys, ["render", MODEL, "--env", str(path), "-o", out,
                                       "--size", "8x8"], path.name)
        assert any(word in err for word in ("budget", "pixel data", "device", "FIFO")), \
            (what, err)
    scene = tmp_path / "scene.toml"
    scene.write_text('environment = "fifo.hdr"\n[[objects]]\nmesh = "' + MODEL + '"\n')
    _one_line_error(capsys, ["render", str(scene), "-o", out, "--size", "8x8"], "FIFO")


def test_an_environment_that_would_overflow_a_float_picture_is_refused(tmp_path, capsys):
    _hdr(tmp_path / "bright.hdr", 8, 4, b"\xff" * 4 * 32)  # 255 x 2^119: about 1.7e38
    _one_line_error(capsys, ["render", MODEL, "--env", str(tmp_path / "bright.hdr"), "-o",
                             str(tmp_path / "o.exr"), "--size", "8x8"], "not finite or beyond")


def test_a_float_output_stays_finite_and_says_so(tmp_path):
    pytest.importorskip("OpenEXR", reason="the exr extra (OpenEXR) is not installed")
    from facet.errors import FacetWarning
    from facet.image.writers import save_float_color

    color = np.ones((2, 2, 3), np.float32)
    color[0, 0] = np.inf
    color[1, 1, 2] = np.nan
    with pytest.warns(FacetWarning, match="2 pixels were not finite"):
        save_float_color(tmp_path / "o.exr", color)
    from facet.formats.hdr_image import _read_exr

    assert np.isfinite(_read_exr(tmp_path / "o.exr")).all()


def _quad_gltf(tmp_path, name, edit):
    from gltf_files import GltfBuilder, quad

    b = GltfBuilder()
    m = quad(b, b.material(name="m"))
    b.node(mesh=m)
    edit(b, m)
    return b.write_gltf(tmp_path / f"{name}.gltf")


def _variants(ext=None, mappings=None):
    def edit(b, m):
        b.doc["extensionsUsed"] = ["KHR_materials_variants"]
        b.doc["extensions"] = {"KHR_materials_variants": ext or {"variants": [{"name": "v"}]}}
        if mappings is not None:
            b.doc["meshes"][m]["primitives"][0]["extensions"] = {
                "KHR_materials_variants": {"mappings": mappings}}
    return edit


def _camera_scale_0(b, m):
    b.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]
    b.node(camera=0, scale=[0, 0, 0], translation=[0, 0, 3])


GLTF = {
    "variants a list of strings": _variants({"variants": ["a", "b"]},
                                            [{"material": 0, "variants": [0]}]),
    "variants an int": _variants({"variants": 5}, [{"material": 0, "variants": [0]}]),
    "a variant's name a list": _variants({"variants": [{"name": ["x"]}]},
                                         [{"material": 0, "variants": [0]}]),
    "mappings an int": _variants(mappings=5),
    "a mapping's variants an int": _variants(mappings=[{"material": 0, "variants": 3}]),
    "a camera node of scale 0": _camera_scale_0,
}


@pytest.mark.parametrize("case", sorted(GLTF))
def test_hostile_gltf_extensions_are_one_line_in_render_and_info(tmp_path, capsys, case):
    path = _quad_gltf(tmp_path, "model", GLTF[case])
    _one_line_error(capsys, ["render", str(path), "-o", str(tmp_path / "o.png"), "--size",
                             "8x8"], "model.gltf")
    _one_line_error(capsys, ["info", str(path)], "model.gltf")


def test_a_batch_job_name_with_a_nul_byte_is_one_line(tmp_path, capsys):
    manifest = tmp_path / "jobs.jsonl"
    manifest.write_text(json.dumps({"model": MODEL, "name": "a\0b"}) + "\n")
    _one_line_error(capsys, ["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"],
                    "cannot be a folder name")


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_an_animation_that_scales_a_part_to_zero_hides_it(tmp_path, renderer, engine):
    """How files hide parts: a node animated to scale 0 draws nothing there, in every
    engine (the tracers refused it: "Singular matrix"); the other part is drawn."""
    import facet
    from facet.geometry.camera import Camera

    def edit(b, m):
        b.node(mesh=m, translation=[-1.5, 0, 0])
        t = b.accessor(np.array([0.0, 1.0]), minmax=True)
        v = b.accessor(np.array([[1, 1, 1], [0, 0, 0]], float))
        b.doc["animations"] = [{"samplers": [{"input": t, "output": v}],
                                "channels": [{"sampler": 0,
                                              "target": {"node": 0, "path": "scale"}}]}]

    scene = facet.load(_quad_gltf(tmp_path, "hide", edit))
    cam = Camera.look_at((-0.25, 0.5, 5), (-0.25, 0.5, 0), fov_y=40)
    seen = {}
    for time in (0.0, 1.0):
        frame = renderer(48, 32).render(scene, cam, engine=engine, time=time,
                                        outputs=("color", "ids"), aa="none")
        seen[time] = int((frame.object_ids >= 0).sum())  # pixels covered
    assert seen[0.0] > 100 and 0.35 < seen[1.0] / seen[0.0] < 0.65, seen


@pytest.mark.parametrize("count", [2_000_000, 80_000_000])
def test_instances_count_against_the_objects_budget_before_allocation(tmp_path, capsys,
                                                                       count):
    """EXT_mesh_gpu_instancing with millions of instances in a 1 KB file (an accessor with
    no bufferView is zeros): one line naming the budget, before anything is decoded (80
    million: MemoryError; 2 million: a hang past 150 s)."""
    def edit(b, m):
        b.doc["accessors"].append({"componentType": 5126, "count": count, "type": "VEC3"})
        b.doc["nodes"][0]["extensions"] = {"EXT_mesh_gpu_instancing": {
            "attributes": {"TRANSLATION": len(b.doc["accessors"]) - 1}}}
        b.doc["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]

    path = _quad_gltf(tmp_path, "many", edit)
    assert path.stat().st_size < 2000
    _one_line_error(capsys, ["render", str(path), "-o", str(tmp_path / "o.png")],
                    "budget of 50,000 objects")


def test_equal_primitives_of_a_scene_file_share_one_geometry(tmp_path):
    """A scene of thousands of equal flat spheres tessellated, checked and uploaded each
    one (30,000: past 60 s); objects of one primitive and size now share one mesh, and a
    flat-shaded mesh file is flattened once."""
    import facet

    scene_file = tmp_path / "many.toml"
    scene_file.write_text("".join(
        f'[[objects]]\nprimitive = "sphere"\nradius = {r}\nflat = true\n'
        f'transform = [{{ translate = [{i}, 0, 0] }}]\n'
        for i, r in enumerate([0.1, 0.1, 0.1, 0.2])) + "".join(
        f'[[objects]]\nmesh = "{MODEL}"\nflat = true\n' for _ in range(2)))
    meshes = [o.mesh for o in facet.load(scene_file).objects]
    assert meshes[0] is meshes[1] is meshes[2] and meshes[3] is not meshes[0]
    assert meshes[4] is meshes[5]
