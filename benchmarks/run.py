"""facet's benchmarks: frame time and cold start, side by side with the bare moderngl floor.

    python benchmarks/run.py [--quick] [--frames N]

Prints tables; asserts nothing. Frame time is render + colour readback at 1024x1024 on
icospheres of ~20k, ~330k and ~1.3M faces, with and without 4x MSAA (facet with one
directional light and ``outputs=("color",)``, like the floor; also facet with every output).
Cold start is a whole process (start, imports, context, load, first frame, PNG written),
for `facet render` and `benchmarks/floor.py`, with its peak resident memory.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import facet  # noqa: E402
from facet.render.renderer import Renderer  # noqa: E402

from floor import Floor  # noqa: E402

SIZE = 1024
SUBDIVISIONS = {5: "20k", 7: "330k", 8: "1.3M"}
SHARED = HERE.parents[1] / "shared" / "models"


def icosphere(subdivisions: int):
    ico = trimesh.creation.icosphere(subdivisions=subdivisions)
    return np.asarray(ico.vertices, "f4"), np.asarray(ico.faces, "u4")


@dataclass
class Timing:
    """Seconds per call of one contender: the median and best of all its calls, and the
    median of each round's block (``rounds``, for ratios: ``ratio``)."""

    median: float
    best: float
    rounds: list[float]


def ratio(a: Timing, b: Timing) -> float:
    """a's time over b's: the median of the ratios of their blocks round by round (each
    pair ran seconds apart, so drift in machine load cancels out of each ratio)."""
    return statistics.median(x / y for x, y in zip(a.rounds, b.rounds, strict=True))


