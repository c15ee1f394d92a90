"""The same dataset jobs on a Ray cluster (``facet batch --ray [ADDRESS]``, the ``ray``
extra): one actor per CPU slot (or per GPU with ``gpus``), each holding one renderer, the
jobs spread over them in short runs as they free up (facet.batch.runner.chunks; an actor
loads the next model while it renders one), files written by the actors to ``out`` (a
folder every node sees), the index written by the driver. A run whose actor is lost is
retried on another (``RETRIES`` times; its finished jobs are skipped then) before its
jobs count as failed. Files are the same as a local
run's: jobs do not depend on where they ran. The driver's ``FACET_*`` settings (the GL
backend, budgets, ...) travel to the actors in their runtime environment, as they reach a
local run's workers, whether the cluster was started here or earlier.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

from ..errors import FacetError, InputError
from ..guard import writing_into
from .layout import append_index, compact_index

RETRIES = 2


def render_dataset_ray(jobs, out, *, address: str | None = None, gpus: int = 0,
                       actors: int | None = None, quiet: bool = True, confine=None) -> dict:
    """Render ``jobs`` into ``out`` on Ray (module docstring); the counts, as the local
    runner returns them. ``address``: a running cluster's (None: start a local one)."""
    try:
        import ray
    except ImportError:
        raise InputError("--ray needs the Ray package: pip install 'facet-render[ray]'") from None
    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    started = not ray.is_initialized()
    if started:
        try:
            ray.init(address=address, include_dashboard=False, log_to_driver=False,
                     configure_logging=False)
        except (ConnectionError, RuntimeError, ValueError) as exc:
            detail = " ".join(str(exc).split())[:200] or type(exc).__name__
            where = f"the Ray cluster at {address}" if address else "a local Ray cluster"
            raise InputError(f"--ray: cannot start or reach {where} ({detail})") from None
    try:
        return _run(ray, jobs, out, gpus, actors, quiet, confine)
    finally:
        if started:
            ray.shutdown()


def _run(ray, jobs, out: Path, gpus: int, actors, quiet: bool, confine) -> dict:
    from .runner import _progress, chunks

    resources = ray.cluster_resources()
    have_gpus, have_cpus = int(resources.get("GPU", 0)), int(resources.get("CPU", 1))
    if gpus and have_gpus < max(1, actors or 0):  # actors that would wait for ever
        raise InputError(f"--gpus with --ray: the Ray cluster has {have_gpus} GPU(s) and "
                         f"{have_cpus} CPUs; leave --gpus out to render on CPU slots")
    count = actors or (have_gpus if gpus else max(1, have_cpus))
    cpus = max(1, have_cpus // count)
    options = {"num_cpus": cpus, "num_gpus": 1 if gpus else 0, "max_restarts": 1}
    settings = {k: v for k, v in os.environ.items() if k.startswith("FACET_")}
    if settings:
        options["runtime_env"] = {"env_vars": settings}
    actor_class = ray.remote(**options)(_RenderActor)
    pool = [actor_class.remote(cpus, None if confine is None else
                               (str(confine[0]), bool(confine[1])))
            for _ in range(count)]
    counts = {"done": 0, "failed": 0, "skipped": 0, "views": 0}
    start = time.perf_counter()
    bar = _progress(sum(j.views.count for j in jobs), quiet)
    pending = {}  # object ref -> (chunk of jobs, attempts, actor index)
    queue = [(chunk, 0) for chunk in chunks(jobs, count)]
    # two chunks in flight per actor: the next waits in the actor's queue, so an actor never
    # idles for a driver round trip between them
    free = list(range(count)) * 2
    try:
        while queue or pending:
            while queue and free:
                chunk, attempts = queue.pop(0)
                k = free.pop()
                pending[pool[k].render.remote(chunk, str(out))] = (chunk, attempts, k)
            done, _ = ray.wait(list(pending), num_returns=1)
            chunk, attempts, k = pending.pop(done[0])
            free.append(k)
            try:
                records = ray.get(done[0])
            except ray.exceptions.RayTaskError as exc:
                if isinstance(exc.cause, FacetError):  # its renderer could not be made
                    raise exc.cause from None
                raise
            except ray.exceptions.RayError as exc:  # the actor was lost: try elsewhere
                if attempts < RETRIES:  # (its finished jobs are skipped then)
                    queue.insert(0, (chunk, attempts + 1))
                    continue
                records = [{"job": job.name, "model": str(job.model), "views": 0,
                            "files": 0, "status": "failed", "seconds": 0.0,
                            "error": f"lost its Ray worker {RETRIES + 1} times "
                                     f"({type(exc).__name__})"} for job in chunk]
            for record in records:
                with writing_into(out):
                    append_index(out / "index.jsonl", record)
                counts[record["status"]] += 1
                counts["views"] += record["views"]
                bar.update(record["views"] if record["status"] == "done" else 0)
    finally:
        bar.close()
        with writing_into(out):
            compact_index(out / "index.jsonl")
        for actor in pool:
            ray.kill(actor)
    counts["seconds"] = round(time.perf_counter() - start, 3)
    return counts


class _RenderActor:
    """One renderer per actor, for its whole life."""

    def __init__(self, threads: int, confine):
        os.environ.setdefault("LP_NUM_THREADS", str(threads))
        from ..errors import FacetError
        from ..render.renderer import Renderer

        self.confine = confine
        try:
            self.renderer, self.error = Renderer(), None
        except FacetError as exc:  # reported by the first call (a bad GPU, no GL at all)
            self.renderer, self.error = None, exc

    def render(self, jobs, out: str) -> list[dict]:
        from .runner import render_jobs

        if self.error is not None:
            raise self.error

        return list(render_jobs(jobs, Path(out), self.renderer, self.confine))
