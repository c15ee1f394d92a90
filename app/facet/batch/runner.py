"""Rendering a dataset: jobs (facet.batch.manifest) streamed to worker processes, each with
one long-lived Renderer (one GL context per worker, never per model), files laid out by
facet.batch.layout. A worker takes jobs in short runs (``chunks``) and loads the next
model in a thread while it renders one (``render_jobs``).

Workers: ``workers`` processes (default: one where the renderer is a CPU rasteriser, which
already uses every core; one per GPU otherwise), each on the EGL device ``gpus[k]`` when
given. Robustness: a finished job (its transforms.json with the job's digest) is skipped,
so a rerun resumes; a job whose model is bad fails alone (its one-line error in the index)
and the run goes on, even when it kills its worker (``_run_pool``); every file is written
atomically; Ctrl-C or SIGTERM stops the workers and leaves no partial file under a final
name. Determinism: a job's files depend only on
the job (random views are seeded per job), not on which worker rendered it.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from ..errors import FacetError, InputError
from .colmap import surface_points, write_colmap
from .layout import append_index, finished, write_transforms, write_view

_WORKER: dict = {}  # in a worker process: its renderer
CHUNK = 8  # jobs handed to a worker at once (render_jobs loads one ahead within them)


def render_job(job, out: Path, renderer, load=None) -> dict:
    """Render one job's views into ``out / job.name``; the index record. ``load``: a
    callable giving the job's scene (default: open its model now)."""
    from ..scene.source import open_scene

    start = time.perf_counter()
    folder = Path(out) / job.name
    record = {"job": job.name, "model": str(job.model), "views": 0, "files": 0}
    digest = job.digest()
    if finished(folder, digest):
        return {**record, "status": "skipped", "seconds": 0.0}
    try:
        scene = load() if load is not None else open_scene(job.model)
        w, h = job.size
        cameras = job.views.cameras(scene.bounds, job.up, w / h)
        # COLMAP's point cloud is read from depth and position, saved or not.
        outputs = (*job.outputs, *(c for c in ("depth", "position") if job.colmap and
                                   c not in job.outputs))
        opts = renderer.options(scene, size=job.size, outputs=outputs, **job.options)
        entries, points = [], []
        rng = np.random.default_rng(job.views.seed)
        for i, camera in enumerate(cameras):
            frame = renderer.render(scene, camera, opts)
            entries.append(write_view(folder, i, frame, job.outputs, job.float_files))
            if job.colmap:
                points.append(surface_points(frame, rng))
        if job.colmap:
            write_colmap(folder, job.size, cameras, [e["file_path"][len("images/"):]
                                                     for e in entries], np.vstack(points))
        write_transforms(folder, job, cameras, entries)
    except (FacetError, MemoryError) as exc:
        error = (str(exc).splitlines()[0] if isinstance(exc, FacetError) else
                 "out of memory: the model is too large for this machine")
        return {**record, "status": "failed", "error": error,
                "seconds": round(time.perf_counter() - start, 3)}
    files = sum(1 for p in folder.rglob("*") if p.is_file() and not p.name.startswith("."))
    return {**record, "status": "done", "views": len(cameras), "files": files,
            "seconds": round(time.perf_counter() - start, 3)}


def render_jobs(jobs, out: Path, renderer, confine=None):
    """render_job for each of ``jobs`` in turn (a generator of index records), the next
    model loading in a thread while this one renders: parsing a file and computing its
    normals is CPU work that overlaps the GPU's (and on a GPU it is most of a model's
    cost). ``confine``: None, or (folder, widen) (``job_root``), the folder outside which
    a job reads no file, in the loader and the renderer alike."""
    from concurrent.futures import ThreadPoolExecutor

    out = Path(out)
    with ThreadPoolExecutor(1, thread_name_prefix="facet-load") as loader:

        def start(job):
            if finished(out / job.name, job.digest()):
                return None
            return loader.submit(_load, job.model, job_root(confine, job.model))

        ahead = start(jobs[0]) if jobs else None
        for k, job in enumerate(jobs):
            current, ahead = ahead, start(jobs[k + 1]) if k + 1 < len(jobs) else None
            with _confined(job_root(confine, job.model)):
                yield render_job(job, out, renderer,
                                 None if current is None else current.result)
            del current  # its scene goes once rendered


def job_root(confine, model) -> Path | None:
    """The folder outside which a job reads no file: ``confine = (folder, widen)``; with
    ``widen`` (the default, a manifest's own folder) a model the manifest lists outside
    that folder gets its own folder instead: the manifest named it, so it is read, and
    what it refers to (textures, material libraries, a scene's meshes) must lie beside
    or under it."""
    if confine is None:
        return None
    root, widen = Path(confine[0]), confine[1]
    model = Path(model).resolve()
    return model.parent if widen and root not in model.parents else root


def _confined(root):
    import contextlib

    if root is None:
        return contextlib.nullcontext()
    from ..guard import confined

    return confined(root)


def _load(model, root):
    from ..scene.source import open_scene

    with _confined(root):
        return open_scene(model)


def _worker_init(devices, counter, threads, confine) -> None:
    """A worker's set-up: its EGL device, llvmpipe's thread count, one renderer, and an
    exit when the parent dies (facet.image.sequence.watch_parent). A renderer that cannot
    be made is reported by the worker's first run of jobs (an exception here would have
    the pool start the worker again, for ever)."""
    import warnings

    from ..errors import show_warning
    from ..image.sequence import watch_parent

    warnings.showwarning = show_warning
    watch_parent()
    with counter.get_lock():
        k = counter.value
        counter.value += 1
    if threads:
        os.environ["LP_NUM_THREADS"] = str(threads)
    device = devices[k % len(devices)] if devices else None
    from ..render.renderer import Renderer

    _WORKER["confine"] = confine
    try:
        _WORKER["renderer"] = Renderer(device=device)
    except FacetError as exc:
        _WORKER["error"] = exc


