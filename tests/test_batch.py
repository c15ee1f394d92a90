"""Datasets (facet.batch): manifests and their errors, view plans, the files and their
transforms.json (a known point re-projects to where the renderer drew it, from the file
alone), resuming, a bad model among good ones, identical files whatever the worker count,
and a run stopped from outside."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

from facet.batch import render_dataset
from facet.batch.manifest import load_manifest
from facet.batch.views import ViewPlan
from facet.cli import main
from facet.errors import InputError

ROOT = Path(__file__).resolve().parents[1]


def _models(folder: Path, n: int) -> list[Path]:
    """n small closed meshes of different shapes and sizes (generated)."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for i in range(n):
        mesh = [trimesh.creation.icosphere(subdivisions=2, radius=0.5 + 0.05 * i),
                trimesh.creation.box(extents=(1, 0.5 + 0.1 * i, 0.8)),
                trimesh.creation.cylinder(radius=0.3, height=1.0 + 0.1 * i),
                trimesh.creation.capsule(radius=0.3, height=0.5)][i % 4]
        mesh.apply_translation((0.1 * i, 0, 0))
        path = folder / f"m{i:02d}.ply"
        mesh.export(path)
        paths.append(path)
    return paths


def _manifest(folder: Path, jobs: list[dict], defaults: dict | None = None) -> Path:
    lines = [json.dumps({"defaults": defaults})] if defaults else []
    lines += [json.dumps(j) for j in jobs]
    path = folder / "dataset.jsonl"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("plan", ["turntable", "sphere", "band", "random"])
def test_view_plans(plan):
    dirs = ViewPlan(plan, 12, seed=3).directions()
    assert dirs.shape == (12, 3) and np.allclose(np.linalg.norm(dirs, axis=1), 1)
    assert len({tuple(np.round(d, 6)) for d in dirs}) == 12  # 12 different views
    if plan == "turntable":
        assert np.allclose(dirs[:, 1], -np.sin(np.radians(20)))  # one elevation
    if plan == "sphere":  # spread evenly: the mean direction is near zero
        assert np.linalg.norm(dirs.mean(axis=0)) < 0.1
    if plan == "random":
        assert np.array_equal(dirs, ViewPlan(plan, 12, seed=3).directions())
        assert not np.array_equal(dirs, ViewPlan(plan, 12, seed=4).directions())


def test_twenty_models_with_every_plan_and_transforms_that_reproject(tmp_path):
    models = _models(tmp_path / "models", 20)
    plans = [{"plan": "turntable", "count": 3}, {"plan": "sphere", "count": 3},
             {"plan": "band", "count": 3, "elevations": [0, 30]},
             {"plan": "random", "count": 3, "seed": 5}]
    jobs = [{"model": f"models/{m.name}", "views": plans[i % 4]} for i, m in enumerate(models)]
    manifest = _manifest(tmp_path, jobs, {"size": [64, 48],
                                          "outputs": ["color", "depth", "ids", "normals"]})
    counts = render_dataset(manifest, tmp_path / "out")
    assert counts["done"] == 20 and counts["failed"] == 0 and counts["views"] == 60
    index = [json.loads(line) for line in (tmp_path / "out" / "index.jsonl").open()]
    assert {r["job"] for r in index} == {m.stem for m in models}
    # From the files alone: the model's centre projects to where the mask is.
    job = tmp_path / "out" / "m03"
    t = json.loads((job / "transforms.json").read_text())
    assert (t["w"], t["h"]) == (64, 48) and len(t["frames"]) == 3
    centre = trimesh.load(models[3]).bounds.mean(axis=0)
    for frame in t["frames"]:
        c2w = np.array(frame["transform_matrix"])
        p = np.linalg.inv(c2w) @ np.append(centre, 1.0)  # OpenGL camera: looking down -z
        u = t["cx"] + t["fl_x"] * p[0] / -p[2]
        v = t["cy"] - t["fl_y"] * p[1] / -p[2]
        mask = np.asarray(Image.open(job / frame["mask_path"]))[..., 0]
        assert mask[int(v), int(u)] == 255
        depth = np.load(job / frame["depth_file_path"])
        assert depth.shape == (48, 64) and depth[int(v), int(u)] > 0
        assert (job / frame["file_path"]).is_file()
    # Back-projecting depth lands on the surface: m04 is a sphere of radius 0.7 about
    # (0.4, 0, 0), so every depth pixel un-projects to about 0.7 from there.
    sphere = tmp_path / "out" / "m04"
    t = json.loads((sphere / "transforms.json").read_text())
    for frame in t["frames"]:
        depth = np.load(sphere / frame["depth_file_path"])
        j, i = np.nonzero(depth > 0)
        d = depth[j, i]
        x = (i + 0.5 - t["cx"]) / t["fl_x"] * d
        y = -(j + 0.5 - t["cy"]) / t["fl_y"] * d
        cam = np.stack([x, y, -d, np.ones_like(d)])
        world = (np.array(frame["transform_matrix"]) @ cam)[:3].T
        r = np.linalg.norm(world - [0.4, 0.0, 0.0], axis=1)
        assert len(r) > 50 and np.abs(r - 0.7).max() < 0.02


