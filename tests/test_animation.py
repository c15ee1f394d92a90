"""glTF animation, skins and morph targets at a chosen time, against numpy references written
here from the specification's formulas (independent of facet.scene.animation: quaternions
through axis and angle, Hermite splines from their basis), then through the renderer: a
posed scene draws exactly what the same vertices placed by hand draw."""

from __future__ import annotations

import json

import numpy as np
import pytest

import facet
from facet.cli import main

from gltf_files import UBYTE, USHORT, GltfBuilder

# -- references from the specification ------------------------------------------------------


def q_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz])


def q_axis_angle(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.append(axis * np.sin(angle / 2), np.cos(angle / 2))


def ref_slerp(q0, q1, u):
    """q0 (q0^-1 q1)^u along the shorter arc, through the relative rotation's axis-angle."""
    q0, q1 = (np.asarray(q, float) / np.linalg.norm(q) for q in (q0, q1))
    rel = q_mul(q0 * [-1, -1, -1, 1], q1)
    if rel[3] < 0:
        rel = -rel
    angle = 2 * np.arccos(np.clip(rel[3], -1, 1))
    if angle < 1e-9 or np.linalg.norm(rel[:3]) < 1e-12:
        return q0
    return q_mul(q0, q_axis_angle(rel[:3], u * angle))


def rot_matrix(q):
    """Rodrigues' formula from the quaternion's axis and angle."""
    q = np.asarray(q, float) / np.linalg.norm(q)
    angle = 2 * np.arccos(np.clip(q[3], -1, 1))
    s = np.linalg.norm(q[:3])
    if s < 1e-12:
        return np.eye(3)
    k = q[:3] / s
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def trs(t=(0, 0, 0), q=(0, 0, 0, 1), s=(1, 1, 1)):
    m = np.eye(4)
    m[:3, :3] = rot_matrix(q) @ np.diag(s)
    m[:3, 3] = t
    return m


def hermite(v0, b0, v1, a1, span, u):
    """The specification's cubic spline: values v, out-tangent b0, in-tangent a1."""
    h00, h10 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u
    h01, h11 = -2 * u**3 + 3 * u**2, u**3 - u**2
    return h00 * v0 + h10 * span * b0 + h01 * v1 + h11 * span * a1


# -- files ----------------------------------------------------------------------------------
BOX = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
BOX_FACES = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                      [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
KEYS = np.array([0.0, 1.0, 2.5])
TRANSLATIONS = np.array([[0, 0, 0], [1, 2, 0], [-1, 0, 3]], float)
ROTATIONS = np.array([q_axis_angle((0, 0, 1), 0), q_axis_angle((0, 1, 1), 2.0),
                      q_axis_angle((1, 0, 0), -1.0)])
SCALES = np.array([[1, 1, 1], [2, 1, 0.5], [1, 3, 1]], float)
# CUBICSPLINE: (in-tangent, value, out-tangent) per key.
TANGENTS_IN = np.array([[0, 0, 0], [1, -1, 0.5], [0.2, 0, 0]], float)
TANGENTS_OUT = np.array([[2, 0, 1], [-0.5, 1, 0], [0, 0, 0]], float)


def _box(b: GltfBuilder) -> int:
    pos = b.accessor(BOX, minmax=True)
    idx = b.accessor(BOX_FACES.reshape(-1), USHORT)
    return b.mesh([{"attributes": {"POSITION": pos}, "indices": idx}])


def _sampler(b, times, values, mode):
    return {"input": b.accessor(np.asarray(times, float), minmax=True),
            "output": b.accessor(np.asarray(values, float)), "interpolation": mode}


def animated_box(tmp_path, t_mode="STEP", r_mode="LINEAR", s_mode="CUBICSPLINE"):
    """A box under a parent node, its translation, rotation and scale animated by three
    samplers (the interpolation of each chosen)."""
    b = GltfBuilder()
    child = b.node(root=False, mesh=_box(b))
    b.node(children=[child], translation=[0.5, 0, 0], rotation=list(
        q_axis_angle((0, 1, 0), 0.3)))
    values = {"translation": TRANSLATIONS, "rotation": ROTATIONS, "scale": SCALES}
    modes = {"translation": t_mode, "rotation": r_mode, "scale": s_mode}
    samplers, channels = [], []
    for path, v in values.items():
        if modes[path] == "CUBICSPLINE":
            ins = TANGENTS_IN if path != "rotation" else np.zeros((3, 4))
            outs = TANGENTS_OUT if path != "rotation" else np.zeros((3, 4))
            v = np.stack([ins, v, outs], axis=1).reshape(-1, v.shape[1])
        samplers.append(_sampler(b, KEYS, v, modes[path]))
        channels.append({"sampler": len(samplers) - 1,
                         "target": {"node": child, "path": path}})
    b.doc["animations"] = [{"name": "move", "samplers": samplers, "channels": channels}]
    return b.write_gltf(tmp_path / "box.gltf")


def ref_value(path, mode, t):
    v = {"translation": TRANSLATIONS, "rotation": ROTATIONS, "scale": SCALES}[path]
    if t <= KEYS[0]:
        return v[0]
    if t >= KEYS[-1]:
        return v[-1]
    k = int(np.searchsorted(KEYS, t, side="right") - 1)
    span = KEYS[k + 1] - KEYS[k]
    u = (t - KEYS[k]) / span
    if mode == "STEP":
        return v[k]
    if mode == "LINEAR":
        return ref_slerp(v[k], v[k + 1], u) if path == "rotation" else \
            v[k] + u * (v[k + 1] - v[k])
    zero = np.zeros_like(v[0])
    ins = TANGENTS_IN if path != "rotation" else None
    outs = TANGENTS_OUT if path != "rotation" else None
    out = hermite(v[k], zero if outs is None else outs[k], v[k + 1],
                  zero if ins is None else ins[k + 1], span, u)
    return out / np.linalg.norm(out) if path == "rotation" else out


PARENT = trs((0.5, 0, 0), q_axis_angle((0, 1, 0), 0.3))


@pytest.mark.parametrize("modes", [("STEP", "LINEAR", "CUBICSPLINE"),
                                   ("LINEAR", "CUBICSPLINE", "STEP"),
                                   ("CUBICSPLINE", "STEP", "LINEAR")])
@pytest.mark.parametrize("t", [-1.0, 0.0, 0.4, 1.0, 1.7, 2.5, 9.0])
def test_a_node_at_time_t_follows_the_specification(tmp_path, modes, t):
    scene = facet.load(animated_box(tmp_path, *modes))
    got = scene.at(t).objects[0].transform
    want = PARENT @ trs(ref_value("translation", modes[0], t),
                        ref_value("rotation", modes[1], t), ref_value("scale", modes[2], t))
    np.testing.assert_allclose(got, want, atol=1e-5)


def test_slerp_takes_the_shorter_arc():
    from facet.scene.animation import slerp

    q0 = q_axis_angle((0, 0, 1), 0.2)
    q1 = -q_axis_angle((0, 0, 1), 1.0)  # the same rotation as +q1, the long way round
    for u in (0.25, 0.5, 0.9):
        got = slerp(q0, q1, u)
        want = q_axis_angle((0, 0, 1), 0.2 + 0.8 * u)
        assert min(np.abs(got - want).max(), np.abs(got + want).max()) < 1e-9


# -- skins ----------------------------------------------------------------------------------
def _strip():
    """A strip along y from 0 to 2 (two columns, 9 rows), its second joint at y = 1."""
    ys = np.linspace(0, 2, 9)
    pos = np.array([[x, y, 0] for y in ys for x in (-0.1, 0.1)])
    faces = np.array([[2 * r, 2 * r + 1, 2 * r + 3] for r in range(8)] +
                     [[2 * r, 2 * r + 3, 2 * r + 2] for r in range(8)])
    w1 = np.clip(pos[:, 1] - 0.5, 0, 1)
    return pos, faces, np.stack([1 - w1, w1], axis=1)


BEND = q_axis_angle((0, 0, 1), np.pi / 2)


def skinned_strip(tmp_path, eight=False):
    """Joint 0 at the origin, joint 1 its child at y = 1 turning 90 degrees about z over one
    second. ``eight``: the second joint's weights come through JOINTS_1 / WEIGHTS_1."""
    pos, faces, w = _strip()
    b = GltfBuilder()
    n = len(pos)
    if eight:
        j0 = np.tile([0, 0, 0, 0], (n, 1))
        j1 = np.tile([1, 0, 0, 0], (n, 1))
        w0 = np.column_stack([w[:, 0], np.zeros((n, 3))])
        w1 = np.column_stack([w[:, 1], np.zeros((n, 3))])
        attrs = {"JOINTS_0": b.accessor(j0, UBYTE), "WEIGHTS_0": b.accessor(w0),
                 "JOINTS_1": b.accessor(j1, UBYTE), "WEIGHTS_1": b.accessor(w1)}
    else:
        attrs = {"JOINTS_0": b.accessor(np.tile([0, 1, 0, 0], (n, 1)), UBYTE),
                 "WEIGHTS_0": b.accessor(np.column_stack([w, np.zeros((n, 2))]))}
    mesh = b.mesh([{"attributes": {"POSITION": b.accessor(pos, minmax=True), **attrs},
                    "indices": b.accessor(faces.reshape(-1), USHORT)}])
    joint1 = b.node(root=False, translation=[0, 1, 0])
    joint0 = b.node(children=[joint1])
    ibm = np.stack([np.eye(4), trs((0, -1, 0))]).transpose(0, 2, 1).reshape(2, 16)
    b.doc["skins"] = [{"joints": [joint0, joint1], "inverseBindMatrices": b.accessor(ibm)}]
    b.node(mesh=mesh, skin=0, translation=[5, 5, 5])  # ignored for skinned meshes
    b.doc["animations"] = [{"samplers": [_sampler(b, [0, 1], [[0, 0, 0, 1], BEND], "LINEAR")],
                            "channels": [{"sampler": 0,
                                          "target": {"node": joint1, "path": "rotation"}}]}]
    return b.write_gltf(tmp_path / "strip.gltf")


def ref_skin(t):
    """Linear blend skinning: sum_k w_k W(joint_k) IBM_k p."""
    pos, faces, w = _strip()
    rot = ref_slerp(np.array([0, 0, 0, 1.0]), BEND, np.clip(t, 0, 1))
    j1 = trs((0, 1, 0), rot) @ trs((0, -1, 0))
    p = np.hstack([pos, np.ones((len(pos), 1))])
    return w[:, :1] * p[:, :3] + w[:, 1:] * (p @ j1.T)[:, :3], faces


@pytest.mark.parametrize("eight", [False, True])
@pytest.mark.parametrize("t", [0.0, 0.5, 1.0])
def test_a_skinned_strip_bends_as_linear_blend_skinning(tmp_path, t, eight):
    scene = facet.load(skinned_strip(tmp_path, eight))
    obj = scene.at(t).objects[0]
    got = obj.mesh.positions @ obj.transform[:3, :3].T + obj.transform[:3, 3]
    want, _ = ref_skin(t)
    np.testing.assert_allclose(got, want, atol=1e-5)
    if t == 1.0:  # the tip turned to point along -x
        assert got[-1, 0] < -0.9 and abs(got[-1, 1] - 1.1) < 1e-5


def test_skinned_normals_turn_with_their_joints(tmp_path):
    """The strip faces +z at rest; bent about z its normals still face +z, and a box
    turned about x by its joint turns its normals with it."""
    obj = facet.load(skinned_strip(tmp_path)).at(1.0).objects[0]
    np.testing.assert_allclose(np.abs(obj.mesh.normals[:, 2]), 1.0, atol=1e-6)


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_posed_scene_draws_what_the_same_vertices_placed_by_hand_draw(tmp_path, renderer,
                                                                        engine):
    """Differential, through each engine: the skinned strip at t = 0.6 and a plain mesh
    of the reference's vertices give the same depth and ids, pixel for pixel (the tracers
    refit the rest pose's hierarchy to the moved triangles)."""
    scene = facet.load(skinned_strip(tmp_path))
    want, faces = ref_skin(0.6)
    plain = facet.Scene()
    plain.add(facet.Mesh(want, faces))
    cam = facet.Camera.look_at((0.5, 1, 5), (0.5, 1, 0), fov_y=40)
    renderer = renderer(64, 64)
    a = renderer.render(scene, cam, size=(64, 64), time=0.6, outputs=("depth", "ids"),
                        engine=engine)
    b = renderer.render(plain, cam, size=(64, 64), outputs=("depth", "ids"), engine=engine)
    assert (a.object_ids >= 0).sum() > 100
    np.testing.assert_array_equal(a.object_ids, b.object_ids)
    np.testing.assert_allclose(a.depth, b.depth, atol=1e-5)
    c = renderer.render(scene, cam, size=(64, 64), time=0.0, outputs=("ids",), engine=engine)
    assert (c.object_ids != a.object_ids).sum() > 50  # time moved it


# -- morph targets --------------------------------------------------------------------------
D0 = np.array([[0, 0, 1], [0, 0, 0], [0, 0, 0], [0, 0, 0.5]], float)
D1 = np.array([[0, 0.5, 0], [0.5, 0, 0], [0, 0, 0], [0, 0, 0]], float)
QUAD = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)


def morphed_quad(tmp_path, node_weights=None):
    b = GltfBuilder()
    mesh = b.mesh([{"attributes": {"POSITION": b.accessor(QUAD, minmax=True)},
                    "indices": b.accessor(np.array([0, 1, 2, 0, 2, 3]), USHORT),
                    "targets": [{"POSITION": b.accessor(D0)}, {"POSITION": b.accessor(D1)}]}])
    b.doc["meshes"][mesh]["weights"] = [0.25, 0.0]
    node = b.node(mesh=mesh, **({"weights": node_weights} if node_weights else {}))
    b.doc["animations"] = [{"name": "w", "samplers": [_sampler(
        b, [1, 2], np.array([[0, 0], [1, 0.5]]).reshape(-1), "LINEAR")],
        "channels": [{"sampler": 0, "target": {"node": node, "path": "weights"}}]}]
    return b.write_gltf(tmp_path / "morph.gltf")


@pytest.mark.parametrize("t, w", [(1.0, (0, 0)), (1.5, (0.5, 0.25)), (2.0, (1, 0.5)),
                                  (7.0, (1, 0.5))])
def test_morph_weights_move_vertices_as_the_weighted_sum(tmp_path, t, w):
    obj = facet.load(morphed_quad(tmp_path)).at(t).objects[0]
    np.testing.assert_allclose(obj.mesh.positions, QUAD + w[0] * D0 + w[1] * D1, atol=1e-6)


def test_default_weights_are_the_nodes_then_the_meshes(tmp_path):
    """Not animated (--animation picks a clip of a different model: none here plays) the
    node's weights win over the mesh's."""
    rest = facet.load(morphed_quad(tmp_path)).at(0.0).objects[0]  # before the first key
    np.testing.assert_allclose(rest.mesh.positions, QUAD, atol=1e-6)
    mesh = facet.Mesh.load(morphed_quad(tmp_path))  # nothing plays: the mesh's weights
    np.testing.assert_allclose(mesh.positions, QUAD + 0.25 * D0, atol=1e-6)
    mesh = facet.Mesh.load(morphed_quad(tmp_path, node_weights=[0.0, 1.0]))
    np.testing.assert_allclose(mesh.positions, QUAD + D1, atol=1e-6)


# -- fronts ---------------------------------------------------------------------------------
def test_time_means_the_same_from_every_front(tmp_path, renderer):
    """Python's time=, the command line's --time and a scene file's [render] time give the
    same picture; --time A:B writes the frames of those times."""
    from PIL import Image

    path = skinned_strip(tmp_path)
    scene = facet.load(path)
    renderer = renderer(48, 48, msaa=4)
    cam = renderer.camera(scene.at(0.5), renderer.options(scene, size=(48, 48)))
    want = renderer.render(scene, cam, size=(48, 48), time=0.5).color
    out = tmp_path / "cli.png"
    assert main(["render", str(path), "-o", str(out), "--size", "48x48", "--time", "0.5",
                 "-q"]) == 0
    np.testing.assert_array_equal(np.asarray(Image.open(out).convert("RGB")), want[..., :3])
    toml = tmp_path / "s.toml"
    toml.write_text(f'[render]\ntime = 0.5\nsize = [48, 48]\n[[objects]]\nmesh = "{path.name}"\n')
    framed = facet.load(toml)
    got = renderer.render(framed, cam).color
    np.testing.assert_array_equal(got, want)
    seq = tmp_path / "f_{:02d}.png"
    assert main(["render", str(path), "-o", str(seq), "--size", "48x48", "--time", "0:1",
                 "--fps", "4", "-q"]) == 0
    frames = sorted(tmp_path.glob("f_*.png"))
    assert len(frames) == 4  # at 0, 0.25, 0.5 and 0.75 s, framed at the first
    start = renderer.camera(scene.at(0.0), renderer.options(scene, size=(48, 48)))
    for k in (0, 2):
        want = renderer.render(scene, start, size=(48, 48), time=0.25 * k).color[..., :3]
        np.testing.assert_array_equal(np.asarray(Image.open(frames[k]).convert("RGB")), want)
    assert not np.array_equal(np.asarray(Image.open(frames[2])),
                              np.asarray(Image.open(frames[0])))


def test_animation_picks_one_by_name_or_index(tmp_path, capsys):
    path = animated_box(tmp_path)
    b = json.loads(path.read_text())
    b["animations"].append({"name": "still", "samplers": [b["animations"][0]["samplers"][0]],
                            "channels": []})
    b["animations"][1]["channels"] = [{"sampler": 0, "target": {"node": 0, "path": "scale"}}]
    path.write_text(json.dumps(b))
    scene = facet.load(path)
    assert scene.animations == ["move", "still"]
    a = scene.at(1.7, "move").objects[0].transform
    assert np.allclose(a, scene.at(1.7, 0).objects[0].transform)
    assert not np.allclose(a, scene.at(1.7, "still").objects[0].transform)
    out = tmp_path / "x.png"
    assert main(["render", str(path), "-o", str(out), "--animation", "run", "--size",
                 "16x16"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "0: move, 1: still" in err[0]
    assert not out.exists()


def _two_clips(tmp_path):
    """A box with two clips driving its translation: "survey" along +x, then "run" along
    +y (as a Fox has Survey, Walk and Run on one skeleton)."""
    b = GltfBuilder()
    node = b.node(mesh=_box(b))
    clips = []
    for name, axis in (("survey", 0), ("run", 1)):
        values = np.zeros((2, 3))
        values[1, axis] = 2.0
        clips.append({"name": name, "samplers": [_sampler(b, [0, 1], values, "LINEAR")],
                      "channels": [{"sampler": 0, "target": {"node": node,
                                                              "path": "translation"}}]})
    b.doc["animations"] = clips
    return b.write_gltf(tmp_path / "clips.gltf")


def test_the_first_animation_plays_by_default_and_all_only_when_asked(tmp_path, renderer):
    """Every glTF viewer plays a file's first clip unless told otherwise: the default pose
    is "survey"'s (x moves, y stays), in Python and through a render; "all" plays both
    (the later clip wins) with one warning line naming the clips that collide. (Old code:
    every clip played by default and the last won: the box moved up.)"""
    scene = facet.load(_two_clips(tmp_path))
    moved = scene.at(0.5).objects[0].transform[:3, 3]
    np.testing.assert_allclose(moved, [1.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(scene.at(0.5, "run").objects[0].transform[:3, 3], [0, 1, 0],
                               atol=1e-9)
    r = renderer(32, 32)
    camera = facet.Camera.look_at((0, 0, 8), (0, 0, 0), fov_y=40)
    default = r.render(scene, camera, time=0.5, shadows=False).object_ids
    first = r.render(scene, camera, time=0.5, animation=0, shadows=False).object_ids
    np.testing.assert_array_equal(default, first)
    with pytest.warns(facet.FacetWarning) as caught:
        both = scene.at(0.5, "all").objects[0].transform[:3, 3]
    np.testing.assert_allclose(both, [0.0, 1.0, 0.0], atol=1e-9)
    lines = [str(w.message) for w in caught]
    assert len(lines) == 1 and "'survey' and 'run'" in lines[0], lines


# -- bad files ------------------------------------------------------------------------------
def _edit(path, change):
    doc = json.loads(path.read_text())
    change(doc)
    path.write_text(json.dumps(doc))
    return path


BAD = {
    "missing node": (lambda d: d["animations"][0]["channels"][0]["target"].update(node=42),
                     "animations[0].channels[0].target.node"),
    "counts disagree": (lambda d: d["accessors"][d["animations"][0]["samplers"][0]["output"]]
                        .update(count=1), "the counts must agree"),
    "NaN key": (None, "NaN"),
    "joint out of range": (None, "joint 1"),
    "unknown path": (lambda d: d["animations"][0]["channels"][0]["target"].update(
        path="colour"), "expected translation, rotation, scale or weights"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_a_broken_animation_is_one_line_and_nothing_written(tmp_path, capsys, case):
    change, words = BAD[case]
    path = skinned_strip(tmp_path)
    if case == "NaN key":
        doc = json.loads(path.read_text())
        b = GltfBuilder()
        b.doc, b.data = doc, bytearray()
        import base64
        b.data = bytearray(base64.b64decode(doc["buffers"][0]["uri"].split(",")[1]))
        doc["animations"][0]["samplers"][0]["input"] = b.accessor(np.array([0.0, np.nan]))
        path = b.write_gltf(tmp_path / "nan.gltf")
    elif case == "joint out of range":
        path = _edit(path, lambda d: d["skins"][0].update(joints=d["skins"][0]["joints"][:1],
                                                          inverseBindMatrices=None))
    else:
        path = _edit(path, change)
    out = tmp_path / "out.png"
    assert main(["render", str(path), "-o", str(out), "--size", "16x16"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert not out.exists()


def test_the_viewer_clock_plays_pauses_steps_and_loops():
    from facet.viewing.playback import Playback

    now = [100.0]
    clock = Playback(0.5, 2.5, clock=lambda: now[0])
    assert clock.time() == 0.5
    now[0] += 1.0
    assert clock.time() == pytest.approx(1.5)
    now[0] += 1.5  # 3.0 -> wraps into [0.5, 2.5)
    assert clock.time() == pytest.approx(1.0)
    assert clock.toggle() is False
    now[0] += 10
    assert clock.time() == pytest.approx(1.0)
    assert clock.step(1 / 30) == pytest.approx(1.0 + 1 / 30)
    assert clock.toggle() is True
    now[0] += 0.25
    assert clock.time() == pytest.approx(1.25 + 1 / 30)


def test_datasets_sample_a_time_per_view(tmp_path):
    """A dataset job's views each stand at their own time (views.times spread over
    [start, end)), recorded per frame in transforms.json."""
    from batch_data import write_manifest

    path = skinned_strip(tmp_path)
    manifest = write_manifest(tmp_path, [{"model": str(path), "name": "strip",
                                          "views": {"plan": "turntable", "count": 4,
                                                    "times": [0, 1]},
                                          "size": [32, 32], "outputs": ["color"]}])
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"]) == 0
    frames = json.loads((tmp_path / "out" / "strip" / "transforms.json").read_text())[
        "frames"]
    assert [f["time"] for f in frames] == [0.0, 0.25, 0.5, 0.75]


def test_motion_blur_follows_the_animation_over_the_shutter(tmp_path, renderer):
    """shutter = S: supersamples stand at times spread over [T, T + S] (the animation, not
    a straight line between two matrices). The bending strip's blurred picture is the mean
    of the stills at those times: pixels the strip sweeps are partly covered, and the
    blurred picture is close to the mean of stills at eight times over the shutter."""
    scene = facet.load(skinned_strip(tmp_path))
    r = renderer(48, 48)
    cam = facet.Camera.look_at((0.3, 1.2, 4), (0.3, 1.2, 0), fov_y=50)
    opts = dict(aa="ssaa:jittered:16", background=(0, 0, 0, 1))
    blurred = r.render(scene, cam, time=0.2, shutter=0.6, **opts).color[..., 1] / 255.0
    still = r.render(scene, cam, time=0.2, **opts).color[..., 1] / 255.0
    stills = np.mean([r.render(scene, cam, time=0.2 + 0.6 * (k + 0.5) / 8, **opts)
                      .color[..., 1] / 255.0 for k in range(8)], axis=0)
    swept = (stills > 0.05) & (stills < 0.6)
    assert swept.sum() > 30
    assert np.abs(blurred - still)[swept].mean() > 0.1  # it moved while the shutter was open
    assert np.abs(blurred - stills)[swept].mean() < 0.08  # as the animation moved it


@pytest.mark.parametrize("shadows", [False, True])
def test_the_rasterizer_skins_in_its_vertex_shader(tmp_path, renderer, shadows):
    """A skinned pose is drawn from its rest mesh and the joint matrices (glsl/lib/skin.glsl):
    no vertex is skinned on the CPU for it (shadow maps fit its loose box), and the picture
    equals that of the numpy-skinned vertices placed by hand (colour, ids; depth within
    float32 rounding)."""
    from facet.scene.skinned import SkinnedPose

    scene = facet.load(skinned_strip(tmp_path, eight=True)).at(0.7)
    pose = scene.objects[0].mesh
    assert isinstance(pose, SkinnedPose)
    r = renderer(64, 64)
    cam = facet.Camera.look_at((0.5, 1, 5), (0.5, 1, 0), fov_y=40)
    floor = facet.Mesh([[-3, -0.5, -2], [3, -0.5, -2], [3, -0.5, 2], [-3, -0.5, 2]],
                       [[0, 2, 1], [0, 3, 2]])
    scene.add(floor)
    scene.add_light(facet.PointLight((1, 4, 3)))
    opts = dict(outputs=("color", "depth", "ids"), shadows=shadows, lights="scene")
    gpu = r.render(scene, cam, **opts)
    assert pose._posed is None  # nothing skinned on the CPU
    want, faces = ref_skin(0.7)
    plain = facet.Scene()
    plain.add(facet.Mesh(want, faces, pose.normals), scene.objects[0].material)
    plain.add(floor)
    plain.add_light(facet.PointLight((1, 4, 3)))
    cpu = r.render(plain, cam, **opts)
    np.testing.assert_array_equal(gpu.object_ids, cpu.object_ids)
    np.testing.assert_allclose(gpu.depth, cpu.depth, atol=1e-5)
    assert np.abs(gpu.color.astype(int) - cpu.color).max() <= 1


def test_a_skinned_poses_loose_box_holds_its_vertices(tmp_path):
    pose = facet.load(skinned_strip(tmp_path)).at(0.8).objects[0].mesh
    loose, exact = pose.loose_bounds, pose.bounds
    assert np.all(loose[0] <= exact[0] + 1e-6) and np.all(loose[1] >= exact[1] - 1e-6)


@pytest.mark.parametrize("model", ["AnimatedMorphCube", "RiggedFigure"])
def test_the_rasterizer_morphs_and_skins_the_khronos_models_as_numpy_does(renderer, model):
    """A morphed (or skinned) pose drawn by the vertex shader equals the numpy-deformed
    vertices placed by hand: ids equal, depth within float32 rounding, colour within 2."""
    from conftest import SHARED_GLTF, shared_model

    path = shared_model(f"{model}/{model}.glb", SHARED_GLTF)
    r = renderer(64, 64)
    framed = facet.load(path).at(0.6)  # (framing reads the vertices: another load's)
    cam = r.camera(framed, r.options(framed))
    scene = facet.load(path).at(0.6)
    gpu = r.render(scene, cam, outputs=("color", "depth", "ids"))
    pose = scene.objects[0].mesh
    assert pose._posed is None
    plain = facet.Scene()
    for o in scene.objects:
        plain.add(facet.Mesh(o.mesh.positions, o.mesh.faces, o.mesh.normals, o.mesh.uvs),
                  o.material, o.transform)
    cpu = r.render(plain, cam, outputs=("color", "depth", "ids"))
    assert (gpu.object_ids != cpu.object_ids).sum() <= 2
    both = (gpu.object_ids >= 0) & (cpu.object_ids >= 0)
    np.testing.assert_allclose(gpu.depth[both], cpu.depth[both], rtol=1e-5)
    assert np.abs(gpu.color.astype(int) - cpu.color)[both].max() <= 2