def _worker_jobs(jobs, out) -> list[dict]:
    if "error" in _WORKER:
        raise _WORKER["error"]  # the run stops with it (render_dataset)
    return list(render_jobs(jobs, out, _WORKER["renderer"], _WORKER.get("confine")))


def chunks(jobs: list, workers: int) -> list[list]:
    """Jobs in runs of up to CHUNK for one worker each (the next one loads while one
    renders), short enough that every worker gets several (the run ends together)."""
    size = max(1, min(CHUNK, len(jobs) // (4 * workers)))
    return [jobs[i:i + size] for i in range(0, len(jobs), size)]


def default_workers(gpus=None) -> int:
    """One worker where the GL is a CPU rasteriser (llvmpipe uses every core already), else
    one per GPU given (at least one)."""
    from ..gl.context import create_headless

    ctx = create_headless()
    try:
        software = "llvmpipe" in str(ctx.info.get("GL_RENDERER", "")).lower()
    finally:
        ctx.release()
    return 1 if software or not gpus else len(gpus)


def render_dataset(jobs, out, *, workers: int | None = None, gpus=None,
                   quiet: bool = True, confine=None) -> dict:
    """Render ``jobs`` into the folder ``out`` (module docstring); returns the counts
    {"done", "failed", "skipped", "views", "seconds"}. ``confine``: None or (folder,
    widen), where a job may read files (``job_root``; facet.guard.confined)."""
    import multiprocessing

    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder")
    out.mkdir(parents=True, exist_ok=True)
    workers = workers or default_workers(gpus)
    if workers < 1:
        raise InputError(f"--workers must be at least 1, got {workers}")
    counts = {"done": 0, "failed": 0, "skipped": 0, "views": 0}
    start = time.perf_counter()
    bar = _progress(sum(j.views.count for j in jobs), quiet)
    ctx = multiprocessing.get_context("spawn")
    counter = ctx.Value("i", 0)
    threads = max(1, (os.cpu_count() or 1) // workers) if workers > 1 else 0
    setup = (list(gpus or []), counter, threads,
             None if confine is None else (str(confine[0]), bool(confine[1])))

    def note(record: dict) -> None:
        append_index(out / "index.jsonl", record)
        counts[record["status"]] += 1
        counts["views"] += record["views"]
        bar.update(record["views"] if record["status"] == "done" else 0)
        if record["status"] == "failed" and not quiet:
            import sys

            print(f"facet: {record['job']}: {record['error']}", file=sys.stderr)

    try:
        _run_pool(ctx, workers, setup, chunks(jobs, workers), out, note)
    finally:
        bar.close()
    counts["seconds"] = round(time.perf_counter() - start, 3)
    return counts


def _run_pool(ctx, workers: int, setup, runs: list[list], out: Path, note) -> None:
    """Runs of jobs on ``workers`` processes, two runs in flight per worker. A worker that
    dies (killed for memory by a huge model, a crash in a driver) breaks the pool: the jobs
    that were in flight are then tried again one at a time, alone, in a new pool, so the
    one that kills its worker is found and fails alone; the others go on."""
    from collections import deque
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    from concurrent.futures.process import BrokenProcessPool

    queue, suspects = deque(runs), deque()
    while queue or suspects:
        pool = ProcessPoolExecutor(workers, mp_context=ctx, initializer=_worker_init,
                                   initargs=setup)
        flight: dict = {}
        try:
            while queue or suspects or flight:
                if suspects:  # alone: nothing else in flight
                    if not flight:
                        run = [suspects.popleft()]
                        flight[pool.submit(_worker_jobs, run, out)] = run
                else:
                    while queue and len(flight) < 2 * workers:
                        run = queue.popleft()
                        flight[pool.submit(_worker_jobs, run, out)] = run
                done, _ = wait(flight, return_when=FIRST_COMPLETED)
                broken = [f for f in done if isinstance(f.exception(), BrokenProcessPool)]
                for future in done:
                    if future not in broken:
                        flight.pop(future)
                        for record in future.result():  # a worker's error: raised here
                            note(record)
                if broken:
                    runs_lost = list(flight.values())
                    flight.clear()
                    if len(runs_lost) == 1 and len(runs_lost[0]) == 1:  # it ran alone
                        note(_died(runs_lost[0][0]))
                    else:
                        suspects.extend(job for run in runs_lost for job in run)
                    raise BrokenProcessPool
        except BrokenProcessPool:
            _stop(pool)
            continue
        except BaseException:
            _stop(pool)  # Ctrl-C / SIGTERM: stop now; files under final names are whole
            raise
        pool.shutdown()


def _died(job) -> dict:
    return {"job": job.name, "model": str(job.model), "views": 0, "files": 0,
            "status": "failed", "seconds": 0.0,
            "error": "its worker process died rendering it (out of memory? a crash in the "
                     "GL driver?); the rest of the run went on"}


def _stop(pool) -> None:
    """Shut ``pool`` down now, its workers killed (what Pool.terminate does)."""
    processes = list(getattr(pool, "_processes", {}).values())  # before shutdown clears it
    for process in processes:
        process.terminate()
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        process.join(5)


def _progress(total: int, quiet: bool):
    import sys

    from tqdm import tqdm

    return tqdm(total=total, desc="batch", unit="view", file=sys.stderr, leave=False,
                disable=quiet or not sys.stderr.isatty())
