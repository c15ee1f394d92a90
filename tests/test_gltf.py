"""glTF loading (facet.formats.gltf): parts with their own materials and node transforms,
accessors (strided, normalized, sparse), strips and fans, materials and their textures,
cameras, Draco, and every error, on files built in code (tests/gltf_files.py) and on the
Khronos samples in ../shared/gltf (skipped when absent)."""

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import facet
from facet.cli import main
from facet.errors import FacetWarning, MeshError
from facet.scene import Mesh
from facet.scene.pbr import PbrMaterial

from conftest import SHARED_GLTF, shared_model
from gltf_files import FLOAT, UBYTE, USHORT, GltfBuilder, png, quad


def shared_gltf(name: str) -> Path:
    return shared_model(name, SHARED_GLTF)


def _quat(axis, degrees):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    h = np.radians(degrees) / 2
    return [*(a * np.sin(h)), np.cos(h)]


def test_parts_keep_materials_and_node_transforms(tmp_path):
    b = GltfBuilder()
    red = b.material(pbrMetallicRoughness={"baseColorFactor": [1, 0, 0, 1],
                                           "metallicFactor": 0.0})
    blue = b.material(pbrMetallicRoughness={"baseColorFactor": [0, 0, 1, 1],
                                            "roughnessFactor": 0.25})
    m_red, m_blue = quad(b, red), quad(b, blue)
    child = b.node(root=False, mesh=m_blue, name="child",
                   matrix=[2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 5, 0, 0, 1])  # column-major
    b.node(mesh=m_red, name="a", translation=[1, 2, 3], rotation=_quat((0, 0, 1), 90),
           scale=[1, 1, 3], children=[child])
    b.node(mesh=m_red, name="b", translation=[-4, 0, 0])
    scene = facet.open_scene(b.write_glb(tmp_path / "parts.glb"))
    names = [o.name for o in scene.objects]
    assert names == ["a", "child", "b"]
    a, c, bb = scene.objects
    rz = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]], float)
    expect_a = np.eye(4)
    expect_a[:3, :3] = rz @ np.diag([1, 1, 3])
    expect_a[:3, 3] = [1, 2, 3]
    np.testing.assert_allclose(a.transform, expect_a, atol=1e-12)
    expect_c = expect_a @ np.array([[2, 0, 0, 5], [0, 2, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1.0]])
    np.testing.assert_allclose(c.transform, expect_c, atol=1e-12)
    assert a.mesh is bb.mesh  # one mesh, two nodes: decoded once
    assert isinstance(a.material, PbrMaterial) and a.material is bb.material
    np.testing.assert_allclose(a.material.base_color, [1, 0, 0, 1])
    assert a.material.metallic == 0.0 and a.material.roughness == 1.0
    assert c.material.metallic == 1.0 and c.material.roughness == 0.25
    assert scene.camera() is None  # no cameras: framed


