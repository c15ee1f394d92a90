"""Supersampling benchmark: colour frame time with ssaa at 4, 16 and 64 samples next to one
sample, on the bundled torus knot at 512x512. The cost should grow about linearly in N (one
scene draw and one full-screen accumulation per sample, one readback).

    python benchmarks/antialias.py
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SIZE = 512


def main() -> None:
    import facet
    from facet.render.renderer import Renderer
    from facet.scene.light import camera_rig

    scene = facet.Scene()
    scene.add(facet.Mesh.load(ROOT / "models" / "default.obj"))
    camera = facet.Camera.frame(scene.bounds)
    for light in camera_rig(camera.view):
        scene.add_light(light)
    rows = []
    with Renderer(SIZE, SIZE) as r:
        for aa, n in (("none", 1), ("ssaa:jittered:4", 4), ("ssaa:jittered:16", 16),
                      ("ssaa:jittered:64", 64)):
            r.render(scene, camera, aa=aa, outputs=("color",))  # warm-up
            times = []
            for _ in range(5 if n < 64 else 3):
                t = time.perf_counter()
                r.render(scene, camera, aa=aa, outputs=("color",))
                times.append(time.perf_counter() - t)
            rows.append((aa, n, statistics.median(times)))
    base = rows[0][2]
    print(f"\nSupersampling: torus knot (9.6k faces), {SIZE}x{SIZE}, colour (median)")
    print(f"{'aa':>18} | {'ms':>7} {'x one sample':>13} {'per sample':>11}")
    for aa, n, t in rows:
        print(f"{aa:>18} | {t * 1e3:7.1f} {t / base:13.1f} {t / base / n:11.2f}")


if __name__ == "__main__":
    main()
