"""Fuzzers for the documents facet reads without GL (run as a child process by
test_hostile_fuzz.py, under a memory limit): a valid Shadertoy JSON export, TOML shader
project, and batch manifest (with its cameras file) are mutated by hypothesis, any value
anywhere replaced by a value of another type or removed, and read by facet's own reader;
so are a glTF's KHR_materials_variants and EXT_mesh_gpu_instancing objects, and PCD point
files' and Radiance HDR environments' headers (their tokens drawn from valid and hostile
ones, with random bodies). Every mutation must read cleanly or raise facet's one-line
error (FacetError without a line break); anything else (a TypeError, a RecursionError, a
hang, an allocation past the memory limit) is a failure.

Usage: python fuzz_documents.py shadertoy|project|manifest|gltf|pcd|hdr EXAMPLES
"""

from __future__ import annotations

import copy
import json
import math
import sys
import tempfile
import warnings
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from facet.errors import FacetError

FRAG = "void mainImage(out vec4 c, in vec2 p) { c = texture(iChannel0, p); }"

SHADERTOY = {"Shader": {"info": {"name": "fuzz"}, "renderpass": [
    {"type": "common", "name": "Common", "code": "float k = 1.0;", "inputs": [],
     "outputs": []},
    {"type": "buffer", "name": "Buffer A", "code": FRAG,
     "inputs": [{"id": "4dXGR8", "ctype": "buffer", "channel": 0,
                 "sampler": {"filter": "linear", "wrap": "clamp", "vflip": "true"}}],
     "outputs": [{"id": "4dXGR8", "channel": 0}]},
    {"type": "image", "name": "Image", "code": FRAG,
     "inputs": [{"id": 257, "ctype": "buffer", "channel": 0},
                {"id": "t", "ctype": "texture", "channel": 1, "src": "/media/a/t.png",
                 "sampler": {"filter": "mipmap", "wrap": "repeat", "vflip": False}},
                {"id": "k", "ctype": "keyboard", "channel": 2},
                {"id": "m", "ctype": "music", "channel": 3}],
     "outputs": [{"id": "4dfGRr", "channel": 0}]}]}}

PROJECT = {"common": "common.glsl",
           "buffer-a": {"shader": "a.frag", "channels": {"0": "buffer-a"}},
           "image": {"shader": "image.frag", "channels": {
               "0": "buffer-a", "1": {"source": "t.png", "filter": "nearest",
                                      "wrap": "repeat", "vflip": True}}}}

MANIFEST = {"defaults": {"size": [16, 12], "outputs": ["color", "depth"]},
            "jobs": [{"model": "m.obj", "views": {"plan": "random", "count": 3, "seed": 4}},
                     {"model": "m.obj", "name": "second", "views": {
                         "plan": "cameras", "file": "t.json"}, "colmap": False},
                     {"model": "m.obj", "views": {"plan": "sphere", "count": 2,
                                                  "elevations": [-10, 40]}}]}

TRANSFORMS = {"w": 16, "h": 12, "camera_angle_x": 0.8, "frames": [
    {"file_path": "images/0000", "transform_matrix": [[1, 0, 0, 0], [0, 1, 0, 0],
                                                      [0, 0, 1, 3], [0, 0, 0, 1]]}]}

ODD_TEXT = ["", "7", "-1", "²", "٣", "a\0b", "~nosuchuser_facet/x", "../../etc/passwd",
            "buffer-e", "cube:", "none", "image", "x" * 300, "\x1b[31m", "1e999"]
SCALARS = st.one_of(st.none(), st.booleans(),
                    st.integers(min_value=-2**70, max_value=2**70),
                    st.sampled_from([-1, 0, 1, 2, 3, 4, 7, 256, 257, 2**31, -2**63]),
                    st.floats(allow_nan=False, allow_infinity=False),
                    st.sampled_from(ODD_TEXT), st.text(max_size=8))
VALUES = st.recursive(SCALARS, lambda inner: st.one_of(
    st.lists(inner, max_size=3), st.dictionaries(st.sampled_from(
        ["id", "channel", "type", "code", "src", "model", "views", "0", "x"]), inner,
        max_size=3)), max_leaves=6)


