"""Turntable benchmark: a 36-frame orbit of the bunny at 512x512 with colour, depth and ids
written to disk (the `facet render --turntable --out-dir` path), next to rendering alone.

    python benchmarks/turntable.py
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parents[1] / "shared" / "models"
FRAMES, SIZE = 36, 512
ROUNDS = 3  # best of


def main() -> None:
    import facet
    from facet.cli.sequence import render_turntable
    from facet.image.outputs import ColorOptions
    from facet.render.renderer import Renderer
    from facet.render.turntable import orbit_cameras

    path = SHARED / "stanford-bunny.obj"
    if not path.is_file():
        print(f"\nTurntable: skipped ({path} not found)")
        return
    scene = facet.Scene()
    scene.add(facet.Mesh.load(path))
    camera = facet.Camera.frame(scene.bounds)
    outputs = ("color", "depth", "ids")
    with Renderer(SIZE, SIZE, msaa=4) as r:
        cams = orbit_cameras(camera, scene.bounds.mean(axis=0), FRAMES)
        opts = r.options(scene, outputs=outputs)  # the default lights follow the camera
        r.render(scene, camera, opts)  # warm-up: programs, uploads
        render_only, with_files = [], []
        for _ in range(ROUNDS):  # alternate, so drift in machine load hits both alike
            t = time.perf_counter()
            for cam in cams:
                r.render(scene, cam, opts)
            render_only.append(time.perf_counter() - t)
            with tempfile.TemporaryDirectory() as tmp:
                args = argparse.Namespace(turntable=FRAMES, up=(0.0, 1.0, 0.0), fps=30.0,
                                          out_dir=tmp, quiet=True, png16=False,
                                          normals_space="world")
                t = time.perf_counter()
                written = render_turntable(r, scene, camera, opts, args, None,
                                           ColorOptions())
                with_files.append(time.perf_counter() - t)
                size_mb = sum(p.stat().st_size for p in written) / 2**20
        render_only, with_files = min(render_only), min(with_files)
    print(f"\nTurntable: bunny (69k faces), {FRAMES} frames, {SIZE}x{SIZE}, 4x MSAA, "
          f"colour + depth + ids (best of {ROUNDS}, alternating)")
    print(f"{'':>28} | {'s':>6} {'fps':>6}")
    print(f"{'render only':>28} | {render_only:6.2f} {FRAMES / render_only:6.1f}")
    print(f"{'render + files written':>28} | {with_files:6.2f} {FRAMES / with_files:6.1f}"
          f"   ({len(written)} files, {size_mb:.1f} MiB; ratio "
          f"{render_only / with_files:.2f} of render-only fps)")


if __name__ == "__main__":
    sys.exit(main())
