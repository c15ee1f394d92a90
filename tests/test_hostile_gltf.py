"""Hostile glTF files: every index, count, offset, stride and type a file states is checked
before facet reads data by it (facet.formats.gltf_check), the node graph for cycles, shared
children and depth; each case is one line and exit 2 in a child process under a memory
limit (never a signal, a hang or a traceback); and a fuzzer mutating a valid file's
numbers and types finds no case that is not a clean render or such a line."""

import copy
import json
import struct

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hostile import facet, refused

from gltf_files import GltfBuilder, png, quad


def _document():
    """A valid document (a textured, sampled quad under two nodes and a camera) and its
    binary buffer."""
    b = GltfBuilder()
    tex = b.texture(png(np.full((4, 4, 3), 200)), {"magFilter": 9729, "wrapS": 10497})
    mat = b.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex},
                                           "baseColorFactor": [1, 1, 1, 1]},
                     emissiveFactor=[0, 0, 0])
    mesh = quad(b, mat)
    child = b.node(root=False, mesh=mesh, translation=[0.5, 0, 0])
    b.node(children=[child], mesh=mesh)
    b.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}]
    b.node(camera=0, translation=[0, 0, 4])
    return b


def _write(tmp_path, doc_change=None, name="m.gltf"):
    b = _document()
    if doc_change is not None:
        doc_change(b.doc)
    return b.write_gltf(tmp_path / name, "m.bin")


def _render(path, *extra):
    return facet("render", path, "-o", path.with_suffix(".png"), "--size", "32x24", *extra)


def _chain(doc, n):
    """n more nodes, each the child of the one before, under the scene's first node."""
    first = len(doc["nodes"])
    doc["nodes"].extend({"children": [first + k + 1]} for k in range(n - 1))
    doc["nodes"].append({})
    doc["nodes"][0].setdefault("children", []).append(first)


