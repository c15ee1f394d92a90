"""Points and lines (facet.Points, facet.Lines): discs of a size in pixels or a world radius
whose depth and id are exact at their centres and whose coverage is the disc's (numpy
reference: the pixel centres within the radius), lines of a width in pixels, the tracers'
spheres and capsules where the rasterizer draws its discs and lines, and the files they come
from (PLY, XYZ, PTS, PCD, OBJ l, glTF POINTS / LINES)."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import facet
from facet.cli import main

from conftest import SHARED_GLTF, shared_model

W, H = 64, 48
CAM = facet.Camera.look_at((0.3, -0.2, 6), (0.3, -0.2, 0), fov_y=40)
CENTRES = np.array([[0.0, 0.0, 0.0], [1.0, 0.5, -1.0], [-1.2, -0.8, 1.0]])


def _project(p):
    """Pixel coordinates (x right, y down; pixel centres at +0.5) and view depth of p."""
    proj = CAM.projection(W, H) @ CAM.view
    clip = proj @ np.append(p, 1.0)
    ndc = clip[:3] / clip[3]
    x, y = (ndc[0] + 1) / 2 * W, (1 - ndc[1]) / 2 * H
    return x, y, -(CAM.view @ np.append(p, 1.0))[2]


def _disc_mask(x, y, radius_px):
    yy, xx = np.mgrid[0:H, 0:W] + 0.5
    return (xx - x) ** 2 + (yy - y) ** 2 <= radius_px ** 2


@pytest.mark.parametrize("size", [5.0, 9.0])
def test_screen_size_discs_cover_their_disc_with_exact_depth_and_ids(renderer, size):
    scene = facet.Scene()
    for c in CENTRES:  # one object per point: each its own id
        scene.add(facet.Points([c], size=size))
    f = renderer(W, H).render(scene, CAM, aa="none", outputs=("color", "depth", "ids"))
    for k, c in enumerate(CENTRES):
        x, y, depth = _project(c)
        want = _disc_mask(x, y, size / 2)
        got = f.object_ids == k
        assert (want != got).sum() <= 2, (k, (want != got).sum())
        assert f.depth[int(y), int(x)] == pytest.approx(depth, rel=1e-6)
        assert np.allclose(f.depth[got], depth, rtol=1e-6)  # a flat disc at its depth


def test_world_size_discs_shrink_with_distance(renderer):
    """A disc of radius r at view depth z is r f / z pixels in radius (f: the focal length
    in pixels)."""
    scene = facet.Scene()
    for c in CENTRES:
        scene.add(facet.Points([c], radius=0.15))
    f = renderer(W, H).render(scene, CAM, aa="none", outputs=("ids",))
    focal = H / 2 / np.tan(np.radians(40) / 2)
    for k, c in enumerate(CENTRES):
        x, y, depth = _project(c)
        want = _disc_mask(x, y, 0.15 * focal / depth)
        assert ((f.object_ids == k) != want).sum() <= 3


def test_lines_cover_their_width(renderer):
    """A horizontal line through pixel-centre row 20, 3 pixels wide: rows 19-21 covered in
    every column it crosses, nothing else; its depth interpolates along it."""
    x0, y0, z = _project(np.array([0.0, 0.0, 0.0]))
    # The world point on the camera's pixel-centre row 20.5 at depth z, spanning the view.
    inv = np.linalg.inv(CAM.projection(W, H) @ CAM.view)
    ndc_y = 1 - 2 * 20.5 / H

    def world(ndc_x):
        clip_z = (CAM.projection(W, H) @ CAM.view @ np.array([0, 0, 0, 1.0]))
        p = inv @ np.array([ndc_x, ndc_y, clip_z[2] / clip_z[3], 1.0])
        return p[:3] / p[3]

    line = facet.Lines([world(-2.0), world(2.0)], width=3)
    scene = facet.Scene()
    scene.add(line)
    f = renderer(W, H).render(scene, CAM, aa="none", outputs=("ids", "depth"))
    covered = f.object_ids == 0
    rows = np.flatnonzero(covered.any(axis=1))
    assert rows.tolist() == [19, 20, 21]
    assert covered[19:22].all()
    assert np.allclose(f.depth[20], z, rtol=1e-5)


def test_points_with_normals_are_lit_and_without_show_their_colour(renderer):
    rng = np.random.default_rng(1)
    n = rng.normal(size=(400, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    lit, flat = facet.Scene(), facet.Scene()
    lit.add(facet.Points(n, normals=n, size=6), facet.Material((0.8, 0.8, 0.8)))
    flat.add(facet.Points(n, colors=np.tile([255, 128, 0], (400, 1)).astype(np.uint8),
                          size=6, edl=False))
    r = renderer(W, H)
    a = r.render(lit, CAM).color[..., :3].astype(int)
    b = r.render(flat, CAM).color[..., :3].astype(int)
    shown = b.sum(axis=2) > 0
    assert np.all(np.abs(b[shown] - [255, 128, 0]).max(axis=1) <= 1)  # unlit: as given
    values = a[a.sum(axis=2) > 0].sum(axis=1)
    assert values.max() - values.min() > 150  # lit: bright facing the light, dark away


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_the_tracers_see_points_as_spheres_and_lines_as_capsules(renderer, engine):
    """Where the rasterizer draws a disc or a line, the tracers hit a sphere or capsule of
    the same size in pixels: a disc's coverage within a pixel ring and the same ids at the
    centres; a line as wide (within a pixel) and as long but for its round ends (the
    rasterizer's ends are square, the capsule's reach its radius further)."""
    scene = facet.Scene()
    for c in CENTRES:
        scene.add(facet.Points([c], size=9.0))
    scene.add(facet.Lines([[-2, 1.3, 0], [2, 1.3, 0]], width=4))
    r = renderer(W, H)
    raster = r.render(scene, CAM, aa="none", outputs=("ids",)).object_ids
    traced = r.render(scene, CAM, aa="none", outputs=("ids",), engine=engine).object_ids
    for k in range(3):
        a, b = raster == k, traced == k
        assert a.sum() > 8
        assert abs(int(a.sum()) - int(b.sum())) <= 0.25 * a.sum(), (k, a.sum(), b.sum())
    a, b = raster == 3, traced == 3
    middle = W // 2
    assert abs(int(a[:, middle].sum()) - int(b[:, middle].sum())) <= 1
    span_a, span_b = np.flatnonzero(a.any(axis=0)), np.flatnonzero(b.any(axis=0))
    assert 0 <= span_a[0] - span_b[0] <= 3 and 0 <= span_b[-1] - span_a[-1] <= 3
    for c in CENTRES:
        x, y, _ = _project(c)
        assert raster[int(y), int(x)] == traced[int(y), int(x)]


# -- files ----------------------------------------------------------------------------------
def test_point_cloud_files_load_positions_colours_and_normals(tmp_path):
    ply = tmp_path / "c.ply"
    ply.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty "
                   "float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty "
                   "float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
                   "end_header\n0 0 0 0 0 1 255 0 0\n1 0 0 0 0 1 0 255 0\n0 1 0 0 0 1 0 0 "
                   "255\n")
    pts = tmp_path / "c.pts"
    pts.write_text("3\n0 0 0 10 255 0 0\n1 0 0 20 0 255 0\n0 1 0 30 0 0 255\n")
    xyz = tmp_path / "c.xyz"
    xyz.write_text("0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n")
    pcd = tmp_path / "c.pcd"
    rgb = np.array([0xFF0000, 0x00FF00, 0x0000FF], np.uint32).view(np.float32)
    header = ("VERSION 0.7\nFIELDS x y z rgb normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4 4\n"
              "TYPE F F F F F F F\nCOUNT 1 1 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\n"
              "DATA binary\n")
    body = np.zeros((3, 7), np.float32)
    body[:, :3] = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    body[:, 3] = rgb
    body[:, 6] = 1.0
    pcd.write_bytes(header.encode() + body.tobytes())
    red, green, blue = [1, 0, 0], [0, 1, 0], [0, 0, 1]
    for path, colours, normals in [(ply, True, True), (pts, True, False),
                                   (xyz, False, True), (pcd, True, True)]:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            points = facet.load(path).objects[0].mesh
        assert isinstance(points, facet.Points), path
        np.testing.assert_allclose(points.positions, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
        if colours:
            np.testing.assert_allclose(points.colors[:, :3], [red, green, blue], atol=1e-6)
        else:
            assert points.colors is None
        if normals:
            np.testing.assert_allclose(points.normals, np.tile([0, 0, 1], (3, 1)))
        else:
            assert points.normals is None


def test_obj_polylines_load_beside_faces(tmp_path):
    obj = tmp_path / "m.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nl 1 4 3\nl -1 -3\n")
    scene = facet.load(obj)
    kinds = [o.mesh.kind for o in scene.objects]
    assert kinds == ["mesh", "lines"]
    np.testing.assert_array_equal(scene.objects[1].mesh.segments, [[0, 3], [3, 2], [3, 1]])


@pytest.mark.parametrize("text, words", [
    ("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
     "POINTS 2\nDATA binary_compressed\n", "LZF"),
    ("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 9\nHEIGHT 1\n"
     "POINTS 9\nDATA ascii\n0 0 0\n", "truncated"),
    ("hello\n", "not a PCD file"),
])
def test_broken_point_files_are_one_line_and_nothing_written(tmp_path, capsys, text, words):
    path = tmp_path / "bad.pcd"
    path.write_text(text)
    out = tmp_path / "o.png"
    assert main(["render", str(path), "-o", str(out), "--size", "16x16"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert not out.exists()


def test_point_sizes_from_the_command_line_and_scene_files(tmp_path):
    from PIL import Image

    xyz = tmp_path / "c.xyz"
    xyz.write_text("0 0 0\n")
    small, big = tmp_path / "s.png", tmp_path / "b.png"
    for out, size in ((small, "3"), (big, "11")):
        assert main(["render", str(xyz), "-o", str(out), "--size", "32x32", "--msaa", "0",
                     "--point-size", size, "-q"]) == 0
    area = [(np.asarray(Image.open(p).convert("L")) > 0).sum() for p in (small, big)]
    assert area[0] < 15 < 80 < area[1]
    toml = tmp_path / "s.toml"
    toml.write_text(f'[[objects]]\nmesh = "{xyz.name}"\npoint_radius = 0.5\n')
    assert facet.load(toml).objects[0].mesh.radius == 0.5


def test_the_khronos_primitive_modes_load_without_warnings(renderer):
    """MeshPrimitiveModes: POINTS, LINES, LINE_LOOP, LINE_STRIP, TRIANGLES, TRIANGLE_STRIP
    and TRIANGLE_FAN, each drawn."""
    path = shared_model("MeshPrimitiveModes/MeshPrimitiveModes.gltf", SHARED_GLTF)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = facet.load(path)
    kinds = sorted(o.mesh.kind for o in scene.objects)
    assert kinds == ["lines"] * 3 + ["mesh"] * 3 + ["points"]
    loops = [o.mesh for o in scene.objects if o.mesh.kind == "lines" and
             o.mesh.segments[-1][1] == o.mesh.segments[0][0]]
    assert len(loops) == 1 and len(loops[0].segments) == 7  # LINE_LOOP closes
    r = renderer(128, 96)
    ids = r.render(scene, outputs=("ids",)).object_ids
    assert set(np.unique(ids)) == {-1, *range(len(scene.objects))}


def test_points_and_lines_in_a_glb_round_trip_json(tmp_path):
    """A glTF POINTS primitive with COLOR_0 keeps its colours (sRGB-encoded as every facet
    colour)."""
    from gltf_files import GltfBuilder

    b = GltfBuilder()
    pos = b.accessor(np.array([[0, 0, 0], [1, 0, 0]], float), minmax=True)
    col = b.accessor(np.array([[1, 0, 0, 1], [0, 0.5, 0, 1]], float))
    b.node(mesh=b.mesh([{"attributes": {"POSITION": pos, "COLOR_0": col}, "mode": 0}]))
    path = b.write_gltf(tmp_path / "p.gltf")
    points = facet.load(path).objects[0].mesh
    assert isinstance(points, facet.Points)
    assert points.colors[0, 0] == pytest.approx(1.0)
    assert points.colors[1, 1] == pytest.approx(0.7354, abs=1e-3)  # sRGB of linear 0.5
    json.loads(path.read_text())


def test_eye_dome_lighting_darkens_what_lies_behind_a_nearer_edge(renderer):
    """Unlit clouds are shaded by eye-dome lighting (glsl/lib/edl.glsl): a flat sheet
    facing the camera keeps its colour; where a nearer sheet overlaps it, the far sheet's
    pixels along the edge darken and the near sheet's do not. With edl=False nothing
    darkens."""
    g = np.linspace(-1, 1, 120)
    xx, yy = np.meshgrid(g, g)
    far = np.stack([xx.ravel(), yy.ravel(), np.full(xx.size, -1.0)], axis=1)
    near = far[far[:, 0] < 0] + [0, 0, 1.5]
    white = np.full((len(far) + len(near), 3), 200, np.uint8)
    r = renderer(W, H)
    cam = facet.Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=40)
    shots = {}
    for edl in (True, False):
        scene = facet.Scene()
        scene.add(facet.Points(np.vstack([far, near]), colors=white, size=3, edl=edl))
        shots[edl] = r.render(scene, cam, aa="none").color[..., 0].astype(int)
    plain = shots[False]
    assert (plain[plain > 0] == 200).all()
    lit = shots[True]
    covered = plain > 0
    darkened = covered & (lit < 190)
    cols = np.flatnonzero(darkened.any(axis=0))
    assert cols.size and (cols >= W // 2 - 3).all()  # only right of the near sheet's edge
    row = lit[H // 2]
    edge = int(np.flatnonzero(darkened[H // 2])[0])
    assert row[edge + 3] == 200 and row[edge - 4] == 200  # each sheet flat: not darkened


def test_a_dataset_renders_a_point_cloud(tmp_path):
    """A dataset job on a point-cloud file writes its views, the cloud in them."""
    from PIL import Image

    from batch_data import write_manifest
    from conftest import ROOT

    manifest = write_manifest(tmp_path, [{"model": str(ROOT / "models" / "helix-points.ply"),
                                          "name": "helix", "views": 2, "size": [32, 32],
                                          "outputs": ["color", "ids"]}])
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"]) == 0
    images = sorted((tmp_path / "out" / "helix").rglob("*.png"))
    colour = [p for p in images if "ids" not in p.name and "depth" not in p.name]
    assert colour and (np.asarray(Image.open(colour[0]).convert("L")) > 0).sum() > 30


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_the_tracers_say_they_light_unlit_points_and_lines(engine):
    scene = facet.Scene()
    scene.add(facet.Points(CENTRES, size=4))
    with facet.Renderer(W, H) as r:  # (a renderer says each line once)
        with pytest.warns(facet.FacetWarning, match="points as lit spheres"):
            r.render(scene, CAM, engine=engine, outputs=("color",))
