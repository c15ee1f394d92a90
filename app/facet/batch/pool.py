"""Rendering a dataset locally (``render_dataset``): with one worker in the calling process
(a notebook, or a script without a ``__main__`` guard, can run it), with more on worker
processes. Each worker holds one long-lived Renderer (its EGL device, llvmpipe's thread
count, an exit when the parent dies) and takes runs of jobs (facet.batch.runner). The pool
survives a worker dying
(killed for memory by a huge model, a crash in a GL driver): the jobs in flight are tried
again one at a time, alone, so the one that kills its worker fails alone and the run goes
on (multiprocessing.Pool would wait for ever). Ctrl-C or SIGTERM kills the workers.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

from ..errors import FacetError, InputError
from ..guard import check_output, writing_into
from .layout import append_index, compact_index
from .runner import _progress, chunks, render_jobs

_WORKER: dict = {}  # in a worker process: its renderer, confinement, or setup error
NO_START = ("the worker processes could not start (they are spawned: a Python script that "
            "renders a dataset needs its code under `if __name__ == \"__main__\":`, and "
            "cannot be run from standard input)")


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

    if getattr(multiprocessing.current_process(), "_inheriting", False):
        # A spawned worker importing a script that renders at import time (no main
        # guard): stop here, before making queues whose semaphores it would leave behind.
        raise InputError(NO_START)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder")
    out.mkdir(parents=True, exist_ok=True)
    with writing_into(out):  # before any job: an index that leads elsewhere is refused now
        check_output(out / "index.jsonl")
    workers = default_workers(gpus) if workers is None else workers
    if workers < 1:
        raise InputError(f"--workers must be at least 1, got {workers}")
    counts = {"done": 0, "failed": 0, "skipped": 0, "views": 0}
    start = time.perf_counter()
    bar = _progress(sum(j.views.count for j in jobs), quiet)
    ctx = multiprocessing.get_context("spawn")
    counter = ctx.Value("i", 0)
    threads = max(1, (os.cpu_count() or 1) // workers) if workers > 1 else 0
    news = ctx.Queue()  # from the workers: each view written, each job's record
    setup = (list(gpus or []), counter, threads,
             None if confine is None else (str(confine[0]), bool(confine[1])), news)
    planned = {_key(j): j.views.count for j in jobs}
    shown = dict.fromkeys(planned, 0)

    def note(record: dict) -> None:
        append_index(out / "index.jsonl", record)
        counts[record["status"]] += 1
        counts["views"] += record["views"]
        key = (record["job"], record["model"])
        bar.update(max(0, planned.get(key, 0) - shown.get(key, 0)))  # the rest: skipped...
        shown[key] = planned.get(key, 0)
        if record["status"] == "failed" and not quiet:
            import sys

            from ..errors import printable

            print(printable(f"facet: {record['job']}: {record['error']}"), file=sys.stderr)

    def view(key) -> None:
        if shown.get(key, 0) < planned.get(key, 0):
            shown[key] += 1
            bar.update(1)

    try:
        with writing_into(out):  # the index, like every job's files, stays inside out
            if workers == 1:
                run_here(jobs, out, (gpus or [None])[0], confine, note, view)
            else:
                run_pool(ctx, workers, setup, chunks(jobs, workers), out, note, news, view)
    finally:
        bar.close()
        with writing_into(out):
            compact_index(out / "index.jsonl")
    counts["seconds"] = round(time.perf_counter() - start, 3)
    return counts


def run_here(jobs, out: Path, device, confine, note, view) -> None:
    """Every job in this process, with one renderer (on EGL device ``device``)."""
    from ..render.renderer import Renderer

    with Renderer(device=device) as renderer:
        for record in render_jobs(jobs, out, renderer, confine,
                                  on_view=lambda job: view(_key(job))):
            note(record)


def _key(job) -> tuple[str, str]:
    return (job.name, str(job.model))


def _worker_init(devices, counter, threads, confine, news) -> None:
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
    _WORKER["news"] = news
    try:
        _WORKER["renderer"] = Renderer(device=device)
    except FacetError as exc:
        _WORKER["error"] = exc
    news.put(("ready", os.getpid()))  # this worker started: a later death is a job's doing


def _worker_jobs(jobs, out) -> list[dict]:
    if "error" in _WORKER:
        raise _WORKER["error"]  # the run stops with it (render_dataset)
    news = _WORKER["news"]
    records = []
    for record in render_jobs(jobs, out, _WORKER["renderer"], _WORKER.get("confine"),
                              on_view=lambda job: news.put(("view", _key(job)))):
        news.put(("job", record))  # noted at once: a worker that dies later loses nothing
        records.append(record)
    return records


def run_pool(ctx, workers: int, setup, runs: list[list], out: Path, note, news,
             view) -> None:
    """Runs of jobs on ``workers`` processes, two runs in flight per worker; ``note`` gets
    each job's record once, as soon as the worker sends it on ``news`` (or, at the latest,
    with its run's result), ``view`` each view written. A worker that dies (killed for
    memory by a huge model, a crash in a driver) breaks the pool: the jobs in flight that
    have no record yet are then tried again one at a time, alone, in a new pool, so the
    one that kills its worker is found and fails alone; the others go on."""
    import queue as queues
    from collections import deque
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    from concurrent.futures.process import BrokenProcessPool

    noted: set = set()

    def once(record: dict) -> None:
        key = (record["job"], record["model"])
        if key not in noted:
            noted.add(key)
            note(record)

    started = [False]  # a worker of the current pool has started
    pids: set[int] = set()  # every worker that started: whose temporary files to remove

    def drain() -> None:
        while True:
            try:
                kind, item = news.get_nowait()
            except queues.Empty:
                return
            if kind == "ready":
                started[0] = True
                pids.add(item)
            else:
                (once if kind == "job" else view)(item)

    queue, suspects = deque(runs), deque()
    while queue or suspects:
        pool = ProcessPoolExecutor(workers, mp_context=ctx, initializer=_worker_init,
                                   initargs=setup)
        started[0] = False
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
                done, _ = wait(flight, timeout=0.2, return_when=FIRST_COMPLETED)
                drain()
                broken = [f for f in done if isinstance(f.exception(), BrokenProcessPool)]
                for future in done:
                    if future not in broken:
                        flight.pop(future)
                        for record in future.result():  # a worker's error: raised here
                            once(record)
                if broken:
                    drain()
                    if not started[0]:  # no worker got as far as its set-up
                        raise InputError(NO_START)
                    alone = [job for run in flight.values() for job in run]
                    lost = [j for j in alone if (j.name, str(j.model)) not in noted]
                    flight.clear()
                    if len(alone) == 1 and lost:  # it ran alone: the culprit
                        once(_died(lost[0]))
                    else:  # the ones without a record, each alone next
                        suspects.extend(lost)
                    raise BrokenProcessPool
        except BrokenProcessPool:
            _stop(pool, out, pids)
            continue
        except BaseException:
            drain()
            _stop(pool, out, pids)  # Ctrl-C / SIGTERM: stop now; files under final names are whole
            raise
        pool.shutdown()


def _died(job) -> dict:
    return {"job": job.name, "model": str(job.model), "views": 0, "files": 0,
            "status": "failed", "seconds": 0.0,
            "error": "its worker process died rendering it (out of memory? a crash in the "
                     "GL driver?); the rest of the run went on"}


def _stop(pool, out: Path, pids) -> None:
    """Shut ``pool`` down now, its workers killed (what Pool.terminate does), and the
    temporary files they were writing removed from ``out``."""
    from ..image.writers import remove_temporaries

    processes = list(getattr(pool, "_processes", {}).values())  # before shutdown clears it
    for process in processes:
        process.terminate()
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        process.join(5)
        if process.is_alive():  # deaf to SIGTERM (stuck in the driver)
            process.kill()
            process.join(5)
    remove_temporaries(out, {p.pid for p in processes} | set(pids))