def test_strided_normalized_and_sparse_accessors(tmp_path):
    b = GltfBuilder()
    pos = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    uv8 = np.array([[0, 255], [255, 255], [255, 0], [0, 0]], np.uint8)
    # Positions interleaved with padding: a 16-byte stride.
    raw = np.zeros((4, 4), np.float32)
    raw[:, :3] = pos
    b.doc["accessors"].append({"bufferView": b.view(raw.tobytes(), stride=16),
                               "componentType": FLOAT, "count": 4, "type": "VEC3",
                               "min": [0, 0, 0], "max": [1, 1, 0]})
    p = len(b.doc["accessors"]) - 1
    uv = b.accessor(uv8, UBYTE, normalized=True)  # KHR_mesh_quantization style
    # Sparse: vertex 2 moves to z = 0.5, on top of the strided base.
    idx_view = b.view(np.array([2], "<u2").tobytes())
    val_view = b.view(np.array([[1, 1, 0.5]], "<f4").tobytes())
    sparse = dict(b.doc["accessors"][p], sparse={
        "count": 1, "indices": {"bufferView": idx_view, "componentType": USHORT},
        "values": {"bufferView": val_view}})
    b.doc["accessors"].append(sparse)
    ps = len(b.doc["accessors"]) - 1
    i = b.accessor(np.array([0, 1, 2, 0, 2, 3]), USHORT)
    b.node(mesh=b.mesh([{"attributes": {"POSITION": ps, "TEXCOORD_0": uv}, "indices": i}]))
    b.doc["extensionsUsed"] = ["KHR_mesh_quantization"]
    mesh = Mesh.load(b.write_gltf(tmp_path / "acc.gltf", "acc.bin"), crease=180)
    got = {tuple(np.round(v, 6)) for v in mesh.positions}
    assert got == {(0, 0, 0), (1, 0, 0), (1, 1, 0.5), (0, 1, 0)}
    # glTF's v points down the image; facet's up: (0, 255) -> (0, 1 - 1) = (0, 0).
    corner = mesh.uvs[np.argmin(np.linalg.norm(mesh.positions - [0, 0, 0], axis=1))]
    np.testing.assert_allclose(corner, [0, 0], atol=1e-6)


@pytest.mark.parametrize("mode,indices", [(5, [0, 1, 3, 2]), (6, [0, 1, 2, 3])])
def test_strips_and_fans_become_consistently_wound_triangles(tmp_path, mode, indices):
    b = GltfBuilder()
    pos = b.accessor(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float),
                     minmax=True)
    i = b.accessor(np.array(indices), USHORT)
    b.node(mesh=b.mesh([{"attributes": {"POSITION": pos}, "indices": i, "mode": mode}]))
    mesh = Mesh.load(b.write_glb(tmp_path / "s.glb"))
    assert mesh.face_count == 2
    tri = mesh.positions[mesh.faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert (n[:, 2] > 0).all()  # both counter-clockwise seen from +z


def test_points_and_lines_load_beside_triangles(tmp_path):
    """(They were left out with a warning; facet.scene.points draws them now.)"""
    import warnings

    b = GltfBuilder()
    pos = b.accessor(np.eye(3), minmax=True)
    b.node(mesh=b.mesh([{"attributes": {"POSITION": pos}, "mode": 0}]))
    assert isinstance(facet.open_scene(b.write_glb(tmp_path / "points.glb")).objects[0].mesh,
                      facet.Points)
    quad(b)
    b.node(mesh=1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = facet.open_scene(b.write_glb(tmp_path / "mixed.glb"))
    assert [o.mesh.kind for o in scene.objects] == ["points", "mesh"]
    b.doc["meshes"][0]["primitives"][0]["mode"] = 1
    b.doc["meshes"][0]["primitives"][0]["indices"] = b.accessor(np.array([0]), 5123)
    with pytest.raises(MeshError, match="a line needs at least 2 vertices"):
        facet.open_scene(b.write_glb(tmp_path / "short.glb"))


def test_materials_textures_samplers_and_transforms(tmp_path):
    b = GltfBuilder()
    image = np.zeros((2, 2, 4), np.uint8)
    image[..., 3] = 255
    tex = b.texture(png(image), {"magFilter": 9728, "minFilter": 9728, "wrapS": 33648,
                                 "wrapT": 33071})
    mat = b.material(
        pbrMetallicRoughness={"baseColorTexture": {"index": tex, "extensions": {
            "KHR_texture_transform": {"offset": [0.5, 0.25], "scale": [2, 3], "texCoord": 1}}},
            "metallicRoughnessTexture": {"index": tex}},
        normalTexture={"index": tex, "scale": 0.5}, occlusionTexture={"index": tex,
                                                                      "strength": 0.3},
        emissiveTexture={"index": tex}, emissiveFactor=[1, 0.5, 0],
        extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 4.0},
                    "KHR_materials_unlit": {}},
        alphaMode="MASK", alphaCutoff=0.3, doubleSided=True)
    quad(b, mat)
    b.node(mesh=0)
    b.doc["extensionsUsed"] = ["KHR_texture_transform", "KHR_materials_emissive_strength",
                               "KHR_materials_unlit"]
    m = facet.open_scene(b.write_glb(tmp_path / "m.glb")).objects[0].material
    assert m.alpha_mode == "MASK" and m.alpha_cutoff == pytest.approx(0.3) and m.double_sided
    assert m.unlit and m.emissive_strength == 4.0 and m.normal_scale == 0.5
    assert m.occlusion_strength == pytest.approx(0.3)
    assert set(m.slots) == {"base_color", "metallic_roughness", "normal", "occlusion",
                            "emissive"}
    slot = m.base_color_texture
    assert slot.texcoord == 1 and slot.wrap == ("mirror", "clamp")
    assert slot.filter == ("nearest", "nearest") and not slot.mipmaps
    # The transform acts on facet's uvs (v up) as the extension's does on glTF's (v down):
    # glTF (u, v) -> (2u + 0.5, 3v + 0.25); in facet's terms v' = 1 - v.
    u, v = 0.2, 0.3
    gl_u, gl_v = 2 * u + 0.5, 3 * (1 - v) + 0.25
    np.testing.assert_allclose(slot.transform @ [u, v, 1], [gl_u, 1 - gl_v, 1], atol=1e-12)
    assert m.base_color_texture.texture is m.emissive_texture.texture  # one image, decoded once


