"""Batch rendering of datasets: manifests of many models (facet.batch.manifest), view
plans (facet.batch.views), jobs rendered by one long-lived renderer (facet.batch.runner)
in local worker processes (facet.batch.pool) or on Ray (facet.batch.ray_runner), and the
files the learning and reconstruction tools read (facet.batch.layout, colmap).
``facet batch`` is its command line."""

from __future__ import annotations


def render_dataset(manifest, out, *, defaults=None, workers=None, gpus=None, quiet=True,
                   confine="manifest", ray=None):
    """Render every job of ``manifest`` (a manifest file, a glob of model files, or a list
    of facet.batch.manifest.Job) into the folder ``out``; returns the counts (done,
    failed, skipped, views, seconds). ``confine``: where jobs may read files. By default
    ("manifest") a manifest file's own folder, and for a model it lists elsewhere that
    model's folder (the manifest named it; what the model refers to must lie beside or
    under it), so a manifest or model from elsewhere cannot pull in the rest of the
    machine; a folder: that folder alone, for every job; None: no confinement. ``ray``:
    run on Ray (facet.batch.ray_runner): True for a local cluster, or a cluster's address."""
    from pathlib import Path

    from .manifest import load_manifest
    from .pool import render_dataset as run

    if workers is not None and workers < 1:
        from ..errors import InputError

        raise InputError(f"--workers must be at least 1, got {workers}")
    jobs = manifest if isinstance(manifest, list) else load_manifest(manifest, defaults)
    if confine == "manifest":
        path = Path(str(manifest)) if not isinstance(manifest, list) else None
        confine = ((path.resolve().parent, True) if path is not None and path.is_file()
                   else None)
    elif confine is not None:
        confine = (Path(confine).resolve(), False)
    if ray:
        from .ray_runner import render_dataset_ray

        return render_dataset_ray(jobs, out, address=None if ray is True else str(ray),
                                  gpus=len(gpus or []), actors=workers, quiet=quiet,
                                  confine=confine)
    return run(jobs, out, workers=workers, gpus=gpus, quiet=quiet, confine=confine)
