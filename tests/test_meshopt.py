"""EXT_meshopt_compression: bufferViews decoded with meshoptimizer's decoder (the meshopt
package, an extra): a model written compressed by the same library (positions, normals
and indices; the file's own buffer a fallback with no data) draws exactly as the plain
one, in every engine; without the package, one line names it; a broken stream is one
line naming the bufferView."""

import json
import sys

import numpy as np
import pytest
import trimesh

import facet
from facet.cli import main

from gltf_files import UINT, GltfBuilder

meshopt = pytest.importorskip("meshopt", reason="the meshopt extra (pip install meshopt)")
CAM = facet.Camera.look_at((0, 0.6, 3.0), (0, 0, 0), fov_y=40, near=0.5, far=20)


def _files(tmp_path):
    """(plain .gltf, compressed .gltf) of one sphere."""
    s = trimesh.creation.icosphere(subdivisions=3)
    v = np.asarray(s.vertices, np.float32)
    n = (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)
    f = np.asarray(s.faces, np.uint32).reshape(-1)
    b = GltfBuilder()
    prim = {"attributes": {"POSITION": b.accessor(v, minmax=True), "NORMAL": b.accessor(n)},
            "indices": b.accessor(f, UINT)}
    b.node(mesh=b.mesh([prim]))
    plain = b.write_gltf(tmp_path / "plain.gltf")
    doc = json.loads(plain.read_text())
    packed = bytearray()
    fallback = 0
    for view, (array, mode) in enumerate(((v, "ATTRIBUTES"), (n, "ATTRIBUTES"),
                                          (f, "TRIANGLES"))):
        stream = meshopt.encode_gltf_buffer(array.reshape(len(array), -1)
                                            if mode == "ATTRIBUTES" else array, mode)
        while len(packed) % 4:
            packed.append(0)
        bv = doc["bufferViews"][view]
        stride = array.itemsize * (array.shape[1] if array.ndim > 1 else 1)
        bv["extensions"] = {"EXT_meshopt_compression": {
            "buffer": 0, "byteOffset": len(packed), "byteLength": len(stream),
            "byteStride": stride, "count": len(array), "mode": mode}}
        bv["buffer"], bv["byteOffset"] = 1, fallback
        fallback += bv["byteLength"]
        packed += stream
    import base64

    doc["buffers"] = [{"byteLength": len(packed), "uri": "data:application/octet-stream;"
                       "base64," + base64.b64encode(bytes(packed)).decode()},
                      {"byteLength": fallback,
                       "extensions": {"EXT_meshopt_compression": {"fallback": True}}}]
    doc["extensionsUsed"] = doc["extensionsRequired"] = ["EXT_meshopt_compression"]
    compressed = tmp_path / "compressed.gltf"
    compressed.write_text(json.dumps(doc))
    return plain, compressed


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_meshopt_file_draws_as_the_plain_one(tmp_path, engine):
    import warnings

    pictures = []
    for path in _files(tmp_path):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            scene = facet.load(path)
        with facet.Renderer(48, 48) as r:
            pictures.append(r.render(scene, CAM, engine=engine, spp=4, seed=1,
                                     float_color=True).color)
    # (meshoptimizer's index codec may start a triangle at another corner, winding kept:
    # the same surface, rounded a little differently)
    np.testing.assert_allclose(pictures[0], pictures[1], atol=2e-5)
    assert pictures[0][..., :3].std() > 0.02


def test_the_decoded_mesh_is_the_plain_one(tmp_path):
    plain, compressed = (facet.load(p).objects[0].mesh for p in _files(tmp_path))
    np.testing.assert_array_equal(plain.positions, compressed.positions)
    np.testing.assert_array_equal(plain.normals, compressed.normals)
    turned = [np.roll(compressed.faces, k, axis=1) for k in range(3)]
    assert all(any((t[i] == plain.faces[i]).all() for t in turned)
               for i in range(len(plain.faces)))


def test_without_the_decoder_one_line_names_it(tmp_path, capsys, monkeypatch):
    _, compressed = _files(tmp_path)
    monkeypatch.setitem(sys.modules, "meshopt", None)
    assert main(["render", str(compressed), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "EXT_meshopt_compression" in err[0] and \
        "pip install meshopt" in err[0], err
    assert not (tmp_path / "o.png").exists()


def test_a_broken_stream_is_one_line(tmp_path, capsys):
    _, compressed = _files(tmp_path)
    doc = json.loads(compressed.read_text())
    doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 7
    compressed.write_text(json.dumps(doc))
    assert main(["render", str(compressed), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bufferViews[0].extensions.EXT_meshopt_compression" in err[0], err