def test_default_material_vertex_colours_and_unsupported_extensions(tmp_path):
    b = GltfBuilder()
    col = b.accessor(np.array([[0.5, 0.5, 0.5, 1]] * 4, float))
    quad(b, None, COLOR_0=col)
    b.node(mesh=0)
    path = b.write_glb(tmp_path / "c.glb")
    obj = facet.open_scene(path).objects[0]
    np.testing.assert_allclose(obj.material.base_color, [1, 1, 1, 1])  # glTF's default
    # Linear 0.5 stored sRGB-encoded (facet's vertex colours are): 0.7354.
    np.testing.assert_allclose(obj.mesh.colors[:, :3], 0.7354, atol=1e-3)
    b.doc["extensionsUsed"] = ["EXT_made_up"]
    with pytest.warns(FacetWarning, match="ignores the glTF extension.*EXT_made_up"):
        facet.open_scene(b.write_glb(tmp_path / "used.glb"))
    b.doc["extensionsRequired"] = ["EXT_made_up"]
    with pytest.raises(MeshError, match="requires the glTF extension.*EXT_made_up"):
        facet.open_scene(b.write_glb(tmp_path / "required.glb"))


def test_cameras_are_named_and_the_default_view_stays_framed(tmp_path):
    b = GltfBuilder()
    quad(b)
    b.node(mesh=0)
    b.doc["cameras"] = [{"type": "perspective", "name": "persp",
                         "perspective": {"yfov": np.radians(50), "znear": 0.1, "zfar": 50}},
                        {"type": "orthographic", "name": "top",
                         "orthographic": {"xmag": 2, "ymag": 1.5, "znear": 0.01, "zfar": 9}}]
    b.node(camera=0, translation=[0.5, 0.5, 4])
    b.node(camera=1, translation=[0.5, 0.5, 3], rotation=_quat((0, 1, 0), 30))
    scene = facet.open_scene(b.write_glb(tmp_path / "cams.glb"))
    assert list(scene.cameras) == ["persp", "top"] and scene.camera() is None
    persp = scene.camera("persp")
    assert persp.fov_y == pytest.approx(50) and persp.far == 50
    np.testing.assert_allclose(persp.eye, [0.5, 0.5, 4], atol=1e-9)
    np.testing.assert_allclose(persp.forward, [0, 0, -1], atol=1e-9)
    top = scene.camera("top")
    assert top.is_orthographic and top.ortho_height == pytest.approx(3.0)
    np.testing.assert_allclose(top.forward, [-np.sin(np.radians(30)), 0,
                                             -np.cos(np.radians(30))], atol=1e-9)


