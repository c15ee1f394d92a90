"""Render options in datasets go through the one door: a job's msaa / spp / environment
render (parsed once, never again), a rerun skips them, an environment file is found beside
the manifest whatever the working folder, and a scene file's [render] table (size,
outputs, up) beats a dataset's defaults while a manifest's values beat the scene file."""

import json

import numpy as np
import pytest
from PIL import Image

from facet.batch import render_dataset

from batch_data import make_models, write_manifest


def test_msaa_spp_and_environment_jobs_render_and_a_rerun_skips_them(tmp_path, monkeypatch):
    data = tmp_path / "data"
    make_models(data / "models", 1)
    sky = np.full((16, 32, 3), (90, 140, 230), np.uint8)  # an equirectangular blue
    Image.fromarray(sky).save(data / "sky.png")
    jobs = [{"model": "models/m00.ply", "name": "msaa", "msaa": 2},
            {"model": "models/m00.ply", "name": "spp", "spp": 4},
            {"model": "models/m00.ply", "name": "env", "environment": "sky.png"}]
    manifest = write_manifest(data, jobs, {"size": [32, 32], "views": 2})
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # the environment is found beside the manifest
    counts = render_dataset(manifest, tmp_path / "out", quiet=True)
    index = [json.loads(line) for line in (tmp_path / "out" / "index.jsonl").open()]
    assert counts["done"] == 3, index
    env = np.asarray(Image.open(tmp_path / "out" / "env" / "images" / "0000.png"))
    assert env[0, 0, 2] > 150  # the sky behind the model, not the black default
    counts = render_dataset(manifest, tmp_path / "out", quiet=True)
    assert counts["skipped"] == 3 and counts["done"] == 0


SCENE = """
[render]
size = [40, 30]
outputs = ["color", "ids"]
up = "z"

[[objects]]
primitive = "cylinder"
radius = 0.3
height = 1.0
transform = [{rotate = {axis = "x", degrees = 90}}]
"""


def test_a_scene_files_render_table_beats_the_datasets_defaults(tmp_path):
    (tmp_path / "scene.toml").write_text(SCENE)
    views = {"plan": "turntable", "count": 4, "elevation": 20}
    manifest = write_manifest(tmp_path, [{"model": "scene.toml", "name": "file"},
                                         {"model": "scene.toml", "name": "job",
                                          "size": [24, 24]}], {"views": views})
    counts = render_dataset(manifest, tmp_path / "out", quiet=True)
    assert counts["done"] == 2
    folder = tmp_path / "out" / "file"
    image = np.asarray(Image.open(folder / "images" / "0000.png"))
    assert image.shape[:2] == (30, 40)  # the file's size, not the dataset's 256 x 256
    assert (folder / "masks").is_dir() and not (folder / "normals").exists()
    transforms = json.loads((folder / "transforms.json").read_text())
    eyes = np.array([np.array(f["transform_matrix"])[:3, 3] for f in transforms["frames"]])
    assert np.ptp(eyes[:, 2]) < 1e-6 < np.ptp(eyes[:, 1])  # orbiting about the file's z up
    job = np.asarray(Image.open(tmp_path / "out" / "job" / "images" / "0000.png"))
    assert job.shape[:2] == (24, 24)  # the manifest's value beats the file's


def _blender_transforms(folder, size, **intrinsics):
    """A NeRF-synthetic / Blender transforms.json: camera_angle_x and the frames' poses
    only (their images beside it give the size), or with the given intrinsics."""
    from facet.geometry.camera import Camera

    (folder / "train").mkdir(parents=True, exist_ok=True)
    frames = []
    for i, eye in enumerate([(0.0, 0.5, 3.0), (2.5, 1.0, 1.5), (-2.0, -0.5, 2.0)]):
        Image.fromarray(np.zeros((size[1], size[0], 3), np.uint8)).save(
            folder / "train" / f"r_{i}.png")
        view = Camera.look_at(eye, (0, 0, 0)).view
        frames.append({"file_path": f"./train/r_{i}", "rotation": 0.0,
                       "transform_matrix": np.linalg.inv(view).tolist()})
    data = {"camera_angle_x": 0.6911, "frames": frames, **intrinsics}
    (folder / "transforms.json").write_text(json.dumps(data))
    return folder / "transforms.json"


def test_a_nerf_synthetic_transforms_json_is_read(tmp_path):
    """camera_angle_x alone (the commonest kind): the size from the frames' images, square
    pixels, the centre in the middle; the sphere's centre (the world origin every pose
    looks at) lands in the middle of each mask. With fl_x, fl_y, cx, cy given they are
    honoured: the centre lands at (cx, cy)."""
    make_models(tmp_path / "models", 1)  # a sphere at the origin
    cams = _blender_transforms(tmp_path / "blender", (40, 30))
    cv = _blender_transforms(tmp_path / "cv", (40, 30), fl_x=50.0, fl_y=45.0, cx=14.0,
                             cy=19.0)
    manifest = write_manifest(tmp_path, [
        {"model": "models/m00.ply", "name": "blender", "outputs": ["color", "ids"],
         "views": {"plan": "cameras", "file": str(cams)}},
        {"model": "models/m00.ply", "name": "cv", "outputs": ["color", "ids"],
         "views": {"plan": "cameras", "file": str(cv)}}])
    assert render_dataset(manifest, tmp_path / "out", quiet=True)["done"] == 2
    for name, centre in (("blender", (20.0, 15.0)), ("cv", (14.0, 19.0))):
        folder = tmp_path / "out" / name
        written = json.loads((folder / "transforms.json").read_text())
        assert (written["w"], written["h"]) == (40, 30)
        if name == "blender":
            assert written["fl_x"] == pytest.approx(20 / np.tan(0.6911 / 2), rel=1e-6)
            assert written["fl_y"] == pytest.approx(written["fl_x"])
        else:
            assert (written["fl_x"], written["fl_y"]) == (50.0, 45.0)
        for i in range(3):
            ids = np.load(folder / "ids" / f"{i:04d}.npy")
            ys, xs = np.nonzero(ids >= 0)
            # pixel-corner convention: pixel (i, j) covers [i, i + 1)
            assert abs(xs.mean() + 0.5 - centre[0]) < 1.0 and \
                abs(ys.mean() + 0.5 - centre[1]) < 1.0, (name, i, xs.mean(), ys.mean())
