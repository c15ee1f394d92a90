"""Rendering a dataset's jobs (facet.batch.manifest) with one long-lived Renderer, files
laid out by facet.batch.layout: ``render_job`` (one model's views), ``render_jobs`` (a
run of jobs, the next model loading in a thread while one renders), ``chunks`` (jobs in
short runs for workers). Where they run: local worker processes (facet.batch.pool) or
Ray actors (facet.batch.ray_runner).

Robustness: a finished job (its transforms.json with the job's digest) is skipped, so a
rerun resumes; a job whose model is bad fails alone (its one-line error in the index) and
the run goes on; every file is written atomically. Determinism: a job's files depend only
on the job (random views are seeded per job), not on which worker rendered it.
"""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..errors import FacetError, gl_out_of_memory
from ..guard import writing_into
from .colmap import surface_points, write_colmap
from .layout import finished, write_transforms, write_view
from .manifest import FRONT, job_root

CHUNK = 8  # jobs handed to a worker at once (render_jobs loads one ahead within them)


def render_job(job, out: Path, renderer, load=None, on_view=None) -> dict:
    """Render one job's views into ``out / job.name``; the index record. ``load``: a
    callable giving the job's scene (default: open its model now); ``on_view(job)``:
    called as each view's files are written (progress)."""
    from ..formats.source import open_scene

    start = time.perf_counter()
    folder = Path(out) / job.name
    record = {"job": job.name, "model": str(job.model), "views": 0, "files": 0}
    digest = job.digest()
    if finished(folder, digest):
        return {**record, "status": "skipped", "seconds": 0.0}
    try:
        scene = load() if load is not None else open_scene(job.model, **job.load)
        opts = job_options(job, scene, renderer)
        # transforms.json points at the colour images; COLMAP's point cloud is read from
        # depth and position, saved or not.
        saved = tuple(dict.fromkeys(("color", *opts.outputs)))
        extra = ("depth", "position") if job.colmap else ()
        opts = replace(opts, outputs=tuple(dict.fromkeys((*saved, *extra))))
        configs = job.views.view_joints(scene)
        posed = [scene] if configs is None else [scene.posed(c) for c in configs]
        bounds = np.array([s.at(opts.time, opts.animation).bounds for s in posed])
        cameras = job.views.cameras(np.stack([bounds[:, 0].min(0), bounds[:, 1].max(0)]),
                                    opts.up, opts.width / opts.height, size=opts.size)
        times = job.views.view_times(len(cameras))
        entries, points = [], []
        rng = np.random.default_rng(job.views.seed)
        for i, camera in enumerate(cameras):
            view_opts = opts if times is None else replace(opts, time=times[i])
            frame = renderer.render(posed[i % len(posed)], camera, view_opts)
            entries.append(write_view(folder, i, frame, saved, job.float_files))
            if times is not None:
                entries[-1]["time"] = round(times[i], 6)
            if configs is not None:
                entries[-1]["joints"] = {k: round(x, 9) for k, x in configs[i].items()}
            if on_view is not None:
                on_view(job)
            if job.colmap:
                points.append(surface_points(frame, rng))
        if job.colmap:
            write_colmap(folder, opts.size, cameras, [e["file_path"][len("images/"):]
                                                      for e in entries], np.vstack(points))
        write_transforms(folder, job, opts.size, cameras, entries)
    except Exception as exc:  # noqa: BLE001 - only the user's kinds; the rest is re-raised
        error = (str(exc).splitlines()[0] if isinstance(exc, FacetError) else
                 "out of memory: the model is too large for this machine"
                 if isinstance(exc, MemoryError) else gl_out_of_memory(exc))
        if error is None:
            raise
        return {**record, "status": "failed", "error": error,
                "seconds": round(time.perf_counter() - start, 3)}
    files = sum(1 for p in folder.rglob("*") if p.is_file() and not p.name.startswith("."))
    return {**record, "status": "done", "views": len(cameras), "files": files,
            "seconds": round(time.perf_counter() - start, 3)}


def job_options(job, scene, renderer):
    """The options of ``job``'s renders of ``scene`` (facet.options.render.options_for: a
    dataset's defaults < the scene file's [render] < the job's). A cameras file's image
    size comes before the dataset's default size (its cameras are made for it)."""
    if job.views.file is not None and "size" not in job.options and \
            "size" not in scene.options:
        from .transforms_file import file_size

        size = file_size(job.views.file)  # (None: the file gives none, the job's is used)
        if size is not None:
            return renderer.options(scene, job.options, front=FRONT, size=size)
    return renderer.options(scene, job.options, front=FRONT)


def render_jobs(jobs, out: Path, renderer, confine=None, on_view=None):
    """render_job for each of ``jobs`` in turn (a generator of index records), the next
    model loading in a thread while this one renders: parsing a file and computing its
    normals is CPU work that overlaps the GPU's (and on a GPU it is most of a model's
    cost). ``confine``: None, or (folder, widen) (``job_root``), the folder outside which
    a job reads no file, in the loader and the renderer alike; ``on_view``: as for
    ``render_job``."""
    from concurrent.futures import ThreadPoolExecutor

    out = Path(out)
    with ThreadPoolExecutor(1, thread_name_prefix="facet-load") as loader:

        def start(job):
            if finished(out / job.name, job.digest()):
                return None
            return loader.submit(_load, job.model, job_root(confine, job.model), job.load)

        ahead = start(jobs[0]) if jobs else None
        for k, job in enumerate(jobs):
            current, ahead = ahead, start(jobs[k + 1]) if k + 1 < len(jobs) else None
            with _confined(job_root(confine, job.model)), writing_into(out):
                yield render_job(job, out, renderer,
                                 None if current is None else current.result, on_view)
            del current  # its scene goes once rendered


def _confined(root):
    import contextlib

    if root is None:
        return contextlib.nullcontext()
    from ..guard import confined

    return confined(root)


def _load(model, root, load=None):
    from ..formats.source import open_scene

    with _confined(root):
        return open_scene(model, **(load or {}))


def chunks(jobs: list, workers: int) -> list[list]:
    """Jobs in runs of up to CHUNK for one worker each (the next one loads while one
    renders), short enough that every worker gets several (the run ends together)."""
    size = max(1, min(CHUNK, len(jobs) // (4 * workers)))
    return [jobs[i:i + size] for i in range(0, len(jobs), size)]


def _progress(total: int, quiet: bool):
    import sys

    from tqdm import tqdm

    return tqdm(total=total, desc="batch", unit="view", file=sys.stderr, leave=False,
                disable=quiet or not sys.stderr.isatty())
