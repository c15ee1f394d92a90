"""Normals where files bring none (crease splitting), tangent frames, PLY triangle strips,
OBJ files with missing material libraries or textures, degenerate triangles, and z-up
framing (facet.scene.normals, facet.formats.loading, facet.geometry.camera)."""

import warnings

import numpy as np
import pytest
import trimesh

from facet.cli import main
from facet.errors import FacetWarning, MeshError
from facet.geometry.camera import Camera
from facet.geometry.framing import default_direction
from facet.scene import Mesh
from facet.scene.normals import crease_normals, tangents


def _stl(tmp_path, tm, name="m.stl"):
    path = tmp_path / name
    tm.export(path)
    return path


def test_a_cube_without_normals_gets_24_axis_aligned_vertices(tmp_path):
    mesh = Mesh.load(_stl(tmp_path, trimesh.creation.box()))
    assert mesh.vertex_count == 24 and mesh.face_count == 12
    assert np.allclose(np.abs(mesh.normals).max(axis=1), 1.0)  # every one axis-aligned
    # Each normal is its face's: the vertex lies on the face the normal points out of.
    tri = mesh.positions[mesh.faces]
    face_n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    face_n /= np.linalg.norm(face_n, axis=1, keepdims=True)
    np.testing.assert_allclose(mesh.normals[mesh.faces], np.repeat(face_n[:, None], 3, 1),
                               atol=1e-6)


def test_a_sphere_stays_smooth_and_crease_180_welds_everything(tmp_path):
    ico = trimesh.creation.icosphere(subdivisions=3)
    path = _stl(tmp_path, ico, "ico.stl")  # STL repeats vertices per face, no normals
    mesh = Mesh.load(path)
    assert mesh.vertex_count == len(ico.vertices)  # welded, nothing split
    radial = mesh.positions / np.linalg.norm(mesh.positions, axis=1, keepdims=True)
    assert np.all(np.sum(mesh.normals * radial, axis=1) > 0.995)
    assert Mesh.load(_stl(tmp_path, trimesh.creation.box(), "b.stl"), crease=180) \
        .vertex_count == 8
    faceted = Mesh.load(path, crease=0)
    assert faceted.vertex_count == 3 * faceted.face_count


def test_crease_angle_threshold_and_seams():
    """Two triangles folded by 40 degrees: one group below a 45-degree crease, split above
    30; vertices that differ in uv (a seam) stay apart even when smooth."""
    a = np.radians(40)
    pos = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -np.cos(a), np.sin(a)]])
    faces = np.array([[0, 1, 2], [0, 3, 1]])
    src, new_faces, normals = crease_normals(pos, faces, 45)
    assert len(src) == 4  # shared edge vertices stay shared
    src, new_faces, normals = crease_normals(pos, faces, 30)
    assert len(src) == 6
    uv = np.array([[0, 0], [1, 0], [0, 1], [0, -1.0]])
    seam = np.vstack([pos, pos[:2]])
    seam_faces = np.array([[0, 1, 2], [4, 3, 5]])
    src, _, _ = crease_normals(seam, seam_faces, 45,
                               np.vstack([uv, [[5, 5], [6, 6]]]))
    assert len(src) == 6  # the seam's copies differ in uv: not welded


def test_tangents_follow_u_and_record_handedness():
    pos = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    n = np.tile([0.0, 0.0, 1.0], (4, 1))
    uv = pos[:, :2]
    t = tangents(pos, n, uv, faces)
    np.testing.assert_allclose(t, np.tile([1, 0, 0, 1], (4, 1)), atol=1e-6)
    mirrored = tangents(pos, n, uv * [1, -1], faces)  # v runs down: left-handed
    np.testing.assert_allclose(mirrored, np.tile([1, 0, 0, -1], (4, 1)), atol=1e-6)
    turned = tangents(pos, n, uv[:, ::-1] * [1, -1] + [0, 1], faces)  # u along +y
    np.testing.assert_allclose(turned[:, :3], np.tile([0, 1, 0], (4, 1)), atol=1e-6)