CASES = {
    "accessor negative byteOffset": (lambda d: d["accessors"][0].update(byteOffset=-10**9),
                                     "accessors[0].byteOffset: expected an integer >= 0"),
    "bufferView negative byteStride": (lambda d: d["bufferViews"][1].update(byteStride=-12),
                                       "bufferViews[1].byteStride: expected an integer in "
                                       "[4, 252]"),
    "node its own child": (lambda d: d["nodes"][0].update(children=[0]),
                           "nodes[0].children: the node is its own child"),
    "two nodes each other's children": (
        lambda d: (d["nodes"][0].update(children=[1]), d["nodes"][1].update(children=[0])),
        "cycle"),
    "a node with two parents": (lambda d: d["nodes"][2].update(children=[0]),
                                "has one parent"),
    "negative count": (lambda d: d["accessors"][0].update(count=-3),
                       "accessors[0].count: expected an integer >= 1"),
    "3e9 elements": (lambda d: d["accessors"][0].update(count=3 * 10**9),
                     "more than facet's budget"),
    "accessor type a list (found by the fuzzer)": (
        lambda d: d["accessors"][1].update(type=[]), "accessors[1].type: unknown type"),
    "accessor componentType a list": (
        lambda d: d["accessors"][1].update(componentType=[5126]),
        "accessors[1].componentType: unknown component type"),
    "unknown sparse componentType": (
        lambda d: d["accessors"][0].update(sparse={
            "count": 1, "indices": {"bufferView": 2, "componentType": 5126},
            "values": {"bufferView": 0}}), "sparse.indices.componentType"),
    "scene index out of range": (lambda d: d.update(scene=7), "scene: expected an integer"),
    "node index out of range": (lambda d: d["scenes"][0]["nodes"].append(99),
                                "got 99"),
    "material index out of range": (
        lambda d: d["meshes"][0]["primitives"][0].update(material=5), "material"),
    "texture index out of range": (
        lambda d: d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].update(
            index=9), "baseColorTexture.index"),
    "sampler index out of range": (lambda d: d["textures"][0].update(sampler=3), "sampler"),
    "camera index out of range": (lambda d: d["nodes"][2].update(camera=4), "camera"),
    "accessor index out of range": (
        lambda d: d["meshes"][0]["primitives"][0]["attributes"].update(POSITION=40),
        "attributes.POSITION"),
    "a string for a texture transform": (
        lambda d: d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].update(
            extensions={"KHR_texture_transform": {"offset": ["a", 0]}}), "offset[0]"),
    "a string for the emissive strength": (
        lambda d: d["materials"][0].update(extensions={
            "KHR_materials_emissive_strength": {"emissiveStrength": "bright"}}),
        "emissiveStrength: expected a number"),
    "a malformed Draco extension": (
        lambda d: d["meshes"][0]["primitives"][0].update(extensions={
            "KHR_draco_mesh_compression": {"bufferView": "x", "attributes": 3}}),
        "KHR_draco_mesh_compression.bufferView"),
    "nodes nested beyond the depth budget": (lambda d: _chain(d, 1500), "levels deep"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_a_hostile_gltf_is_one_line(tmp_path, case):
    change, message = CASES[case]
    refused(_render(_write(tmp_path, change)), message)


def test_a_million_nodes_are_refused_quickly(tmp_path):
    path = _write(tmp_path, lambda d: d["nodes"].extend({} for _ in range(10**6)))
    refused(_render(path), "nodes: 1,000,003 of them, more than facet's budget")


def test_the_valid_document_renders(tmp_path):
    code, err = _render(_write(tmp_path))
    assert code == 0, err


def _mutations():
    """(a path into the document, a hostile value) pairs."""
    paths = st.sampled_from([
        ("accessors", 0, "count"), ("accessors", 0, "byteOffset"), ("accessors", 1, "type"),
        ("accessors", 2, "componentType"), ("bufferViews", 0, "byteOffset"),
        ("bufferViews", 1, "byteLength"), ("bufferViews", 1, "byteStride"),
        ("bufferViews", 0, "buffer"), ("meshes", 0, "primitives", 0, "indices"),
        ("meshes", 0, "primitives", 0, "mode"), ("nodes", 1, "children"),
        ("nodes", 0, "mesh"), ("nodes", 0, "matrix"), ("nodes", 1, "rotation"),
        ("textures", 0, "source"), ("images", 0, "bufferView"), ("cameras", 0, "type"),
        ("cameras", 0, "perspective", "yfov"), ("materials", 0, "alphaMode"),
        ("materials", 0, "emissiveFactor"), ("scenes", 0, "nodes"), ("buffers", 0,
                                                                      "byteLength")])
    values = st.one_of(st.integers(-2**40, 2**40), st.sampled_from([0, -1, 1, 3, 2**31, 2**63]),
                       st.floats(allow_nan=True), st.text(max_size=3), st.none(),
                       st.lists(st.integers(-5, 5), max_size=17), st.booleans())
    return st.tuples(paths, values)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                  HealthCheck.function_scoped_fixture])
@given(mutation=_mutations())
def test_fuzzed_documents_render_or_are_refused_in_one_line(tmp_path, mutation):
    """Never a crash, a hang or a traceback: each mutated file renders, or is one line."""
    path, value = mutation
    b = _document()
    doc = copy.deepcopy(b.doc)
    doc["buffers"] = [{"byteLength": len(b.data), "uri": "m.bin"}]
    target = doc
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    (tmp_path / "m.bin").write_bytes(bytes(b.data))
    (tmp_path / "f.gltf").write_text(json.dumps(doc, allow_nan=True))
    code, err = facet("render", tmp_path / "f.gltf", "-o", tmp_path / "f.png", "--size",
                      "16x16", "-q", timeout=60)
    assert code in (0, 2), (path, value, code, err[-1500:])
    assert "Traceback" not in err, (path, value, err[-1500:])
    if code == 2:
        errors = [line for line in err.splitlines() if line.startswith("facet: error:")]
        assert len(errors) == 1, err


def test_a_glb_whose_chunks_lie_about_their_lengths(tmp_path):
    path = _document().write_glb(tmp_path / "m.glb")
    data = bytearray(path.read_bytes())
    data[12:16] = struct.pack("<I", 10**9)  # the JSON chunk's length
    path.write_bytes(bytes(data))
    refused(_render(path), "m.glb")