def _paths(value, prefix=()):
    """Every key path in a JSON-like value (the root excluded)."""
    items = value.items() if isinstance(value, dict) else enumerate(value) \
        if isinstance(value, list) else ()
    for key, inner in items:
        yield (*prefix, key)
        yield from _paths(inner, (*prefix, key))


@st.composite
def mutated(draw, document):
    doc = copy.deepcopy(document)
    for _ in range(draw(st.integers(1, 3))):
        paths = list(_paths(doc))
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        parent = doc
        for key in path[:-1]:
            parent = parent[key]
        if draw(st.booleans()) and isinstance(parent, dict):
            del parent[path[-1]]
        else:
            parent[path[-1]] = draw(VALUES)
    return doc


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v) if -2**63 <= v < 2**63 else json.dumps(str(v))
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") \
            if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v if x is not None) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {_toml_value(x)}"
                               for k, x in v.items() if x is not None) + "}"
    return '""'


def toml_text(doc) -> str:
    """A TOML document for a dict (nulls left out: TOML has none)."""
    if not isinstance(doc, dict):
        return ""
    return "\n".join(f"{json.dumps(str(k))} = {_toml_value(v)}" for k, v in doc.items()
                     if v is not None) + "\n"


def _clean_or_one_line(read) -> None:
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            read()
    except FacetError as exc:
        message = str(exc)
        assert message and "\n" not in message, repr(message)


