"""Supersampling benchmark: colour frame time with ssaa at 4, 16 and 64 samples next to one
sample, on the bundled torus knot at 512x512. The cost should grow about linearly in N (one
scene draw and one full-screen accumulation per sample, one readback).

Then the measured error of each pattern (notes §2.8-2.10): mean absolute difference from a
256-sample grid reference on the thin slanted bars of tests/test_antialias.py (the test
asserts the orderings; this prints the numbers).

    python benchmarks/antialias.py
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SIZE = 512


def pattern_errors() -> None:
    sys.path.insert(0, str(ROOT / "tests"))
    from facet.geometry.sampling import PATTERNS
    from facet.render.renderer import Renderer
    from test_antialias import CAMERA, S, bars

    scene = bars()
    with Renderer(S, S, float_color=True) as r:
        def img(aa):
            return r.render(scene, CAMERA, shading="unlit", aa=aa,
                            outputs=("color",)).color[..., 0]

        ref = img("ssaa:grid:256")
        centre = np.abs(img("none") - ref).mean()
        errors = {(name, n): np.abs(img(f"ssaa:{name}:{n}") - ref).mean()
                  for name in PATTERNS for n in (4, 16, 64)}
    print(f"\nAnti-aliasing error: thin slanted bars, {S}x{S}, mean |pattern - 256-sample "
          f"grid| in units of full white (one centre sample: {centre:.4f})")
    print(f"{'pattern':>10} | {'N=4':>7} {'N=16':>7} {'N=64':>7}")
    for name in PATTERNS:
        print(f"{name:>10} | " + " ".join(f"{errors[name, n]:7.4f}" for n in (4, 16, 64)))


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
    pattern_errors()


if __name__ == "__main__":
    main()