def time_interleaved(fns, frames: int, block: int = 4) -> list[Timing]:
    """Timings of each function. The functions take turns in blocks of ``block`` calls, so
    that drift in machine load (2 shared cores) hits every contender alike; the first call
    of each block is not counted, so that no contender is timed in the wake of another's
    memory traffic (reading 8 MB back leaves the caches cold for whoever comes next)."""
    for fn in fns:
        fn()  # warm-up: first-use compilation, uploads
    samples = [[] for _ in fns]
    rounds = [[] for _ in fns]
    for _ in range(max(1, -(-frames // (block - 1)))):
        for fn, out, per_round in zip(fns, samples, rounds, strict=True):
            here = []
            for k in range(block):
                t = time.perf_counter()
                fn()
                if k:
                    here.append(time.perf_counter() - t)
            out += here
            per_round.append(statistics.median(here))
    return [Timing(statistics.median(s), min(s), r) for s, r in zip(samples, rounds, strict=True)]


def _compare(pos, faces, scene, msaa: int, frames: int) -> list[Timing]:
    """Timings per frame of: the floor with and without back-face culling,
    facet colour only, facet's default call with only its colour used, the floor making
    and reading the default outputs (colour, depth, ids), facet's default call with every
    output read."""
    floors = []
    for cull, exact in ((True, False), (False, False), (True, True)):
        floor = Floor(SIZE, SIZE, msaa, cull=cull, exact=exact)
        with floor.ctx:  # moderngl makes its objects in the context that is current
            floor.upload(pos, pos, faces)
        floors.append(floor)
    f = floors[0]
    camera = facet.Camera.look_at(f.eye, f.target, fov_y=40.0, near=f.near, far=f.far)

    def frame_of(floor):
        def frame():
            with floor.ctx:  # several contexts live in this process
                floor.frame()
        return frame

    with Renderer(SIZE, SIZE, msaa=msaa) as r:
        def every_output():
            frame = r.render(scene, camera)
            return frame.color, frame.depth, frame.object_ids

        r.render(scene, camera)
        scene.objects[0].mesh.closed  # noqa: B018 - known before timing (else found later)
        times = time_interleaved([frame_of(floors[0]), frame_of(floors[1]),
                                  lambda: r.render(scene, camera, outputs=("color",)),
                                  lambda: r.render(scene, camera).color,
                                  frame_of(floors[2]), every_output], frames)
    for floor in floors:
        floor.ctx.release()
    return times


def frame_table(frames: int, subdivisions) -> None:
    print(f"\nFrame time, {SIZE}x{SIZE}, a closed icosphere, render + colour readback (median "
          f"of {frames}; fps; ratios: the median of round-by-round ratios)")
    print("  default: facet's render(scene, camera) (colour, depth, ids), colour used; "
          "all read: depth and ids read too;\n  floor all: the bare floor making and "
          "reading colour, depth and ids (one pass, or two under MSAA)")
    print(f"{'faces':>8} {'AA':>5} | {'floor cull':>10} {'no cull':>8} | {'facet colour':>12} "
          f"{'/cull':>6} | {'default':>7} {'/colour':>7} | {'floor all':>9} {'/cull':>6} | "
          f"{'all read':>8} {'/colour':>7} {'/floor':>7}")
    for sub in subdivisions:
        pos, faces = icosphere(sub)
        mesh = facet.Mesh(pos, faces, pos)  # unit sphere: normals = positions
        scene = facet.Scene()
        scene.add(mesh)
        scene.add_light(facet.DirectionalLight((-0.5, -0.6, -0.6)))
        for msaa in (0, 4):
            cull, nocull, colour, default, floor_all, every = \
                _compare(pos, faces, scene, msaa, frames)
            print(f"{len(faces):>8} {('4x' if msaa else 'none'):>5} | "
                  f"{1 / cull.median:10.1f} {1 / nocull.median:8.1f} | "
                  f"{1 / colour.median:12.1f} {ratio(colour, cull):6.2f} | "
                  f"{1 / default.median:7.1f} {ratio(default, colour):7.2f} | "
                  f"{1 / floor_all.median:9.1f} {ratio(floor_all, cull):6.2f} | "
                  f"{1 / every.median:8.1f} {ratio(every, colour):7.2f} "
                  f"{ratio(every, floor_all):7.2f}")
    # An open mesh (one triangle of the sphere removed): facet draws both faces, so its
    # floor is the one without culling.
    sub = subdivisions[len(subdivisions) // 2]
    pos, faces = icosphere(sub)
    faces = faces[1:]
    scene = facet.Scene()
    scene.add(facet.Mesh(pos, faces, pos))
    scene.add_light(facet.DirectionalLight((-0.5, -0.6, -0.6)))
    assert not scene.objects[0].mesh.closed
    print("\nAn open mesh (the sphere with one triangle removed: not culled)")
    print(f"{'faces':>8} {'AA':>5} | {'floor no cull':>13} | {'facet colour':>12} "
          f"{'/no cull':>8}")
    for msaa in (0, 4):
        _, nocull, colour, *_ = _compare(pos, faces, scene, msaa, frames)
        print(f"{len(faces):>8} {('4x' if msaa else 'none'):>5} | {1 / nocull.median:13.1f} | "
              f"{1 / colour.median:12.1f} {ratio(colour, nocull):8.2f}")


def run_process(cmd) -> tuple[float, float]:
    """Wall time (s) and peak RSS (MiB) of one whole process (see benchmarks/measure.py)."""
    res = subprocess.run([sys.executable, str(HERE / "measure.py"), *map(str, cmd)],
                         capture_output=True, text=True)
    if res.returncode != 0:
        raise SystemExit(f"benchmark command failed: {' '.join(map(str, cmd))}\n{res.stderr}")
    wall, peak_kib = res.stdout.split()
    return float(wall), int(peak_kib) / 1024


def cold_table(runs: int, models) -> None:
    print(f"\nCold start: whole process to PNG written, {SIZE}x{SIZE}, no AA, one light "
          f"(median of {runs}; peak RSS)")
    print(f"{'model':>22} | {'floor s':>8} {'MiB':>6} | {'facet s':>8} {'MiB':>6} "
          f"{'ratio':>6} {'mem':>5}")
    facet_cmd = [sys.executable, "-m", "facet", "render", "--size", f"{SIZE}x{SIZE}",
                 "--msaa", "0", "--light", "dir:-0.5,-0.6,-0.6", "-q"]
    with tempfile.TemporaryDirectory() as tmp:
        for name, path in models:
            out = Path(tmp) / "out.png"
            floor = [run_process([sys.executable, str(HERE / "floor.py"), str(path), str(out),
                                  "--size", f"{SIZE}x{SIZE}"]) for _ in range(runs)]
            ours = [run_process([*facet_cmd, str(path), "-o", str(out)]) for _ in range(runs)]
            tf, mf = statistics.median(w for w, _ in floor), max(m for _, m in floor)
            to, mo = statistics.median(w for w, _ in ours), max(m for _, m in ours)
            print(f"{name:>22} | {tf:8.2f} {mf:6.0f} | {to:8.2f} {mo:6.0f} {to / tf:6.2f} "
                  f"{mo / mf:5.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small meshes and few repetitions")
    ap.add_argument("--frames", type=int, default=None)
    ap.add_argument("--blender", default=os.environ.get("FACET_BPY_PYTHON"),
                    help="a Python with bpy: Cycles beside the path-traced datasets")
    a = ap.parse_args()
    subs = [5] if a.quick else list(SUBDIVISIONS)
    frames = a.frames or (5 if a.quick else 21)
    import moderngl

    ctx = moderngl.create_context(standalone=True, backend="egl")
    print(f"GL: {ctx.info['GL_RENDERER']} / {ctx.info['GL_VERSION']}; "
          f"{os.cpu_count()} CPUs; numpy {np.__version__}")
    ctx.release()
    frame_table(frames, subs)
    with tempfile.TemporaryDirectory() as tmp:
        models = []
        if (SHARED / "stanford-bunny.obj").is_file():
            models.append(("stanford-bunny (69k)", SHARED / "stanford-bunny.obj"))
        else:
            print(f"(bunny not found in {SHARED}; cold start on icospheres only)")
        sub = 5 if a.quick else 8
        ply = Path(tmp) / f"icosphere{sub}.ply"
        trimesh.creation.icosphere(subdivisions=sub).export(ply)
        models.append((f"icosphere ({SUBDIVISIONS[sub]})", ply))
        cold_table(2 if a.quick else 5, models)
    import pathtrace
    import splats

    import antialias
    import batch
    import gltf
    import instancing
    import interactive
    import load
    import points
    import raytrace
    import shaderlab
    import shadows
    import transparency
    import turntable
    import viewer

    antialias.main()
    shadows.main()
    transparency.main()
    turntable.main()
    viewer.main()
    interactive.main()
    gltf.main()
    instancing.table(a.quick)
    load.table(a.quick)
    points.table(a.quick)
    splats.table(a.quick)
    shaderlab.main()
    raytrace.table(a.quick)
    raytrace.frame(a.quick)
    pathtrace.main(a.quick)
    batch.table(20 if a.quick else 200)
    batch.path_table(2 if a.quick else 10, a.blender)


if __name__ == "__main__":
    main()
