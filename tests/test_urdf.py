"""URDF robots (facet.formats.urdf): links placed exactly by the joint configuration
(facet's depth against a ray caster over the shapes at the poses yourdfpy's own forward
kinematics gives, through one explicit camera, in the rasterizer and the Whitted tracer),
limits and mimic joints, package:// through the search path, the guard, collision
geometry, and the command line. Robots are written here."""

from __future__ import annotations

import numpy as np
import pytest

import facet
from facet.errors import InputError, MeshError
from facet.geometry.camera import Camera

yourdfpy = pytest.importorskip("yourdfpy", reason="URDF needs yourdfpy (the urdf extra)")

from test_usd import _box, _cylinder_x, _hit_object, _rays, _sphere  # noqa: E402

ROBOT = """<?xml version="1.0"?>
<robot name="arm">
  <material name="blue"><color rgba="0.1 0.2 0.8 1"/></material>
  <link name="base"><visual><geometry><box size="0.4 0.3 0.1"/></geometry>
    <material name="blue"/></visual>
    <collision><geometry><sphere radius="0.25"/></geometry></collision></link>
  <link name="upper"><visual><origin xyz="0 0 0.25" rpy="0 1.5707963267948966 0"/>
    <geometry><cylinder radius="0.05" length="0.5"/></geometry>
    <material name="red"><color rgba="0.8 0.1 0.1 1"/></material></visual></link>
  <link name="fore"><visual><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.06 0.06"/>
    </geometry></visual></link>
  <link name="hand"><visual><geometry>{hand}</geometry></visual></link>
  <link name="finger_a"><visual><geometry><sphere radius="0.03"/></geometry></visual></link>
  <link name="finger_b"><visual><geometry><sphere radius="0.03"/></geometry></visual></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="wrist" type="fixed"><parent link="fore"/><child link="hand"/>
    <origin xyz="0.4 0 0" rpy="0.3 0 0"/></joint>
  <joint name="slide" type="prismatic"><parent link="hand"/><child link="finger_a"/>
    <origin xyz="0 0.05 0"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.05" effort="1" velocity="1"/></joint>
  <joint name="slide_mimic" type="prismatic"><parent link="hand"/><child link="finger_b"/>
    <origin xyz="0 -0.05 0"/><axis xyz="0 -1 0"/>
    <limit lower="0" upper="0.05" effort="1" velocity="1"/>
    <mimic joint="slide" multiplier="1" offset="0"/></joint>
</robot>
"""
SPHERE_HAND = '<sphere radius="0.08"/>'


def _robot(folder, hand=SPHERE_HAND):
    path = folder / "arm.urdf"
    path.write_text(ROBOT.format(hand=hand))
    return path