def test_missing_files_and_bad_files_name_what_they_need(tmp_path):
    b = GltfBuilder()
    quad(b)
    b.node(mesh=0)
    path = b.write_gltf(tmp_path / "box.gltf", "box.bin")
    (tmp_path / "box.bin").unlink()
    with pytest.raises(MeshError, match=r"box.gltf: needs the buffer file 'box.bin', which "
                                        r"is not in"):
        facet.open_scene(path)
    b2 = GltfBuilder()
    b2.doc["images"] = [{"uri": "gone.png"}]
    b2.doc["textures"] = [{"source": 0}]
    mat = b2.material(pbrMetallicRoughness={"baseColorTexture": {"index": 0}})
    quad(b2, mat)
    b2.node(mesh=0)
    with pytest.warns(FacetWarning, match="texture file 'gone.png' not found"):
        scene = facet.open_scene(b2.write_gltf(tmp_path / "t.gltf"))
    assert scene.objects[0].material.base_color_texture is None  # drawn without it
    (tmp_path / "junk.glb").write_bytes(b"glTF\x02\x00\x00\x00garbage")
    with pytest.raises(MeshError, match="junk.glb"):
        facet.open_scene(tmp_path / "junk.glb")


def test_degenerate_triangles(tmp_path):
    b = GltfBuilder()
    pos = b.accessor(np.array([[0, 0, 0], [1, 1, 1], [2, 2, 2]], float), minmax=True)
    b.node(mesh=b.mesh([{"attributes": {"POSITION": pos}}]))
    with pytest.raises(MeshError, match="all 1 triangles have zero area"):
        facet.open_scene(b.write_glb(tmp_path / "flat.glb"))


def test_dracopy_is_a_core_dependency():
    """Draco files open in a default install: the distribution requires DracoPy with no
    extra (it was the 'draco' extra: a plain install refused such files)."""
    import tomllib

    with open(Path(__file__).resolve().parents[1] / "pyproject.toml", "rb") as f:
        core = tomllib.load(f)["project"]["dependencies"]
    assert any(r.lower().startswith("dracopy") for r in core), core


def test_draco_needs_dracopy_and_decodes_with_it(monkeypatch):
    draco = shared_gltf("Box/draco/Box.gltf")
    plain = facet.open_scene(shared_gltf("Box/Box.glb"))
    decoded = facet.open_scene(draco)
    a, b = decoded.objects[0].mesh, plain.objects[0].mesh
    assert a.face_count == b.face_count == 12
    np.testing.assert_allclose(np.sort(a.positions, axis=0), np.sort(b.positions, axis=0),
                               atol=1e-3)
    monkeypatch.setitem(sys.modules, "DracoPy", None)  # as if it were not installed
    with pytest.raises(MeshError, match=r"Draco-compressed .*pip install DracoPy"):
        facet.open_scene(draco)


@pytest.mark.parametrize("name,parts", [
    ("Box/Box.glb", 1), ("BoxVertexColors/BoxVertexColors.glb", 1),
    ("OrientationTest/OrientationTest.glb", 13),
    ("TextureCoordinateTest/TextureCoordinateTest.glb", 5),
    ("TextureSettingsTest/TextureSettingsTest.glb", 10),
    ("VertexColorTest/VertexColorTest.glb", 2), ("AlphaBlendModeTest/AlphaBlendModeTest.glb", 9),
    ("NormalTangentTest/NormalTangentTest.glb", 1), ("Cameras/Cameras.gltf", 1),
    ("SimpleSparseAccessor/SimpleSparseAccessor.gltf", 1),
])
def test_khronos_samples_load_as_parts(name, parts):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # these use nothing facet leaves out
        scene = facet.open_scene(shared_gltf(name))
    assert len(scene.objects) == parts
    assert all(isinstance(o.material, PbrMaterial) for o in scene.objects)