def _folder() -> Path:
    folder = Path(tempfile.mkdtemp(prefix="facet-fuzz-"))
    from PIL import Image

    Image.new("RGB", (4, 4)).save(folder / "t.png")
    for name in ("a.frag", "image.frag"):
        (folder / name).write_text(FRAG + "\n")
    (folder / "common.glsl").write_text("float k = 1.0;\n")
    (folder / "m.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (folder / "t.json").write_text(json.dumps(TRANSFORMS))
    return folder


FOLDER = _folder()
SETTINGS = dict(deadline=None, derandomize=True, database=None,
                suppress_health_check=list(HealthCheck))


def shadertoy(examples: int) -> None:
    from facet.lab.shadertoy_json import load_shadertoy_json

    @settings(max_examples=examples, **SETTINGS)
    @given(mutated(SHADERTOY))
    def check(doc):
        (FOLDER / "e.json").write_text(json.dumps(doc))
        _clean_or_one_line(lambda: load_shadertoy_json(FOLDER / "e.json", FOLDER))
    check()


def project(examples: int) -> None:
    from facet.lab.assemble import check_channels
    from facet.lab.project import load_project

    @settings(max_examples=examples, **SETTINGS)
    @given(mutated(PROJECT))
    def check(doc):
        (FOLDER / "p.toml").write_text(toml_text(doc))
        _clean_or_one_line(lambda: check_channels(load_project(FOLDER / "p.toml")))
    check()


def manifest(examples: int) -> None:
    from facet.batch.manifest import _camera_count, load_manifest

    @settings(max_examples=examples, **SETTINGS)
    @given(st.booleans(), mutated(MANIFEST), mutated(TRANSFORMS))
    def check(transforms_too, doc, cameras):
        _camera_count.cache_clear()
        (FOLDER / "t.json").write_text(json.dumps(cameras if transforms_too else TRANSFORMS))
        (FOLDER / "m.json").write_text(json.dumps(doc))
        _clean_or_one_line(lambda: _plan_every_view(load_manifest(FOLDER / "m.json")))
    check()


def _plan_every_view(jobs) -> None:
    """Each job's cameras, as a worker makes them (a unit cube's bounds)."""
    import numpy as np

    bounds = np.array([[-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]])
    for job in jobs:
        job.views.cameras(bounds, base=FOLDER)
        np.random.default_rng(job.views.seed)  # the worker's, for COLMAP's points


GLTF_EXTENSIONS = {  # the new readers' parts of a glTF, mutated and spliced in
    "variants": {"variants": [{"name": "red"}, {"name": "blue"}]},
    "mappings": {"mappings": [{"material": 0, "variants": [0]},
                              {"material": 1, "variants": [1]}]},
    "instancing": {"attributes": {"TRANSLATION": 3, "SCALE": 4}}}


def _gltf_document() -> dict:
    """A quad with two materials in variants, placed twice by EXT_mesh_gpu_instancing."""
    import numpy as np

    from gltf_files import GltfBuilder, quad

    b = GltfBuilder()
    m = quad(b, b.material(name="red"))
    b.material(name="blue")
    b.accessor(np.array([[0, 0, 0], [2, 0, 0]], float))  # 3: TRANSLATION
    b.accessor(np.array([[1, 1, 1], [0.5, 0.5, 0.5]], float))  # 4: SCALE
    b.node(mesh=m)
    return b


def gltf(examples: int) -> None:
    import facet

    builder = _gltf_document()

    @settings(max_examples=examples, **SETTINGS)
    @given(mutated(GLTF_EXTENSIONS))
    def check(parts):
        doc = builder.doc
        doc["extensionsUsed"] = ["KHR_materials_variants", "EXT_mesh_gpu_instancing"]
        doc["extensions"] = {"KHR_materials_variants": parts.get("variants")}
        doc["meshes"][0]["primitives"][0]["extensions"] = {
            "KHR_materials_variants": parts.get("mappings")}
        doc["nodes"][0]["extensions"] = {"EXT_mesh_gpu_instancing": parts.get("instancing")}
        builder.write_gltf(FOLDER / "f.gltf")
        _clean_or_one_line(lambda: facet.load(FOLDER / "f.gltf"))
    check()


TOKENS = st.sampled_from(["x", "y", "z", "rgb", "intensity", "normal_x", "1", "2", "3",
                          "4", "8", "F", "U", "I", "0", "-1", "-2", "a", "1e23",
                          "99999999999999999999", "ascii", "binary", "binary_compressed",
                          "nan", ""])


def pcd(examples: int) -> None:
    import facet

    keys = ["VERSION", "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT",
            "POINTS", "DATA"]
    valid = {"VERSION": ".7", "FIELDS": "x y z", "SIZE": "4 4 4", "TYPE": "F F F",
             "COUNT": "1 1 1", "WIDTH": "2", "HEIGHT": "1", "VIEWPOINT": "0 0 0 1 0 0 0",
             "POINTS": "2", "DATA": "ascii"}

    @settings(max_examples=examples, **SETTINGS)
    @given(st.dictionaries(st.sampled_from(keys), st.lists(TOKENS, max_size=5)
                           .map(" ".join), max_size=4),
           st.sets(st.sampled_from(keys), max_size=2), st.binary(max_size=64))
    def check(changed, dropped, body):
        head = "".join(f"{k} {changed.get(k, valid[k])}\n" for k in keys
                       if k not in dropped)
        (FOLDER / "f.pcd").write_bytes(head.encode() + (body or b"0 0 0\n1 1 1\n"))
        _clean_or_one_line(lambda: facet.load(FOLDER / "f.pcd"))
    check()


def hdr(examples: int) -> None:
    from facet.formats.hdr_image import read_hdr_image

    sizes = st.sampled_from(["-Y", "+Y", "+X", "-X", "4", "8", "0", "-3", "32768",
                             "99999999999999999999", "1e3", "a", ""])

    @settings(max_examples=examples, **SETTINGS)
    @given(st.sampled_from(["#?RADIANCE", "#?RGBE", "#?XYZ"]),
           st.sampled_from(["FORMAT=32-bit_rle_rgbe", "FORMAT=32-bit_rle_xyze", ""]),
           st.lists(sizes, min_size=0, max_size=5), st.binary(max_size=256))
    def check(magic, fmt, size, body):
        text = f"{magic}\n{fmt}\n\n{' '.join(size)}\n".encode()
        (FOLDER / "f.hdr").write_bytes(text + body)
        _clean_or_one_line(lambda: read_hdr_image(FOLDER / "f.hdr"))
    check()


if __name__ == "__main__":
    {"shadertoy": shadertoy, "project": project, "manifest": manifest, "gltf": gltf,
     "pcd": pcd, "hdr": hdr}[sys.argv[1]](int(sys.argv[2]))