def test_manifest_errors_name_the_line_and_key(tmp_path):
    _models(tmp_path / "models", 1)
    cases = [
        ([{"model": "models/m00.ply", "views": {"plan": "spiral"}}], "dataset.jsonl:1.views"
         ".plan: 'spiral'"),
        ([{"model": "models/m00.ply"}, {"model": "models/none.ply"}],
         "dataset.jsonl:2.model: .*none.ply: no such file"),
        ([{"model": "models/m00.ply", "shadng": "flat"}], "dataset.jsonl:1: unknown key "
         "'shadng' \\(did you mean 'shading'\\?\\)"),
        ([{"model": "models/m00.ply", "views": {"count": 0}}], "1..100000 views"),
        ([{"model": "models/m00.ply", "size": [0, 10]}], "dataset.jsonl:1: size"),
    ]
    for jobs, message in cases:
        with pytest.raises(InputError, match=message):
            load_manifest(_manifest(tmp_path, jobs))
    toml = tmp_path / "d.toml"
    toml.write_text('[defaults]\nsize = [32, 32]\n[[jobs]]\nmodel = "models/m00.ply"\n'
                    'name = "a"\n[[jobs]]\nmodel = "models/m00.ply"\nname = "a"\n')
    assert [j.name for j in load_manifest(toml)] == ["a", "a-2"]  # folders kept apart
    # A .json manifest may be one (pretty-printed) document: {"defaults", "jobs"} or a list.
    doc = tmp_path / "d.json"
    doc.write_text(json.dumps({"defaults": {"size": [40, 30]},
                               "jobs": [{"model": "models/m00.ply", "views": 3}]}, indent=2))
    (job,) = load_manifest(doc)
    assert job.size == (40, 30) and job.views.count == 3
    doc.write_text(json.dumps([{"model": "models/m00.ply"}, {"model": "models/m00.ply"}],
                              indent=2))
    assert len(load_manifest(doc)) == 2
    doc.write_text(json.dumps({"defaults": {}, "jobs": [{"model": "models/m00.ply",
                                                         "sise": 3}]}, indent=2))
    with pytest.raises(InputError, match=r"d.json: jobs\[0\]: unknown key 'sise'"):
        load_manifest(doc)


