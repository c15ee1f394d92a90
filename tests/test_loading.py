"""Mesh loading through trimesh: formats, materials, normals, and every kind of bad file."""

import numpy as np
import pytest
import trimesh

from facet.errors import FacetError, MeshError
from facet.scene import Mesh
from facet.scene.normals import smooth_normals
from facet.scene.pbr import PbrMaterial

from conftest import shared_model


def test_smooth_normals_of_a_sphere_point_outwards():
    ico = trimesh.creation.icosphere(subdivisions=3)
    n = smooth_normals(np.asarray(ico.vertices, np.float32), np.asarray(ico.faces))
    v = ico.vertices / np.linalg.norm(ico.vertices, axis=1, keepdims=True)
    assert np.all(np.sum(n * v, axis=1) > 0.995)


def test_flat_shaded_uses_face_normals():
    mesh = Mesh.load(_write(trimesh.creation.box(), "box.stl"), crease=180)
    flat = mesh.flat_shaded()
    assert flat.face_count == 12 and flat.vertex_count == 36
    # Every normal is axis-aligned (a face normal of the cube), unlike the welded smooth ones
    # (crease 180: one vertex per corner position, its normal the mean of three faces).
    assert np.allclose(np.abs(flat.normals).max(axis=1), 1.0)
    assert mesh.vertex_count == 8
    assert not np.allclose(np.abs(mesh.normals).max(axis=1), 1.0)


_TMP = {}


def _write(tm, name):
    import tempfile
    from pathlib import Path

    d = _TMP.setdefault("dir", Path(tempfile.mkdtemp()))
    tm.export(d / name)
    return d / name


@pytest.mark.parametrize("ext", ["obj", "stl", "ply", "off", "glb"])
def test_formats_load_the_same_surface(ext):
    ico = trimesh.creation.icosphere(subdivisions=2)
    mesh = Mesh.load(_write(ico, f"ico.{ext}"))
    assert mesh.face_count == 320
    assert np.allclose(mesh.bounds, [[-1, -1, -1], [1, 1, 1]], atol=1e-6)
    assert mesh.vertex_count == 162  # STL's triangle soup is welded for smooth normals


def test_obj_normals_from_file_are_kept(tmp_path):
    (tmp_path / "t.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0.6 0 0.8\nvn 0.6 0 0.8\n"
                                    "vn 0.6 0 0.8\nf 1//1 2//2 3//3\n")
    mesh = Mesh.load(tmp_path / "t.obj")
    assert np.allclose(mesh.normals, [0.6, 0, 0.8], atol=1e-6)


def test_mtl_material(tmp_path):
    (tmp_path / "m.mtl").write_text("newmtl red\nKd 0.9 0.1 0.2\nKs 0.4 0.4 0.4\nNs 50\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                    "f 1 2 3\n")
    mat = Mesh.load(tmp_path / "m.obj").material
    assert np.allclose(mat.color, [0.9, 0.1, 0.2]) and mat.ks == pytest.approx(0.4)
    assert mat.shininess == 50 and mat.kd == 1.0


def test_gltf_base_color(tmp_path):
    box = trimesh.creation.box()
    box.visual = trimesh.visual.TextureVisuals(material=trimesh.visual.material.PBRMaterial(
        baseColorFactor=[51, 204, 102, 255], roughnessFactor=0.5))
    box.export(tmp_path / "b.glb")
    mat = Mesh.load(tmp_path / "b.glb").material
    # glTF's factors are linear and kept as they are; metallic defaults to 1 (the spec's).
    assert isinstance(mat, PbrMaterial)
    assert np.allclose(mat.base_color, [0.2, 0.8, 0.4, 1.0], atol=1 / 255)
    assert mat.roughness == pytest.approx(0.5) and mat.metallic == 1.0
    assert mat.kd == 0.0 and mat.shininess > 10  # the Phong stand-ins: a metal


def test_no_material_when_the_file_has_none():
    assert Mesh.load(_write(trimesh.creation.box(), "plain.ply")).material is None


@pytest.mark.parametrize("name,content,message", [
    ("missing.obj", None, "no such file"),
    ("mesh.abc", "1 2 3\n", "unknown mesh format '.abc'"),
    ("empty.obj", "", "the file is empty"),
    ("garbage.ply", "ply\nformat nonsense 9\nthis is not a ply\n", "cannot read the file"),
    ("truncated.stl", b"\0" * 80 + (1000).to_bytes(4, "little") + b"\1" * 100,
     "cannot read the file"),
    ("nofaces.obj", "v 0 0 0\nv 1 0 0\n", "0 faces"),
    ("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "NaN or infinite"),
    ("inf.obj", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n", "NaN or infinite"),
])
def test_bad_files_raise_mesh_error_naming_the_file(tmp_path, name, content, message):
    path = tmp_path / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif content is not None:
        path.write_text(content)
    with pytest.raises(MeshError, match=message) as info:
        Mesh.load(path)
    assert name in str(info.value)
    assert isinstance(info.value, FacetError)


def test_directory_is_rejected(tmp_path):
    (tmp_path / "dir.obj").mkdir()
    with pytest.raises(MeshError, match="is a directory"):
        Mesh.load(tmp_path / "dir.obj")


@pytest.mark.parametrize("name,faces", [("stanford-bunny.obj", 69451), ("suzanne.obj", 968),
                                        ("spot.obj", 5856), ("teapot.obj", 6320)])
def test_real_meshes_load(name, faces):
    """Face counts after triangulation (suzanne's 468 quads become 936 triangles)."""
    mesh = Mesh.load(shared_model(name))
    assert mesh.face_count == faces
    assert np.all(np.isfinite(mesh.normals))
    assert np.allclose(np.linalg.norm(mesh.normals, axis=1), 1, atol=1e-4)
