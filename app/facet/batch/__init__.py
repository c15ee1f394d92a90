"""Batch rendering of datasets: manifests of many models (facet.batch.manifest), view
plans (facet.batch.views), jobs rendered by one long-lived renderer (facet.batch.runner)
in local worker processes (facet.batch.pool) or on Ray (facet.batch.ray_runner), and the
files the learning and reconstruction tools read (facet.batch.layout, colmap).
``facet batch`` is its command line."""

from __future__ import annotations

from typing import Annotated

from ..boundary import Count, FilePath, Items, checked


@checked
def render_dataset(manifest: FilePath | list, out: FilePath, *, defaults: dict | None = None,
                   workers: Annotated[int | None, Count(1, 4096)] = None,
                   gpus: Annotated[list | tuple | None, Items(-1, Count(0))] = None,
                   quiet: bool = True, confine: FilePath | None = "manifest",
                   ray: bool | str | None = None) -> dict:
    """Render every job of a manifest into a dataset folder, on every core (and GPU, or
    a Ray cluster), resuming what is already there.

    Parameters
    ----------
    manifest : str, Path or list of facet.batch.manifest.Job
        A manifest file (TOML / JSON lines), a glob of model files, or jobs.
    out : str or Path
        The output folder (``index.jsonl``, one folder of views per model).
    defaults : dict, optional
        Job settings under the manifest's own (``views``, ``outputs``, ``size``, ...).
    workers : int, optional
        Worker processes (default: one per core, or one per GPU).
    gpus : list of int, optional
        EGL device indices, one worker each.
    quiet : bool
        No progress lines.
    confine : str, Path or None
        Where jobs may read files: ``"manifest"`` (a manifest file's folder, and a model's
        own folder for a model it names elsewhere), a folder for every job, or None.
    ray : bool or str, optional
        Run on Ray: True for a local cluster, or a cluster's address.

    Returns
    -------
    dict
        The counts: ``done``, ``failed``, ``skipped``, ``views`` and ``seconds``.
    """
    from pathlib import Path

    from .manifest import Job, load_manifest

    if isinstance(manifest, list) and not all(isinstance(j, Job) for j in manifest):
        from ..boundary import ArgumentError

        raise ArgumentError("render_dataset: manifest: expected a manifest file, a glob or a "
                            "list of facet.batch.manifest.Job, got a list of "
                            f"{', '.join(sorted({type(j).__name__ for j in manifest}))}")
    from .pool import render_dataset as run

    if workers is not None and workers < 1:
        from ..errors import InputError

        raise InputError(f"--workers must be at least 1, got {workers}")
    held: tuple[Path, bool] | None = None  # (folder, per job) of the confinement
    if confine == "manifest":
        path = Path(str(manifest)) if not isinstance(manifest, list) else None
        held = (path.resolve().parent, True) if path is not None and path.is_file() else None
    elif confine is not None:
        held = (Path(confine).resolve(), False)
    # Confinement first: a job's cameras file is checked against it before it is read.
    jobs = manifest if isinstance(manifest, list) else load_manifest(manifest, defaults,
                                                                     held)
    if ray:
        from .ray_runner import render_dataset_ray

        return render_dataset_ray(jobs, out, address=None if ray is True else str(ray),
                                  gpus=len(gpus or []), actors=workers, quiet=quiet,
                                  confine=held)
    return run(jobs, out, workers=workers, gpus=gpus, quiet=quiet, confine=held)
