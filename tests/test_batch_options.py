"""Render options in datasets go through the one door: a job's msaa / spp / environment
render (parsed once, never again), a rerun skips them, an environment file is found beside
the manifest whatever the working folder, and a scene file's [render] table (size,
outputs, up) beats a dataset's defaults while a manifest's values beat the scene file."""

import json

import numpy as np
from PIL import Image

from batch_data import make_models, write_manifest
from facet.batch import render_dataset


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
