"""Batch benchmark: a dataset of 200 models of about 20k triangles (icospheres of varying
size and position, written as PLY), 256x256, 8 views each on a sphere, colour + depth +
normals + transforms.json: one worker, local workers, and Ray on this machine; and what a
model costs besides its views (load, upload, teardown).

    python benchmarks/batch.py [--models N]

Prints tables; asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh


def make_models(folder: Path, n: int) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    base = trimesh.creation.icosphere(subdivisions=5)  # 20,480 triangles
    rng = np.random.default_rng(0)
    lines = []
    for i in range(n):
        mesh = base.copy()
        mesh.apply_scale(rng.uniform(0.5, 2.0, 3))
        mesh.apply_translation(rng.uniform(-1, 1, 3))
        path = folder / f"m{i:04d}.ply"
        mesh.export(path)
        lines.append(json.dumps({"model": f"models/{path.name}"}))
    manifest = folder.parent / "dataset.jsonl"
    defaults = {"size": [256, 256], "outputs": ["color", "depth", "normals"],
                "views": {"plan": "sphere", "count": 8}}
    manifest.write_text(json.dumps({"defaults": defaults}) + "\n" + "\n".join(lines) + "\n")
    return manifest


def overhead(manifest: Path, models: int = 12, reps: int = 3) -> tuple[float, float]:
    """(seconds per model besides its views, seconds of its 8 views): a worker's run of
    ``models`` jobs (facet.batch.runner.render_jobs: load one ahead, upload, render, write,
    let go) against the same views and files of scenes already loaded and uploaded;
    interleaved ``reps`` times, medians."""
    from facet.batch.layout import write_transforms, write_view
    from facet.batch.manifest import load_manifest
    from facet.batch.runner import render_jobs
    from facet.render.renderer import Renderer
    from facet.scene.source import open_scene

    jobs = load_manifest(manifest)[:models + 1]
    whole, views = [], []
    with Renderer() as r, tempfile.TemporaryDirectory() as tmp:
        list(render_jobs(jobs[:1], Path(tmp) / "warm", r))  # programs compiled
        for rep in range(reps):
            t = time.perf_counter()
            list(render_jobs(jobs[1:], Path(tmp) / f"a{rep}", r))
            whole.append((time.perf_counter() - t) / models)
            ready = []
            for job in jobs[1:]:
                scene = open_scene(job.model)
                cams = job.views.cameras(scene.bounds, job.up)
                opts = r.options(scene, size=job.size, outputs=job.outputs)
                r.render(scene, cams[0], opts).settle()  # uploaded
                ready.append((job, scene, cams, opts))
            t = time.perf_counter()
            for k, (job, scene, cams, opts) in enumerate(ready):
                folder = Path(tmp) / f"b{rep}-{k}"
                entries = [write_view(folder, i, r.render(scene, cam, opts), job.outputs)
                           for i, cam in enumerate(cams)]
                write_transforms(folder, job, cams, entries)
            views.append((time.perf_counter() - t) / models)
            del ready
    w, v = statistics.median(whole), statistics.median(views)
    return w - v, v


def _row(label: str, render_dataset, manifest: Path, out: Path, **kw) -> None:
    t = time.perf_counter()
    counts = render_dataset(manifest, out, **kw)
    dt = time.perf_counter() - t
    print(f"{label:>28} | {counts['views'] / dt:8.1f} {dt:7.1f}")


def table(n: int) -> None:
    from facet.batch import render_dataset

    with tempfile.TemporaryDirectory() as tmp:
        manifest = make_models(Path(tmp) / "models", n)
        extra, views = overhead(manifest)
        print(f"\nBatch: {n} models of 20k triangles, 256x256, 8 views each, colour + depth + "
              "normals + transforms.json")
        print(f"{'':>28} | {'views/s':>8} {'s':>7}")
        for label, kw in [("1 worker", dict(workers=1)), ("2 local workers", dict(workers=2))]:
            _row(label, render_dataset, manifest, Path(tmp) / label.replace(" ", "-"), **kw)
        try:
            import ray
        except ImportError:
            print("(Ray not installed: pip install 'facet[ray]')")
        else:
            t = time.perf_counter()
            ray.init(include_dashboard=False, log_to_driver=False, configure_logging=False)
            started = time.perf_counter() - t
            _row("Ray, local cluster", render_dataset, manifest, Path(tmp) / "ray", ray=True)
            ray.shutdown()
            print(f"(the Ray cluster's start, {started:.1f} s, is not counted)")
        print(f"per model besides its views (load, one ahead in a thread; upload; teardown): "
              f"{extra * 1e3:.0f} ms, {extra / views:.0%} of its 8 views' {views * 1e3:.0f} ms")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", type=int, default=200)
    table(ap.parse_args().models)


if __name__ == "__main__":
    main()