def test_samples_features_arrive():
    sparse = facet.open_scene(shared_gltf("SimpleSparseAccessor/SimpleSparseAccessor.gltf"))
    assert sparse.objects[0].mesh.positions[:, 1].max() > 2.5  # the sparse peaks (4 high)
    colors = facet.open_scene(shared_gltf("VertexColorTest/VertexColorTest.glb"))
    # The test panel has a texture and vertex colours: both kept (they multiply).
    assert any(o.material.base_color_texture is not None and o.mesh.colors is not None
               for o in colors.objects)
    blend = facet.open_scene(shared_gltf("AlphaBlendModeTest/AlphaBlendModeTest.glb"))
    assert {o.material.alpha_mode for o in blend.objects} == {"OPAQUE", "MASK", "BLEND"}
    cams = facet.open_scene(shared_gltf("Cameras/Cameras.gltf"))
    assert len(cams.cameras) == 2 and cams.camera() is None
    ntt = facet.open_scene(shared_gltf("NormalTangentTest/NormalTangentTest.glb"))
    assert ntt.objects[0].mesh.tangents is not None  # computed: the file has none


def test_command_line_renders_the_parts_as_the_scene_file_does(tmp_path):
    """`facet render model.glb` and a scene file naming it draw the same picture (per-part
    materials, node transforms)."""
    glb = shared_gltf("OrientationTest/OrientationTest.glb")
    toml = tmp_path / "s.toml"
    toml.write_text(f'[[objects]]\nmesh = "{glb.as_posix()}"\n')
    outs = []
    for model in (glb, toml):
        out = tmp_path / f"{model.stem}-{model.suffix[1:]}.png"
        assert main(["render", str(model), "-o", str(out), "--size", "96x72", "-q"]) == 0
        outs.append(np.asarray(__import__("PIL.Image").Image.open(out)))
    np.testing.assert_array_equal(outs[0], outs[1])
    colours = outs[0].reshape(-1, outs[0].shape[-1])[:, :3]
    # The arrows keep their colours (red, green, blue), not one material for all.
    for channel in range(3):
        others = [c for c in range(3) if c != channel]
        strong = (colours[:, channel] > 120) & (colours[:, others].max(1) < 80)
        assert strong.sum() > 5, channel


def test_a_models_own_camera_by_first_or_index(tmp_path, capsys):
    """`--camera first` (or an index, or the name `facet info` lists) renders through the
    file's own camera, the same picture as by its name; a scene file's render.camera takes
    the same; a wrong one is one line listing them (first and indices were refused)."""
    path = shared_gltf("Cameras/Cameras.gltf")
    scene = facet.open_scene(path)
    names = list(scene.cameras)
    assert scene.camera("first") is scene.cameras[names[0]]
    assert scene.camera("1") is scene.cameras[names[1]]
    pictures = []
    for pick in ("first", "0", names[0]):
        out = tmp_path / f"{pick}.png"
        assert main(["render", str(path), "--camera", pick, "-o", str(out), "--size", "64x48",
                     "-q"]) == 0
        pictures.append(np.asarray(__import__("PIL.Image").Image.open(out)))
    framed = tmp_path / "framed.png"
    assert main(["render", str(path), "-o", str(framed), "--size", "64x48", "-q"]) == 0
    np.testing.assert_array_equal(pictures[0], pictures[1])
    np.testing.assert_array_equal(pictures[0], pictures[2])
    assert not np.array_equal(pictures[0], np.asarray(__import__("PIL.Image").Image.open(framed)))
    toml = tmp_path / "s.toml"
    toml.write_text('[render]\ncamera = "1"\n\n'
                    '[cameras.near]\ntype = "perspective"\neye = [0, 0, 3]\n\n'
                    '[cameras.far]\ntype = "perspective"\neye = [0, 0, 9]\n\n'
                    '[[objects]]\nprimitive = "cube"\n')
    assert facet.load(toml).camera().eye[2] == 9  # (the second camera, "far")
    assert main(["render", str(path), "--camera", "7", "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'first', or an index 0-1" in err[0], err