@pytest.mark.parametrize("binary", [False, True])
def test_ply_triangle_strips_load(tmp_path, binary):
    """A grid stored as one strip with a restart (-1), as scanners export it."""
    xs, ys = np.meshgrid(np.arange(4.0), np.arange(3.0))
    pos = np.stack([xs.ravel(), ys.ravel(), np.zeros(12)], 1)
    rows = []
    for r in range(2):  # one strip per row of quads, zig-zagging up and down
        rows.append(np.ravel(np.column_stack([np.arange(4) + 4 * r, np.arange(4) + 4 * r + 4])))
    strip = np.concatenate([rows[0], [-1], rows[1]])
    header = ["ply", f"format {'binary_little_endian' if binary else 'ascii'} 1.0",
              "element vertex 12", "property float x", "property float y",
              "property float z", "element tristrips 1",
              "property list int int vertex_indices", "end_header"]
    path = tmp_path / "strip.ply"
    if binary:
        body = pos.astype("<f4").tobytes() + np.array([len(strip)], "<i4").tobytes() + \
            strip.astype("<i4").tobytes()
        path.write_bytes(("\n".join(header) + "\n").encode() + body)
    else:
        lines = header + [" ".join(map(str, p)) for p in pos] + \
            [" ".join(map(str, [len(strip), *strip]))]
        path.write_text("\n".join(lines) + "\n")
    mesh = Mesh.load(path)
    assert mesh.face_count == 12  # 2 rows x 3 quads x 2 triangles
    tri = mesh.positions[mesh.faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert np.all(n[:, 2] < 0) or np.all(n[:, 2] > 0)  # one consistent winding
    assert np.isclose(np.abs(n[:, 2]).sum() / 2, 6.0)  # covers the 3 x 2 grid once


def test_obj_with_missing_mtl_or_texture_loads_with_one_warning(tmp_path):
    obj = tmp_path / "m.obj"
    obj.write_text("mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.warns(FacetWarning, match=r"material library 'gone.mtl' not found") as rec:
        mesh = Mesh.load(obj)
    assert len(rec) == 1 and mesh.face_count == 1
    (tmp_path / "here.mtl").write_text("newmtl a\nKd 1 0 0\nmap_Kd missing.png\n")
    obj.write_text("mtllib here.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                   "vt 0 1\nf 1/1 2/2 3/3\n")
    with pytest.warns(FacetWarning, match=r"texture 'missing.png' not found"):
        Mesh.load(obj)


def test_degenerate_triangles_all_or_some(tmp_path, capsys):
    flat = tmp_path / "flat.obj"
    flat.write_text("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\nf 1 1 2\n")
    with pytest.raises(MeshError, match="all 2 triangles have zero area"):
        Mesh.load(flat)
    assert main(["render", str(flat), "-o", str(tmp_path / "f.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "zero area" in err[0] and not (tmp_path / "f.png").exists()
    some = tmp_path / "some.obj"
    some.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 2 2\nf 1 2 3\nf 1 4 4\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = Mesh.load(some)
    assert np.all(np.isfinite(mesh.normals)) and mesh.face_count == 2


def test_z_up_frames_from_above_and_orbits_about_z(tmp_path):
    bounds = np.array([[-1, -1, 0], [1, 1, 3.0]])
    cam = Camera.frame(bounds, up=(0, 0, 1))
    center = bounds.mean(axis=0)
    assert cam.eye[2] > center[2]  # looking down on it, as y-up views do
    up_world = np.linalg.inv(cam.view)[:3, 1]
    assert up_world[2] > 0.8  # the picture's up is +z
    d = default_direction((0, 0, 1))
    y = default_direction()
    # The same elevation as the y-up default: the angle to the up axis is kept.
    assert np.isclose(d[2] / np.linalg.norm(d), y[1] / np.linalg.norm(y))
    # The command line: --up z and --up 0,0,1 give the same camera, unlike the default.
    tall = trimesh.creation.cylinder(radius=0.3, height=3.0)  # along z
    path = _stl(tmp_path, tall, "tall.stl")
    cams = {}
    for flag in ("z", "0,0,1", "y"):
        out = tmp_path / f"t-{flag}.png"
        assert main(["render", str(path), "-o", str(out), "--size", "32x32", "--up", flag,
                     "-q"]) == 0
        cams[flag] = __import__("json").loads(out.with_suffix(".json").read_text())
    assert cams["z"]["world_to_camera"] == cams["0,0,1"]["world_to_camera"]
    assert cams["z"]["world_to_camera"] != cams["y"]["world_to_camera"]
    assert main(["render", str(path), "-o", str(tmp_path / "x.png"), "--up", "0,0,0"]) == 2