def test_resume_bad_models_and_identical_files_across_worker_counts(tmp_path, capsys):
    models = _models(tmp_path / "models", 4)
    (tmp_path / "models" / "bad.obj").write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    jobs = [{"model": f"models/{m.name}"} for m in models]
    jobs.insert(2, {"model": "models/bad.obj"})
    manifest = _manifest(tmp_path, jobs, {"size": [48, 48], "views": {"plan": "random",
                                                                       "count": 2}})
    code = main(["batch", str(manifest), "-o", str(tmp_path / "one"), "-q"])
    assert code == 1  # a job failed: exit 1, the others done
    assert "4 done, 1 failed" in capsys.readouterr().err
    index = [json.loads(line) for line in (tmp_path / "one" / "index.jsonl").open()]
    bad = next(r for r in index if r["job"] == "bad")
    assert bad["status"] == "failed" and "NaN or infinite" in bad["error"]
    # A rerun skips what is finished; the index keeps one line per job, the skipped ones
    # with the record of the run that rendered them.
    assert main(["batch", str(manifest), "-o", str(tmp_path / "one"), "-q"]) == 1
    assert "0 done, 1 failed, 4 skipped" in capsys.readouterr().err
    again = [json.loads(line) for line in (tmp_path / "one" / "index.jsonl").open()]
    assert sorted(r["job"] for r in again) == sorted(r["job"] for r in index)
    assert {r["job"]: r["status"] for r in again} == {r["job"]: r["status"] for r in index}
    # Two workers write byte-identical files.
    assert main(["batch", str(manifest), "-o", str(tmp_path / "two"), "--workers", "2",
                 "-q"]) == 1
    capsys.readouterr()
    for m in models:
        for a in sorted((tmp_path / "one" / m.stem).rglob("*.*")):
            b = tmp_path / "two" / a.relative_to(tmp_path / "one")
            assert a.read_bytes() == b.read_bytes(), a


@pytest.mark.slow
def test_a_run_stopped_from_outside_resumes(tmp_path):
    models = _models(tmp_path / "models", 6)
    manifest = _manifest(tmp_path, [{"model": f"models/{m.name}"} for m in models],
                         {"size": [128, 128], "views": {"plan": "sphere", "count": 30}})
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    proc = subprocess.Popen([sys.executable, "-m", "facet", "batch", str(manifest), "-o",
                             str(out), "-q"], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True)
    end = time.time() + 60
    while time.time() < end and len(list(out.glob("*/images/*.png"))) < 10:
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and b"Traceback" not in err
    for png in out.rglob("*.png"):
        assert png.read_bytes().endswith(b"IEND\xaeB`\x82")  # whole under final names
    finished = [d for d in out.iterdir() if (d / "transforms.json").is_file()]
    assert len(finished) < 6
    assert main(["batch", str(manifest), "-o", str(out), "-q"]) == 0  # resumes
    assert all((out / m.stem / "transforms.json").is_file() for m in models)
    assert not [p for p in out.rglob("*") if ".facet-" in p.name]


@pytest.mark.slow
def test_a_local_ray_cluster_writes_the_same_files(tmp_path):
    pytest.importorskip("ray", reason="the ray extra is not installed")
    models = _models(tmp_path / "models", 5)
    manifest = _manifest(tmp_path, [{"model": f"models/{m.name}"} for m in models],
                         {"size": [48, 48], "views": {"plan": "random", "count": 3,
                                                     "seed": 11}})
    local = render_dataset(manifest, tmp_path / "local")
    on_ray = render_dataset(manifest, tmp_path / "ray", ray=True)
    assert local["done"] == on_ray["done"] == 5 and on_ray["failed"] == 0
    files = sorted(p.relative_to(tmp_path / "local")
                   for p in (tmp_path / "local").rglob("*.*") if p.suffix in (".png", ".npy"))
    assert len(files) == 5 * 3 * 3
    for rel in files:
        assert (tmp_path / "local" / rel).read_bytes() == (tmp_path / "ray" / rel).read_bytes()


