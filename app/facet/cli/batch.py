"""``facet batch``: render a dataset from a manifest (facet.batch)."""

from __future__ import annotations

import argparse
import re

from . import args as A

EPILOG = """\
MANIFEST is a .toml, .jsonl or .json manifest, or a glob of model files in quotes:
  facet batch dataset.toml -o dataset/
  facet batch "models/*.obj" -o thumbs/ --views 1 --size 512x512 --outputs color
  facet batch dataset.toml -o dataset/ --workers 4 --gpus 0,1,2,3
  facet batch "scans/*.ply" -o splats/ --views sphere:64 --colmap --float-files npy,exr
A rerun skips finished jobs; a bad model fails its own job (see DATASET/index.jsonl) and
the run goes on; the exit status is 1 when any job failed. Without --confine a job reads
files inside the manifest's folder, or inside its model's folder when the manifest lists
a model elsewhere. --views, --size, --outputs, --seed, --float-files and --colmap replace
the manifest's [defaults]; a job's own values win over both.
"""


def add_parser(sub) -> None:
    b = sub.add_parser("batch", help="render a dataset of many models (a manifest)",
                       description="Render every job of MANIFEST into DATASET: per job a "
                       "folder of views (images/, depth/, normals/, masks/ ...) and a "
                       "nerfstudio transforms.json, and DATASET/index.jsonl.", epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    b.add_argument("manifest", help="a .toml / .jsonl / .json manifest, or a glob of model "
                   "files")
    b.add_argument("-o", "--output", type=A.output_path, required=True, metavar="DATASET",
                   help="the dataset folder (made if missing)")
    b.add_argument("--views", metavar="N|PLAN:N",
                   help="default view plan: N (N views on a sphere), or turntable:N, "
                   "sphere:N, band:N, random:N")
    b.add_argument("--size", metavar="WxH", help="default image size (256x256)")
    b.add_argument("--outputs", metavar="LIST",
                   help="default channels: color,depth,normals (also ids, position, uv)")
    b.add_argument("--seed", type=int, help="default seed of random view plans")
    b.add_argument("--float-files", metavar="npy|exr|npy,exr",
                   help="file formats of the float channels (default npy; exr needs "
                   "pip install 'facet-render[exr]')")
    b.add_argument("--colmap", action="store_true",
                   help="also write each job's cameras as a COLMAP text model (sparse/0/)")
    b.add_argument("--workers", type=int, metavar="N",
                   help="worker processes (default: 1 on a CPU rasteriser, which uses "
                   "every core already; one per GPU with --gpus)")
    b.add_argument("--gpus", metavar="0,1,...", help="EGL device indices, one per worker")
    b.add_argument("--ray", nargs="?", const=True, metavar="ADDRESS",
                   help="run on a Ray cluster (its ADDRESS, or without one a local cluster; "
                   "pip install 'facet-render[ray]'); the output folder must be one every "
                   "node sees")
    b.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    A.add_confine_option(b)


def run(args) -> int:
    import sys
    from pathlib import Path

    from ..batch import render_dataset
    from ..errors import InputError

    defaults = {}
    if args.views:
        plan, _, count = args.views.rpartition(":")
        if not re.fullmatch(r"[0-9]+", count):
            raise InputError(f"--views {args.views!r}: expected N or PLAN:N, like sphere:8")
        defaults["views"] = {"plan": plan or "sphere", "count": int(count)}
    if args.size:
        defaults["size"] = args.size
    if args.outputs:
        defaults["outputs"] = args.outputs
    if args.seed is not None:
        defaults["seed"] = args.seed
    if args.float_files:
        defaults["float_files"] = args.float_files.split(",")
    if args.colmap:
        defaults["colmap"] = True
    gpus = None
    if args.gpus:
        try:
            gpus = [int(g) for g in args.gpus.split(",")]
        except ValueError:
            raise InputError(f"--gpus {args.gpus!r}: expected device numbers like 0,1") \
                from None
        if any(g < 0 for g in gpus):
            raise InputError(f"--gpus {args.gpus!r}: device numbers are >= 0")
    if args.workers is not None and args.workers < 1:  # (the flag's name, not the API's)
        raise InputError(f"--workers must be at least 1, got {args.workers}")
    counts = render_dataset(args.manifest, args.output, defaults=defaults,
                            workers=args.workers, gpus=gpus, quiet=args.quiet,
                            confine=args.confine or "manifest", ray=args.ray)
    print(f"facet batch: {counts['done']} done, {counts['failed']} failed, "
          f"{counts['skipped']} skipped; {counts['views']} views in {counts['seconds']:.1f} s "
          f"(index: {Path(args.output) / 'index.jsonl'})", file=sys.stderr)
    return 1 if counts["failed"] else 0
