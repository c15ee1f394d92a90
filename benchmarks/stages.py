"""OpenUSD and URDF benchmark: a stage of 10,000 prims and 1M triangles, and a 50-link
robot at 1,000 joint configurations through ``facet batch``, beside Blender 4.5 importing
and rendering the same (Workbench) when a Python with ``bpy`` is named.

    python benchmarks/stages.py [--quick] [--blender PYTHON]

PYTHON (or FACET_BPY_PYTHON): a Python 3.11 with ``pip install bpy==4.5.*`` (Blender as a
module; it pins its own numpy, so it lives apart from facet's environment). Blender runs
benchmarks/blender_peer.py; its robot is the same link meshes (STL) posed by the matrices
facet's forward kinematics give (Blender reads no URDF), so its time leaves the kinematics
out. Prints tables; asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import facet  # noqa: E402
from stage_models import write_robot, write_stage  # noqa: E402

FACET = [sys.executable, "-m", "facet"]


def _wall(cmd: list, **kw) -> float:
    t = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True, **kw)
    return time.perf_counter() - t


def facet_stage(stage: Path, size: int, views: int, out: Path) -> dict:
    """Load, first frame (upload and draw) and an orbit's frames, in one process; and the
    default call, `facet render STAGE` from a cold process."""
    t = time.perf_counter()
    scene = facet.load(stage)
    load = time.perf_counter() - t
    bounds = scene.bounds
    centre, radius = bounds.mean(0), float(np.linalg.norm(bounds[1] - bounds[0]) / 2)
    with facet.Renderer(size, size) as r:
        t = time.perf_counter()
        frame = r.render(scene, _orbit(centre, radius, 0.3), outputs=("color",))
        first = time.perf_counter() - t
        frame.save(out / "facet_stage.png")
        times = []
        for k in range(1, views + 1):
            t = time.perf_counter()
            _ = r.render(scene, _orbit(centre, radius, 0.3 + 2 * np.pi * k / views),
                         outputs=("color",)).color  # (read back: the frame is done)
            times.append(time.perf_counter() - t)
    cli = _wall([*FACET, "render", str(stage), "--size", f"{size}x{size}", "-q",
                 "-o", str(out / "facet_cli.png")])
    return {"load": load, "first": first, "per_view": statistics.median(times), "cli": cli,
            "triangles": sum(len(o.mesh.faces) for o in scene.objects),
            "prims": len(scene.objects)}


def _orbit(centre, radius: float, angle: float):
    d = 2.6 * radius
    eye = centre + d * np.array([np.cos(angle), 0.5, np.sin(angle)])
    return facet.Camera.look_at(eye, centre, near=d * 0.05, far=d * 4)


def facet_robot(urdf: Path, size: int, views: int, out: Path) -> dict:
    """Load, and `facet batch` of one job of ``views`` random configurations (equal work:
    colour only; the default call: the dataset's default channels)."""
    t = time.perf_counter()
    scene = facet.load(urdf)
    load = time.perf_counter() - t
    rows = {}
    for label, outputs in (("colour", ["color"]), ("default", None)):
        job = {"model": str(urdf), "name": "robot", "size": [size, size],
               "views": {"plan": "sphere", "count": views, "random_joints": True}}
        if outputs:
            job["outputs"] = outputs
        manifest = out / f"robot_{label}.jsonl"
        manifest.write_text(json.dumps(job) + "\n")
        wall = _wall([*FACET, "batch", str(manifest), "-o", str(out / f"ds_{label}"), "-q",
                      "--workers", "1"])
        rows[label] = wall
    return {"load": load, "links": len(scene.objects), **rows}


def robot_poses(urdf: Path, views: int, out: Path) -> Path:
    """The link meshes and their placements at ``views`` random configurations (facet's
    forward kinematics), for Blender."""
    from facet.scene.articulated import random_configurations

    scene = facet.load(urdf)
    configs = random_configurations(scene, views, 2)
    poses = np.array([[o.transform for o in scene.posed(c).objects] for c in configs])
    files = [str(urdf.parent / "meshes" / f"link{i}.stl") for i in range(len(scene.objects))]
    path = out / "poses.npz"
    np.savez(path, files=np.array(files), poses=poses)
    return path


def blender(python: str | None, args: list) -> dict | None:
    if not python:
        return None
    cmd = [python, str(HERE / "blender_peer.py"), *map(str, args)]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        print(f"(blender failed: {done.stderr.strip().splitlines()[-1:]})")
        return None
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="1,000 prims, 100 poses")
    ap.add_argument("--blender", default=os.environ.get("FACET_BPY_PYTHON"),
                    help="a Python with bpy (Blender 4.5 as a module)")
    a = ap.parse_args()
    prims, poses = (1_000, 100) if a.quick else (10_000, 1_000)
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        stage = write_stage(root / "stage.usdc", prims)
        urdf = write_robot(root)
        st = facet_stage(stage, 512, 10, root)
        bl = blender(a.blender, ["stage", stage, 512, 3, root / "blender_stage"])
        print(f"\nStage: {st['prims']:,} Mesh prims, {st['triangles']:,} triangles, .usdc, "
              "512x512 colour")
        print("| | load s | first frame s | a frame s | frames/s | `facet render` cold s |")
        print("|---|---|---|---|---|---|")
        print(f"| facet | {st['load']:.2f} | {st['first']:.2f} | {st['per_view']:.4f} | "
              f"{1 / st['per_view']:.1f} | {st['cli']:.2f} |")
        if bl:
            print(f"| Blender {bl['version']} (import, Workbench) | {bl['load']:.2f} | "
                  f"{bl['first']:.2f} | {bl['per_view']:.3f} | {1 / bl['per_view']:.2f} | |")
        else:
            print("| Blender | not run (give --blender or FACET_BPY_PYTHON) | | | | |")
        rb = facet_robot(urdf, 256, poses, root)
        pose_file = robot_poses(urdf, 201, root)
        blr = blender(a.blender, ["robot", pose_file, 256, 200, root / "blender_robot"])
        print(f"\nRobot: {rb['links']} links (a mesh each, 1,280 triangles), {poses:,} random "
              "configurations, 256x256, one job, one worker")
        print("| | load s | views | wall s (whole run) | views/s |")
        print("|---|---|---|---|---|")
        print(f"| facet batch, colour | {rb['load']:.2f} | {poses} | {rb['colour']:.1f} | "
              f"{poses / rb['colour']:.1f} |")
        print(f"| facet batch, default channels | | {poses} | {rb['default']:.1f} | "
              f"{poses / rb['default']:.1f} |")
        if blr:
            print(f"| Blender {blr['version']} (STL import, Workbench, poses given) | "
                  f"{blr['load']:.2f} | 200 | | {1 / blr['per_view']:.1f} |")
        else:
            print("| Blender | not run (give --blender or FACET_BPY_PYTHON) | | | |")


if __name__ == "__main__":
    main()