def test_exr_files_and_a_colmap_model_that_reprojects(tmp_path):
    """float_files = ["npy", "exr"] writes both, bit for bit the same floats; colmap = true
    writes sparse/0 whose cameras and poses project the model's surface points (and a
    known point) to where the renderer drew them, read from the text files alone."""
    openexr = pytest.importorskip("OpenEXR", reason="the exr extra is not installed")
    models = _models(tmp_path / "models", 2)
    manifest = _manifest(tmp_path, [{"model": f"models/{m.name}"} for m in models],
                         {"size": [64, 48], "views": {"plan": "sphere", "count": 4},
                          "outputs": ["color", "depth", "normals", "ids"],
                          "float_files": ["npy", "exr"], "colmap": True})
    assert render_dataset(manifest, tmp_path / "out")["done"] == 2
    job = tmp_path / "out" / "m00"
    for npy in [*job.glob("depth/*.npy"), *job.glob("normals/*.npy")]:
        exr = openexr.File(str(npy.with_suffix(".exr")), separate_channels=True).channels()
        a = np.load(npy)
        b = exr["Y"].pixels if a.ndim == 2 else np.dstack([exr[c].pixels for c in "RGB"])
        assert b.dtype == np.float32 and np.array_equal(a, b), npy
    # COLMAP text model: parse it as COLMAP's readers do.
    sparse = job / "sparse" / "0"

    def rows(name):
        return [line.split() for line in (sparse / name).read_text().splitlines()
                if line and not line.startswith("#")]

    (cam,) = rows("cameras.txt")
    assert cam[:4] == ["1", "PINHOLE", "64", "48"]
    fx, fy, cx, cy = map(float, cam[4:])
    images = rows("images.txt")
    assert len(images) == 4 and [r[9] for r in images] == [f"{i:04d}.png" for i in range(4)]
    points = np.array([[float(x) for x in r[1:7]] for r in rows("points3D.txt")])
    assert len(points) > 500
    r = np.linalg.norm(points[:, :3] - [0.0, 0.0, 0.0], axis=1)
    assert np.abs(r - 0.5).max() < 0.02  # m00: an icosphere of radius 0.5 at the origin
    centre = np.zeros(3)
    for row in images:
        w, x, y, z = map(float, row[1:5])
        R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        t = np.array([float(v) for v in row[5:8]])
        mask = np.asarray(Image.open(job / "masks" / row[9]))[..., 0]
        depth = np.load(job / "depth" / row[9].replace(".png", ".npy"))
        p = R @ centre + t  # OpenCV camera: x right, y down, +z ahead
        u, v = fx * p[0] / p[2] + cx, fy * p[1] / p[2] + cy
        assert mask[int(v), int(u)] == 255
        # The surface points project into the model's silhouette (the rim of the faceted
        # sphere aside), and at least the quarter this view gave land at their own depth.
        cam_points = points[:, :3] @ R.T + t
        uv = cam_points[:, :2] / cam_points[:, 2:] * [fx, fy] + [cx, cy]
        j, i = uv[:, 1].astype(int), uv[:, 0].astype(int)
        seen = np.abs(depth[j, i] - cam_points[:, 2]) < 0.005
        assert seen.sum() > 0.2 * len(points) and (mask[j, i] == 255).mean() > 0.9
    # A bad value is one error naming the key.
    bad = _manifest(tmp_path, [{"model": "models/m00.ply", "float_files": "tiff"}])
    with pytest.raises(InputError, match=r"dataset.jsonl:1.float_files: 'tiff'; give"):
        load_manifest(bad)


def test_exr_without_openexr_is_one_error_before_rendering(tmp_path, monkeypatch):
    import facet.image.writers as writers

    _models(tmp_path / "models", 1)
    manifest = _manifest(tmp_path, [{"model": "models/m00.ply", "float_files": ["exr"]}])
    monkeypatch.setattr(writers, "exr_available", lambda: False)  # as if not installed
    with pytest.raises(InputError, match=r"float_files: EXR files need pip install "
                                         r"'facet\[exr\]'"):
        load_manifest(manifest)


def test_a_gpu_that_does_not_exist_stops_the_run_with_one_error(tmp_path, capsys):
    """--gpus 99: the workers cannot make their renderer; the run stops at once with the
    EGL device's error (not a CPU in its place, not a pool restarting workers for ever)."""
    _models(tmp_path / "models", 2)
    manifest = _manifest(tmp_path, [{"model": "models/m00.ply"}, {"model": "models/m01.ply"}])
    start = time.time()
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "--gpus", "99",
                 "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "on EGL device 99" in err and "Traceback" not in err
    assert time.time() - start < 30
    assert not list((tmp_path / "out").rglob("*.png"))


def _children(pid: int) -> list[int]:
    kids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            kids.append(int(stat.parent.name))
    return kids


