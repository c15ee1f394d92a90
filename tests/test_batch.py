"""Datasets (facet.batch): manifests and their errors, view plans, the files and their
transforms.json (a known point re-projects to where the renderer drew it, from the file
alone), EXR and COLMAP outputs, the cameras plan, and what a job may read (confinement).
How runs behave (resume, bad models, dying workers, Ray) is in test_batch_runs.py."""

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

import facet
from facet.batch import render_dataset
from facet.batch.manifest import load_manifest
from facet.batch.views import ViewPlan
from facet.errors import InputError

from batch_data import make_models, write_manifest

ROOT = Path(__file__).resolve().parents[1]


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
    models = make_models(tmp_path / "models", 20)
    plans = [{"plan": "turntable", "count": 3}, {"plan": "sphere", "count": 3},
             {"plan": "band", "count": 3, "elevations": [0, 30]},
             {"plan": "random", "count": 3, "seed": 5}]
    jobs = [{"model": f"models/{m.name}", "views": plans[i % 4]} for i, m in enumerate(models)]
    manifest = write_manifest(tmp_path, jobs, {"size": [64, 48],
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
    make_models(tmp_path / "models", 1)
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
            load_manifest(write_manifest(tmp_path, jobs))
    toml = tmp_path / "d.toml"
    toml.write_text('[defaults]\nsize = [32, 32]\n[[jobs]]\nmodel = "models/m00.ply"\n'
                    'name = "a"\n[[jobs]]\nmodel = "models/m00.ply"\nname = "a"\n')
    assert [j.name for j in load_manifest(toml)] == ["a", "a-2"]  # folders kept apart
    # A .json manifest may be one (pretty-printed) document: {"defaults", "jobs"} or a list.
    doc = tmp_path / "d.json"
    doc.write_text(json.dumps({"defaults": {"size": [40, 30]},
                               "jobs": [{"model": "models/m00.ply", "views": 3}]}, indent=2))
    (job,) = load_manifest(doc)
    assert job.options["size"] == (40, 30) and job.views.count == 3
    doc.write_text(json.dumps([{"model": "models/m00.ply"}, {"model": "models/m00.ply"}],
                              indent=2))
    assert len(load_manifest(doc)) == 2
    doc.write_text(json.dumps({"defaults": {}, "jobs": [{"model": "models/m00.ply",
                                                         "sise": 3}]}, indent=2))
    with pytest.raises(InputError, match=r"d.json: jobs\[0\]: unknown key 'sise'"):
        load_manifest(doc)


def test_exr_files_and_a_colmap_model_that_reprojects(tmp_path):
    """float_files = ["npy", "exr"] writes both, bit for bit the same floats; colmap = true
    writes sparse/0 whose cameras and poses project the model's surface points (and a
    known point) to where the renderer drew them, read from the text files alone."""
    openexr = pytest.importorskip("OpenEXR", reason="the exr extra is not installed")
    models = make_models(tmp_path / "models", 2)
    manifest = write_manifest(tmp_path, [{"model": f"models/{m.name}"} for m in models],
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
    bad = write_manifest(tmp_path, [{"model": "models/m00.ply", "float_files": "tiff"}])
    with pytest.raises(InputError, match=r"dataset.jsonl:1.float_files: 'tiff'; give"):
        load_manifest(bad)


def test_exr_without_openexr_is_one_error_before_rendering(tmp_path, monkeypatch):
    import facet.image.writers as writers

    make_models(tmp_path / "models", 1)
    manifest = write_manifest(tmp_path, [{"model": "models/m00.ply", "float_files": ["exr"]}])
    monkeypatch.setattr(writers, "exr_available", lambda: False)  # as if not installed
    with pytest.raises(InputError, match=r"float_files: EXR files need pip install "
                                         r"'facet-render\[exr\]'"):
        load_manifest(manifest)


def test_confinement_reads_what_the_manifest_names_and_nothing_it_does_not(tmp_path):
    """By default a job reads inside the manifest's folder, or, for a model the manifest
    lists elsewhere, inside that model's folder: listed models anywhere render; a scene
    that reaches outside its folder for a mesh fails its job (one line); --confine DIR
    holds every job to DIR."""
    here, there, elsewhere = (tmp_path / n for n in ("here", "there", "elsewhere"))
    make_models(there, 1)
    make_models(elsewhere, 1)
    here.mkdir()
    (here / "reach.toml").write_text(f'[[objects]]\nmesh = "{elsewhere / "m00.ply"}"\n')
    (there / "reach.toml").write_text('[[objects]]\nmesh = "../elsewhere/m00.ply"\n')
    (there / "inside.toml").write_text('[[objects]]\nmesh = "m00.ply"\n')
    jobs = [{"model": str(there / "m00.ply"), "name": "listed"},
            {"model": "reach.toml", "name": "reach-here"},
            {"model": str(there / "reach.toml"), "name": "reach-there"},
            {"model": str(there / "inside.toml"), "name": "inside-there"}]
    manifest = write_manifest(here, jobs, {"size": [32, 32], "views": 1})
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


def test_cameras_plan_reproduces_the_views_of_a_transforms_json(tmp_path):
    """plan = "cameras" renders from a transforms.json's poses (here one facet wrote): as
    many views as it has frames, the same pictures; a file that is no transforms.json is
    an error naming the line and key before anything renders."""
    make_models(tmp_path / "models", 3)
    first = write_manifest(tmp_path, [{"model": "models/m02.ply", "views": {
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
    with pytest.raises(InputError, match=r"again.jsonl:1.views.file: .*bad.json: a "
                                         r"transforms.json has a list of \"frames\""):
        load_manifest(again)


def test_command_line_defaults_replace_the_manifests_and_jobs_win(tmp_path):
    """Precedence: manifest [defaults] < command-line defaults (--size, --outputs ...) < a
    job's own values."""
    make_models(tmp_path / "models", 2)
    manifest = write_manifest(tmp_path, [{"model": "models/m00.ply"},
                                         {"model": "models/m01.ply", "size": [20, 10]}],
                              {"size": [64, 48], "outputs": ["color", "depth"]})
    plain, sized = load_manifest(manifest)
    assert plain.options["size"] == (64, 48) and plain.options["outputs"] == ("color", "depth")
    plain, sized = load_manifest(manifest, {"size": "32x32", "outputs": "color"})
    assert plain.options["size"] == (32, 32) and plain.options["outputs"] == ("color",)
    assert sized.options["size"] == (20, 10) and sized.options["outputs"] == ("color",)


def test_the_summary_names_the_index_once_slashed(tmp_path, capsys):
    """`facet batch ... -o dataset/` says where the index is as a path (it printed
    dataset//index.jsonl)."""
    from facet.cli import main

    make_models(tmp_path / "models", 1)
    manifest = write_manifest(tmp_path, [{"model": "models/m00.ply"}],
                              {"size": [16, 16], "views": {"plan": "sphere", "count": 1}})
    out = str(tmp_path / "dataset") + "/"
    assert main(["batch", str(manifest), "-o", out, "-q"]) == 0
    err = capsys.readouterr().err
    assert "index.jsonl" in err and "//index.jsonl" not in err, err


def test_a_nerf_synthetic_file_with_no_images_takes_the_jobs_size(tmp_path):
    """A Blender / NeRF-synthetic transforms.json gives camera_angle_x and poses only (no
    w, h, and its images not beside it): the job's size is the images' (was refused: "no
    image size: give w and h"), the field of view the file's angle."""
    import math

    make_models(tmp_path / "models", 1)
    pose = np.eye(4)
    pose[:3, 3] = (0.0, 0.0, 4.0)  # looking down -z at the model, OpenGL convention
    (tmp_path / "transforms.json").write_text(json.dumps({
        "camera_angle_x": math.radians(40.0),
        "frames": [{"file_path": "./train/r_0", "transform_matrix": pose.tolist()}]}))
    manifest = tmp_path / "cams.jsonl"
    manifest.write_text(json.dumps({"model": "models/m00.ply", "size": [40, 30],
                                    "views": {"plan": "cameras",
                                              "file": "transforms.json"}}) + "\n")
    assert render_dataset(manifest, tmp_path / "out")["views"] == 1
    image = np.asarray(Image.open(tmp_path / "out" / "m00" / "images" / "0000.png"))
    assert image.shape[:2] == (30, 40)
    written = json.loads((tmp_path / "out" / "m00" / "transforms.json").read_text())
    assert written["camera_angle_x"] == pytest.approx(math.radians(40.0), rel=1e-4)


def test_a_command_line_default_that_jobs_override_is_said(tmp_path):
    """--views N when jobs set their own views: the jobs' views win, as the precedence
    says, and one line says so (the flag was silently without effect)."""
    import warnings

    make_models(tmp_path / "models", 2)
    manifest = write_manifest(tmp_path, [
        {"model": "models/m00.ply", "views": {"plan": "sphere", "count": 2}},
        {"model": "models/m01.ply"}])
    with pytest.warns(facet.FacetWarning, match=r"1 of 2 jobs set their own views: --views"):
        own, plain = load_manifest(manifest, {"views": {"plan": "sphere", "count": 5}})
    assert own.views.count == 2 and plain.views.count == 5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_manifest(manifest, {"size": [32, 32]})  # (no job sets its size: nothing said)