CONFIG = {"shoulder": 0.6, "elbow": -0.8, "slide": 0.04}
CAMERA = Camera.look_at((0.9, -1.1, 0.9), (0.2, 0.0, 0.4), up=(0, 0, 1), fov_y=45, near=0.1,
                        far=10)


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_links_land_where_yourdfpys_forward_kinematics_puts_them(tmp_path, engine):
    path = _robot(tmp_path)
    robot = yourdfpy.URDF.load(str(path), load_meshes=False)
    robot.update_cfg(CONFIG)

    def pose(link, xyz=(0, 0, 0), rpy=None):
        m = robot.get_transform(frame_to=link, frame_from="base")
        local = np.eye(4)
        local[:3, 3] = xyz
        if rpy is not None:  # a turn about y by rpy[1] (the upper arm's visual)
            c, s = np.cos(rpy), np.sin(rpy)
            local[:3, :3] = [[c, 0, s], [0, 1, 0], [-s, 0, c]]
        return m @ local

    def scaled_box(sx, sy, sz):  # a box of sides (sx, sy, sz) as a unit box, scaled
        return np.diag([sx, sy, sz, 1.0])

    o, d = _rays(CAMERA, 64, 48)
    ys = np.array([[0, 1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    ts = [_hit_object(o, d, pose("base") @ scaled_box(0.4, 0.3, 0.1), _box(0.5)),
          # the cylinder (along z in URDF) turned onto x by the visual's rpy: along x here
          _hit_object(o, d, pose("upper", (0, 0, 0.25), np.pi / 2) @ ys @ ys,
                      lambda oo, dd: _cylinder_x(0.05, 0.5)(oo[..., [2, 1, 0]],
                                                            dd[..., [2, 1, 0]])),
          _hit_object(o, d, pose("fore", (0.2, 0, 0)) @ scaled_box(0.4, 0.06, 0.06),
                      _box(0.5)),
          _hit_object(o, d, pose("hand"), _sphere(0.08)),
          _hit_object(o, d, pose("finger_a"), _sphere(0.03)),
          _hit_object(o, d, pose("finger_b"), _sphere(0.03))]
    t = np.min(ts, axis=0)
    which = np.argmin(ts, axis=0)
    want = np.where(np.isfinite(t), t * (d @ -CAMERA.view[2, :3]), 0.0)
    scene = facet.load(path, joints=CONFIG)
    with facet.Renderer(64, 48) as r:
        got = r.render(scene, CAMERA, engine=engine, outputs=("depth",), aa="none").depth
    inside = (want > 0) & (got > 0)
    for axis in (0, 1):
        for s in (1, -1):
            inside &= np.roll(want > 0, s, axis) & (np.roll(which, s, axis) == which)
    assert ((want > 0) != (got > 0)).mean() < 0.03
    err = np.abs(got - want)[inside] / want[inside]
    tol = 2e-3 if engine == "raster" else 1e-4
    assert inside.sum() > 150 and np.quantile(err, 0.99) < tol, err.max()
    for k in (0, 1, 2, 3):
        assert ((which == k) & inside).sum() > 3, k


def test_limits_mimic_joints_and_unknown_names(tmp_path):
    path = _robot(tmp_path)
    with pytest.raises(InputError, match=r"joint 'elbow' = 2.5 rad is outside its limits "
                                         r"\[-2, 2\] rad"):
        facet.load(path, joints={"elbow": 2.5})
    with pytest.raises(InputError, match=r"joint 'slide' = 0.1 m is outside its limits"):
        facet.load(path, joints={"slide": 0.1})
    with pytest.raises(InputError, match="no joint named 'knee'; its joints are shoulder"):
        facet.load(path, joints={"knee": 0.1})
    with pytest.raises(InputError, match="mimics 'slide'; set 'slide' instead"):
        facet.load(path, joints={"slide_mimic": 0.01})
    scene = facet.load(path, joints={"slide": 0.05})
    centres = {o.name.split("/")[0]: o.transform[:3, 3] for o in scene.objects}
    gap = np.linalg.norm(centres["finger_a"] - centres["finger_b"])
    assert gap == pytest.approx(2 * (0.05 + 0.05), abs=1e-9)  # both fingers moved
    base = next(o for o in scene.objects if o.name.startswith("base"))
    assert np.allclose(base.material.base_color[:3], [0.1, 0.2, 0.8])  # the named material


def test_package_paths_the_guard_and_collision_geometry(tmp_path, monkeypatch):
    import trimesh

    pkg = tmp_path / "ws" / "arm_pkg" / "meshes"
    pkg.mkdir(parents=True)
    trimesh.creation.icosphere(radius=0.08).export(pkg / "ball.stl")
    robot_dir = tmp_path / "robot"
    robot_dir.mkdir()
    path = _robot(robot_dir, '<mesh filename="package://arm_pkg/meshes/ball.stl"/>')
    with pytest.raises(MeshError, match="package://arm_pkg/meshes/ball.stl is in no folder"):
        facet.load(path)
    scene = facet.load(path, package_path=(tmp_path / "ws",))
    assert any(o.name.startswith("hand/") for o in scene.objects)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws"))
    assert len(facet.load(path).objects) == len(scene.objects)
    with pytest.raises(MeshError, match="ball.stl"):  # a mesh outside the confinement
        facet.load(path, confine=robot_dir)
    collision = facet.load(path, collision=True)
    assert [o.name for o in collision.objects] == ["base/0"]  # the one collision element
    (tmp_path / "evil.urdf").write_text(
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
        '<robot name="r"><link name="&x;"/></robot>')
    with pytest.raises(MeshError, match="declares a DTD or entities"):
        facet.load(tmp_path / "evil.urdf")


def test_the_command_line_poses_a_robot(tmp_path, capsys):
    from facet.cli import main

    path = _robot(tmp_path)
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "slide_mimic (prismatic [0, 0.05] mimics slide)" in out
    pictures = []
    for joints in ("shoulder=0,elbow=0", "shoulder=1.2,elbow=-1.5"):
        png = tmp_path / f"{joints}.png"
        assert main(["render", str(path), "--joints", joints, "--size", "64x48",
                     "-q", "-o", str(png)]) == 0
        from PIL import Image

        pictures.append(np.asarray(Image.open(png)).astype(int))
    assert np.abs(pictures[0] - pictures[1]).mean() > 1  # the arm moved
    assert main(["render", str(path), "--joints", "elbow=9", "-o",
                 str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "outside its limits" in err and "Traceback" not in err
    assert not (tmp_path / "x.png").exists()


def test_a_dataset_of_robot_poses_is_one_manifest(tmp_path):
    """Each job a configuration of the same robot: the pictures follow the joints (the
    view plan, each framed on its pose); a job whose joint is out of range fails alone,
    its reason in the index."""
    import json

    from PIL import Image

    from facet.cli import main

    from batch_data import write_manifest

    path = _robot(tmp_path)
    jobs = [{"model": str(path), "name": f"pose{k}", "joints": joints,
             "views": {"plan": "turntable", "count": 1}, "size": [48, 48],
             "outputs": ["color"]}
            for k, joints in enumerate([{"shoulder": 0.0}, {"shoulder": 1.2, "elbow": -1.5}])]
    manifest = write_manifest(tmp_path, jobs)
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"]) == 0
    frames = [json.loads((tmp_path / "out" / f"pose{k}" / "transforms.json").read_text())
              ["frames"][0] for k in range(2)]
    images = [np.asarray(Image.open(tmp_path / "out" / f"pose{k}" / frames[k]["file_path"]))
              .astype(int) for k in range(2)]
    assert np.abs(images[0] - images[1]).mean() > 1
    bad = write_manifest(tmp_path, [dict(jobs[0], joints={"elbow": 5.0})])
    assert main(["batch", str(bad), "-o", str(tmp_path / "bad"), "-q"]) == 1
    record = json.loads((tmp_path / "bad" / "index.jsonl").read_text().splitlines()[0])
    assert record["status"] == "failed" and "outside its limits" in record["error"]


def test_collada_meshes_load_as_a_robots_do(tmp_path):
    """A link's COLLADA (.dae) mesh through trimesh's reader (pycollada, in the urdf
    extra), scaled by its element; a .dae with a DTD is refused (its entities could name
    any file)."""
    import trimesh

    box = trimesh.creation.box(extents=(0.2, 0.1, 0.05))
    (tmp_path / "hand.dae").write_bytes(trimesh.exchange.dae.export_collada(box))
    path = _robot(tmp_path, '<mesh filename="hand.dae" scale="2 2 2"/>')
    scene = facet.load(path)
    hand = next(o for o in scene.objects if o.name.startswith("hand/"))
    np.testing.assert_allclose(hand.mesh.bounds[1] - hand.mesh.bounds[0], [0.2, 0.1, 0.05],
                               atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(hand.transform[:3, :3], axis=0), 2.0)
    (tmp_path / "evil.dae").write_text('<?xml version="1.0"?><!DOCTYPE c [<!ENTITY x '
                                       'SYSTEM "file:///etc/passwd">]><COLLADA>&x;</COLLADA>')
    with pytest.raises(MeshError, match="declares a DTD or entities"):
        facet.load(tmp_path / "evil.dae")


def test_a_loaded_robot_poses_again_as_if_loaded_in_that_configuration(tmp_path):
    """``Scene.posed`` moves every link as ``facet.load(joints=...)`` and yourdfpy's own
    forward kinematics place them (joints not named keep their values); the pictures
    agree; ``Scene.joints`` gives the ranges; a bad name or value is one error."""
    path = _robot(tmp_path)
    scene = facet.load(path)
    assert scene.joints == {"shoulder": (-1.5, 1.5), "elbow": (-2.0, 2.0),
                            "slide": (0.0, 0.05)}
    posed = scene.posed({"shoulder": 0.6}).posed({"elbow": -0.8, "slide": 0.04})
    direct = facet.load(path, joints=CONFIG)
    for a, b in zip(posed.objects, direct.objects, strict=True):
        np.testing.assert_allclose(a.transform, b.transform, atol=1e-12)
    robot = yourdfpy.URDF.load(str(path), load_meshes=False)
    robot.update_cfg(CONFIG)
    finger = next(o for o in posed.objects if o.name.startswith("finger_b"))
    np.testing.assert_allclose(finger.transform, robot.get_transform("finger_b", "base"),
                               atol=1e-12)
    with facet.Renderer(48, 36) as r:
        a = r.render(posed, CAMERA, outputs=("depth",)).depth
        b = r.render(direct, CAMERA, outputs=("depth",)).depth
        c = r.render(scene, CAMERA, outputs=("depth",)).depth
    np.testing.assert_array_equal(a, b)
    assert (a != c).mean() > 0.02  # (the rest pose differs)
    with pytest.raises(InputError, match="outside its limits"):
        scene.posed({"elbow": 3.0})
    with pytest.raises(InputError, match="no joint named 'knee'"):
        scene.posed({"knee": 0.1})
    plain = facet.Scene()
    plain.add(facet.shapes.Sphere(1.0))
    with pytest.raises(InputError, match="no robot to pose"):
        plain.posed({"elbow": 0.1})


def test_one_job_poses_a_robot_per_view(tmp_path):
    """views.joints: one configuration per view, recorded in transforms.json; the views
    differ by the pose; random_joints samples every joint within its limits (seeded); a
    list that does not match the count is refused before rendering."""
    import json

    from PIL import Image

    from facet.cli import main

    from batch_data import write_manifest

    path = _robot(tmp_path)
    configs = [{"shoulder": 0.0}, {"shoulder": 1.2, "elbow": -1.5}, {"slide": 0.05}]
    job = {"model": str(path), "name": "arm", "size": [40, 40], "outputs": ["color"],
           "views": {"plan": "turntable", "elevation": 30, "joints": configs}}
    manifest = write_manifest(tmp_path, [job, dict(job, name="rnd", views={
        "plan": "sphere", "count": 4, "random_joints": True})])
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"]) == 0
    frames = json.loads((tmp_path / "out" / "arm" / "transforms.json").read_text())["frames"]
    assert [f["joints"] for f in frames] == configs
    images = [np.asarray(Image.open(tmp_path / "out" / "arm" / f["file_path"])).astype(int)
              for f in frames]
    assert all(np.abs(images[i] - images[j]).mean() > 0.5 for i, j in ((0, 1), (0, 2), (1, 2)))
    rnd = json.loads((tmp_path / "out" / "rnd" / "transforms.json").read_text())["frames"]
    ranges = facet.load(path).joints
    assert len(rnd) == 4 and all(set(f["joints"]) == set(ranges) for f in rnd)
    assert all(ranges[k][0] <= v <= ranges[k][1] for f in rnd for k, v in f["joints"].items())
    assert len({json.dumps(f["joints"]) for f in rnd}) == 4
    bad = write_manifest(tmp_path, [dict(job, views={"count": 2, "joints": configs})])
    assert main(["batch", str(bad), "-o", str(tmp_path / "bad"), "-q"]) == 2
    assert not (tmp_path / "bad").exists()


def test_scene_add_places_a_posed_robot_that_poses_again_there(tmp_path):
    """``Scene.add`` of a loaded robot in a configuration: its links where the robot puts
    them, moved by the transform; the world poses it again (``posed``) there."""
    path = _robot(tmp_path)
    world = facet.Scene()
    world.add(facet.shapes.Box((2.0, 2.0, 0.02)))
    move = np.eye(4)
    move[:3, 3] = (0.5, -0.25, 0.01)
    ids = world.add(facet.load(path, joints=CONFIG), transform=move)
    direct = facet.load(path, joints=CONFIG)
    assert ids == list(range(1, 1 + len(direct.objects)))
    for oid, o in zip(ids, direct.objects, strict=True):
        np.testing.assert_allclose(world.objects[oid].transform, move @ o.transform,
                                   atol=1e-12)
    again = world.posed({"shoulder": -0.4})
    other = facet.load(path, joints={**CONFIG, "shoulder": -0.4})
    for oid, o in zip(ids, other.objects, strict=True):
        np.testing.assert_allclose(again.objects[oid].transform, move @ o.transform,
                                   atol=1e-12)
    np.testing.assert_array_equal(again.objects[0].transform, world.objects[0].transform)
    with pytest.raises(InputError, match="keep their materials"):
        world.add(direct, material=facet.Material())


def test_continuous_floating_and_planar_joints(tmp_path):
    """A continuous joint turns without limits (as yourdfpy turns it); floating and planar
    joints stand at their origin, said in one line; none of them takes a value unless it
    moves."""
    path = tmp_path / "joints.urdf"
    path.write_text("""<?xml version="1.0"?>
<robot name="j">
  <link name="base"><visual><geometry><box size="0.2 0.2 0.2"/></geometry></visual></link>
  <link name="wheel"><visual><origin xyz="0.3 0 0"/><geometry><sphere radius="0.05"/>
    </geometry></visual></link>
  <link name="free"><visual><geometry><sphere radius="0.04"/></geometry></visual></link>
  <link name="slab"><visual><geometry><box size="0.1 0.1 0.01"/></geometry></visual></link>
  <joint name="spin" type="continuous"><parent link="base"/><child link="wheel"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 0 1"/></joint>
  <joint name="drift" type="floating"><parent link="base"/><child link="free"/>
    <origin xyz="0 0.5 0"/></joint>
  <joint name="glide" type="planar"><parent link="base"/><child link="slab"/>
    <origin xyz="0 -0.5 0"/><axis xyz="0 0 1"/></joint>
</robot>""")
    with pytest.warns(facet.errors.FacetWarning, match="drift, glide .* stand at their origin"):
        scene = facet.load(path, joints={"spin": 7.5})
    robot = yourdfpy.URDF.load(str(path), load_meshes=False)
    robot.update_cfg({"spin": 7.5})
    at = {o.name.split("/")[0]: o.transform for o in scene.objects}
    want = robot.get_transform("wheel", "base") @ np.array(
        [[1, 0, 0, 0.3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    np.testing.assert_allclose(at["wheel"], want, atol=1e-12)
    np.testing.assert_allclose(at["free"][:3, 3], [0, 0.5, 0], atol=1e-12)
    assert scene.joints == {"spin": (-np.pi, np.pi)}
    with pytest.raises(InputError, match="'glide' is planar; it takes no value"):
        scene.posed({"glide": 0.1})
