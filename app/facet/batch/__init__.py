"""Batch rendering of datasets: manifests of many models (facet.batch.manifest), view
plans (facet.batch.views), worker processes each holding one renderer
(facet.batch.runner), and the files the learning and reconstruction tools read
(facet.batch.layout). ``facet batch`` is its command line."""

from __future__ import annotations


def render_dataset(manifest, out, *, defaults=None, workers=None, gpus=None, quiet=True,
                   confine="manifest", ray=None):
    """Render every job of ``manifest`` (a manifest file, a glob of model files, or a list
    of facet.batch.manifest.Job) into the folder ``out``; returns the counts (done,
    failed, skipped, views, seconds). ``confine``: the folder outside which no file is
    read; by default a manifest file's own folder (a manifest names files, and one from
    elsewhere should not reach the rest of the machine), None for no confinement. ``ray``:
    run on Ray (facet.batch.ray_runner): True for a local cluster, or a cluster's address."""
    from pathlib import Path

    from .manifest import load_manifest
    from .runner import render_dataset as run

    jobs = manifest if isinstance(manifest, list) else load_manifest(manifest, defaults)
    if confine == "manifest":
        path = Path(str(manifest)) if not isinstance(manifest, list) else None
        confine = path.resolve().parent if path is not None and path.is_file() else None
    if ray:
        from .ray_runner import render_dataset_ray

        return render_dataset_ray(jobs, out, address=None if ray is True else str(ray),
                                  gpus=len(gpus or []), actors=workers, quiet=quiet,
                                  confine=confine)
    return run(jobs, out, workers=workers, gpus=gpus, quiet=quiet, confine=confine)
