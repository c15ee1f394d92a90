"""EXT_mesh_gpu_instancing: a node's instances are the same objects its copies placed one by
one would be, pixel for pixel in every engine; the Khronos sample's 125 instances load
warning-free; broken instance data is one error line."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import facet
from facet.cli import main

from conftest import SHARED_GLTF, shared_model
from gltf_files import USHORT, GltfBuilder
from test_animation import BOX, BOX_FACES, q_axis_angle

T = np.array([[0, 0, 0], [1.5, 0, 0], [0, 1.5, -1], [-1.5, -0.5, 0.5], [0.5, -1.5, 0]], float)
R = np.array([q_axis_angle((0, 1, 0), a) for a in (0.0, 0.5, 1.0, -0.7, 2.0)])
S = np.array([[1, 1, 1], [0.5, 1, 1], [1, 0.3, 1], [-1, 1, 1], [0.7, 0.7, 0.7]], float)
# The instances' accessors hold float32: the nodes get the same values.
T, R, S = (a.astype(np.float32).astype(float) for a in (T, R, S))


def _box(b):
    return b.mesh([{"attributes": {"POSITION": b.accessor(BOX, minmax=True)},
                    "indices": b.accessor(BOX_FACES.reshape(-1), USHORT),
                    "material": b.material(pbrMetallicRoughness={
                        "baseColorFactor": [0.8, 0.5, 0.2, 1], "metallicFactor": 0.0})}])


def instanced(tmp_path):
    b = GltfBuilder()
    b.doc["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
    b.node(mesh=_box(b), rotation=list(q_axis_angle((1, 0, 0), 0.3)), extensions={
        "EXT_mesh_gpu_instancing": {"attributes": {
            "TRANSLATION": b.accessor(T), "ROTATION": b.accessor(R),
            "SCALE": b.accessor(S)}}})
    return b.write_gltf(tmp_path / "instanced.gltf")


def one_by_one(tmp_path):
    b = GltfBuilder()
    mesh = _box(b)
    kids = [b.node(root=False, mesh=mesh, translation=list(t), rotation=list(r),
                   scale=list(s)) for t, r, s in zip(T, R, S, strict=True)]
    b.node(children=kids, rotation=list(q_axis_angle((1, 0, 0), 0.3)))
    return b.write_gltf(tmp_path / "nodes.gltf")


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_instances_equal_their_copies_placed_one_by_one(tmp_path, renderer, engine):
    a, b = facet.load(instanced(tmp_path)), facet.load(one_by_one(tmp_path))
    assert len(a.objects) == len(b.objects) == 5
    r = renderer(64, 64)
    cam = r.camera(b, r.options(b))
    opts = dict(outputs=("color", "depth", "ids"), engine=engine, spp=4 if engine == "path"
                else None)
    fa, fb = r.render(a, cam, **opts), r.render(b, cam, **opts)
    assert len(np.unique(fb.object_ids)) == 6  # five boxes and the background
    np.testing.assert_array_equal(fa.object_ids, fb.object_ids)
    np.testing.assert_array_equal(fa.depth, fb.depth)
    np.testing.assert_array_equal(fa.color, fb.color)


def test_the_khronos_instancing_sample_loads_its_125_instances_without_warnings():
    path = shared_model("SimpleInstancing/SimpleInstancing.glb", SHARED_GLTF)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = facet.load(path)
    assert len(scene.objects) == 125
    assert len({id(o.mesh) for o in scene.objects}) == 1  # one mesh, placed 125 times
    centres = np.array([o.transform[:3, 3] for o in scene.objects])
    assert len(np.unique(centres.round(4), axis=0)) == 125


@pytest.mark.parametrize("change, words", [
    (lambda a: a.update(SCALE=a["TRANSLATION"]) or a.update(TRANSLATION=a["ROTATION"]),
     "expected VEC3"),
    (lambda a: a.pop("ROTATION") and a.pop("SCALE") and a.pop("TRANSLATION"),
     "no TRANSLATION, ROTATION or SCALE"),
    (lambda a: a.update(TRANSLATION=99), "TRANSLATION"),
])
def test_broken_instances_are_one_line_and_nothing_written(tmp_path, capsys, change, words):
    path = instanced(tmp_path)
    doc = json.loads(path.read_text())
    change(doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"])
    path.write_text(json.dumps(doc))
    out = tmp_path / "out.png"
    assert main(["render", str(path), "-o", str(out), "--size", "16x16"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert not out.exists()


def test_instance_counts_that_disagree_are_refused(tmp_path, capsys):
    path = instanced(tmp_path)
    doc = json.loads(path.read_text())
    attrs = doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]
    doc["accessors"][attrs["SCALE"]]["count"] = 3
    path.write_text(json.dumps(doc))
    assert main(["render", str(path), "-o", str(tmp_path / "o.png"), "--size", "16x16"]) == 2
    assert "different numbers of instances" in capsys.readouterr().err


@pytest.mark.parametrize("kind, msaa, shadows", [
    ("phong", 0, False), ("phong", 4, True), ("pbr", 0, True), ("pbr", 4, False),
    ("pbr-textured", 0, False), ("pbr-textured", 4, True)])
def test_instanced_draws_equal_one_by_one_draws(renderer, kind, msaa, shadows):
    """The rasterizer draws objects sharing a mesh and a material in one instanced draw
    (per winding and culling state; the shadow maps too); the same objects each with its
    own copy of the material are drawn one by one: colour, depth and ids agree pixel for
    pixel, mirrored and culled instances included."""
    import copy

    from facet.geometry import transforms as Tr
    from facet.scene.pbr import PbrMaterial, TextureSlot

    from conftest import sphere_mesh

    mesh = sphere_mesh(3)
    if kind == "phong":
        material = facet.Material((0.8, 0.4, 0.2), ks=0.5, shininess=32)
    else:
        slot = TextureSlot(facet.Texture.checker()) if kind == "pbr-textured" else None
        material = PbrMaterial(base_color=(0.3, 0.6, 0.9, 1), roughness=0.4,
                               base_color_texture=slot)
    places = [Tr.translate((x, y, 0)) @ Tr.scale(s)
              for x, y, s in [(-2, 0, (1, 1, 1)), (0, 0, (-1, 1, 1)), (2, 0, (0.5, 1, 1)),
                              (-1, 1.8, (1, -1, 1)), (1, 1.8, (0.7, 0.7, 0.7)),
                              (0, -1.8, (1, 1, 1))]]
    shared, separate = facet.Scene(), facet.Scene()
    for m in places:
        shared.add(mesh, material, m)
        separate.add(mesh, copy.copy(material), m)
    floor = facet.Mesh([[-5, -3, -3], [5, -3, -3], [5, -3, 3], [-5, -3, 3]],
                       [[0, 2, 1], [0, 3, 2]])
    for scene in (shared, separate):
        scene.add(floor)
        scene.add_light(facet.PointLight((2, 6, 4), intensity=1.0))
    r = renderer(96, 64, msaa)
    cam = facet.Camera.look_at((0, 0.3, 7), (0, 0.3, 0), fov_y=50)
    opts = dict(outputs=("color", "depth", "ids", "normals"), shadows=shadows)
    a, b = r.render(shared, cam, **opts), r.render(separate, cam, **opts)
    assert len(np.unique(b.object_ids)) == 8
    np.testing.assert_array_equal(a.object_ids, b.object_ids)
    np.testing.assert_array_equal(a.depth, b.depth)
    np.testing.assert_array_equal(a.normals, b.normals)
    np.testing.assert_array_equal(a.color, b.color)