@pytest.mark.slow
def test_a_worker_killed_mid_run_does_not_stop_or_hang_the_run(tmp_path):
    """A worker process dies (as one killed for memory by a huge model would): the jobs it
    had are tried again, alone, and the run finishes with every job done."""
    models = _models(tmp_path / "models", 6)
    manifest = _manifest(tmp_path, [{"model": f"models/{m.name}"} for m in models],
                         {"size": [96, 96], "views": {"plan": "sphere", "count": 40}})
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    proc = subprocess.Popen([sys.executable, "-m", "facet", "batch", str(manifest), "-o",
                             str(out), "--workers", "2", "-q"], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    end = time.time() + 60
    while time.time() < end and len(list(out.glob("*/images/*.png"))) < 5:
        time.sleep(0.05)
    workers = [k for k in _children(proc.pid)
               if b"spawn_main" in Path(f"/proc/{k}/cmdline").read_bytes()]
    assert workers, "no worker processes found"
    os.kill(workers[0], signal.SIGKILL)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err.decode()
    index = [json.loads(line) for line in (out / "index.jsonl").open()]
    assert {r["job"] for r in index if r["status"] == "done"} == {m.stem for m in models}
    assert all((out / m.stem / "transforms.json").is_file() for m in models)


@pytest.mark.slow
def test_ray_actors_that_cannot_render_stop_the_run_with_their_error(tmp_path, monkeypatch):
    """An actor whose renderer cannot be made (here: a wrong backend name, as a bad GPU or
    a node without GL would) stops the run with that error, not retries and a vague
    "lost its worker"; more GPU actors than the cluster has GPUs is one error up front."""
    pytest.importorskip("ray", reason="the ray extra is not installed")
    _models(tmp_path / "models", 2)
    manifest = _manifest(tmp_path, [{"model": "models/m00.ply"}, {"model": "models/m01.ply"}])
    with pytest.raises(InputError, match=r"the Ray cluster has \d+ GPU"):
        render_dataset(manifest, tmp_path / "gpu", ray=True, gpus=[0], workers=64)
    monkeypatch.setenv("FACET_GL_BACKEND", "vulkan")  # the actors inherit it
    with pytest.raises(InputError, match="unknown OpenGL backend 'vulkan'"):
        render_dataset(manifest, tmp_path / "out", ray=True)


def test_confinement_reads_what_the_manifest_names_and_nothing_it_does_not(tmp_path):
    """By default a job reads inside the manifest's folder, or, for a model the manifest
    lists elsewhere, inside that model's folder: listed models anywhere render; a scene
    that reaches outside its folder for a mesh fails its job (one line); --confine DIR
    holds every job to DIR."""
    here, there, elsewhere = (tmp_path / n for n in ("here", "there", "elsewhere"))
    _models(there, 1)
    _models(elsewhere, 1)
    here.mkdir()
    (here / "reach.toml").write_text(f'[[objects]]\nmesh = "{elsewhere / "m00.ply"}"\n')
    (there / "reach.toml").write_text('[[objects]]\nmesh = "../elsewhere/m00.ply"\n')
    (there / "inside.toml").write_text('[[objects]]\nmesh = "m00.ply"\n')
    jobs = [{"model": str(there / "m00.ply"), "name": "listed"},
            {"model": "reach.toml", "name": "reach-here"},
            {"model": str(there / "reach.toml"), "name": "reach-there"},
            {"model": str(there / "inside.toml"), "name": "inside-there"}]
    manifest = _manifest(here, jobs, {"size": [32, 32], "views": 1})
    render_dataset(manifest, tmp_path / "out")
    status = {r["job"]: r for r in map(json.loads, (tmp_path / "out" / "index.jsonl").open())}
    assert status["listed"]["status"] == status["inside-there"]["status"] == "done"
    for name in ("reach-here", "reach-there"):
        assert status[name]["status"] == "failed"
        assert "outside the confinement folder" in status[name]["error"]
    render_dataset(manifest, tmp_path / "strict", confine=here)
    status = {r["job"]: r for r in map(json.loads, (tmp_path / "strict" / "index.jsonl").open())}
    assert status["listed"]["status"] == "failed"  # DIR alone, for every job
    assert render_dataset(manifest, tmp_path / "open", confine=None)["done"] == 4


@pytest.mark.slow
def test_a_job_that_kills_its_worker_every_time_fails_alone(tmp_path):
    """A job whose worker dies each time it runs it (as a model too large for memory
    would; here the test kills the worker whenever the job writes a view) is found by
    running the suspects alone, fails with its one line, and the others are done."""
    models = _models(tmp_path / "models", 5)
    manifest = _manifest(tmp_path, [{"model": f"models/{m.name}"} for m in models],
                         {"size": [96, 96], "views": {"plan": "sphere", "count": 30}})
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    proc = subprocess.Popen([sys.executable, "-m", "facet", "batch", str(manifest), "-o",
                             str(out), "--workers", "1", "-q"], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    killed, last = 0, 0.0
    end = time.time() + 120
    while proc.poll() is None and time.time() < end:
        view = out / "m02" / "images" / "0000.png"
        stamp = view.stat().st_mtime if view.exists() else 0.0
        if stamp > last:  # m02 is being rendered (again): its worker dies
            for k in _children(proc.pid):
                if b"spawn_main" in Path(f"/proc/{k}/cmdline").read_bytes():
                    os.kill(k, signal.SIGKILL)
            killed, last = killed + 1, stamp
        time.sleep(0.01)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1 and b"Traceback" not in err, err.decode()
    assert killed >= 2  # in company first, then alone
    index = {r["job"]: r for r in map(json.loads, (out / "index.jsonl").open())}
    assert index["m02"]["status"] == "failed" and "worker process died" in index["m02"]["error"]
    assert all(index[m.stem]["status"] == "done" for m in models if m.stem != "m02")


def test_cameras_plan_reproduces_the_views_of_a_transforms_json(tmp_path):
    """plan = "cameras" renders from a transforms.json's poses (here one facet wrote): as
    many views as it has frames, the same pictures; a file that is no transforms.json is
    an error naming the line and key before anything renders."""
    _models(tmp_path / "models", 3)
    first = _manifest(tmp_path, [{"model": "models/m02.ply", "views": {
        "plan": "random", "count": 5, "seed": 4}}], {"size": [64, 48],
                                                   "outputs": ["color", "depth", "ids"]})
    render_dataset(first, tmp_path / "a")
    poses = tmp_path / "a" / "m02" / "transforms.json"
    again = tmp_path / "again.jsonl"
    again.write_text(json.dumps({"model": "models/m02.ply", "size": [64, 48],
                                 "outputs": ["color", "depth", "ids"],
                                 "views": {"plan": "cameras", "file": str(poses)}}) + "\n")
    (job,) = load_manifest(again)
    assert job.views.count == 5
    assert render_dataset(again, tmp_path / "b")["views"] == 5
    for i in range(5):
        a = np.asarray(Image.open(tmp_path / "a" / "m02" / "images" / f"{i:04d}.png"))
        b = np.asarray(Image.open(tmp_path / "b" / "m02" / "images" / f"{i:04d}.png"))
        assert np.abs(a.astype(int) - b).max() <= 2  # near / far refitted: same picture
        for channel in ("depth", "ids"):
            x = np.load(tmp_path / "a" / "m02" / channel / f"{i:04d}.npy")
            y = np.load(tmp_path / "b" / "m02" / channel / f"{i:04d}.npy")
            if channel == "ids":
                assert np.array_equal(x, y)
            else:
                assert np.allclose(x, y, atol=1e-4)
    (tmp_path / "bad.json").write_text('{"frames": 3}')
    again.write_text(json.dumps({"model": "models/m02.ply", "views": {
        "plan": "cameras", "file": "bad.json"}}) + "\n")
    with pytest.raises(InputError, match=r"again.jsonl:1.views.file: .*bad.json: cannot read"):
        load_manifest(again)


def test_zero_workers_is_an_error(tmp_path, capsys):
    _models(tmp_path / "models", 1)
    manifest = _manifest(tmp_path, [{"model": "models/m00.ply"}])
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "--workers", "0"]) == 2
    assert "--workers must be at least 1, got 0" in capsys.readouterr().err
