"""Shadow benchmark: frame time of the bundled example scene at 800x600 (4x MSAA) with
shadows from 1, 4 and 8 lights, next to the same lights without shadows. The maps are drawn
once per frame (one tile per directional/spot light, six per point light).

    python benchmarks/shadows.py
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    import facet
    from facet.render.renderer import Renderer
    from facet.scene import DirectionalLight, PointLight, SpotLight

    base = facet.load_scene(ROOT / "models" / "example.toml")
    camera = base.camera("main")
    print("\nShadows: models/example.toml (6 objects), 800x600, 4x MSAA, colour (median of 5)")
    print(f"{'lights':>32} | {'no shadows ms':>13} {'shadows ms':>11} {'ratio':>6}")
    with Renderer(800, 600, msaa=4) as r:
        for count in (1, 4, 8):
            scene = base
            lights = []
            for i in range(count):
                a = 2 * np.pi * i / count
                kind = (DirectionalLight((np.cos(a), -1.5, np.sin(a)), intensity=0.6 / count ** 0.5)
                        if i % 3 == 0 else
                        SpotLight((3 * np.cos(a), 3, 3 * np.sin(a)),
                                  (-np.cos(a), -1, -np.sin(a)), intensity=0.5)
                        if i % 3 == 1 else
                        PointLight((2 * np.cos(a), 2.5, 2 * np.sin(a)), intensity=0.4))
                lights.append(kind)
            scene.lights = lights
            row = []
            for shadows in (False, True):
                r.render(scene, camera, outputs=("color",), shadows=shadows)  # warm-up
                times = []
                for _ in range(5):
                    t = time.perf_counter()
                    r.render(scene, camera, outputs=("color",), shadows=shadows)
                    times.append(time.perf_counter() - t)
                row.append(statistics.median(times))
            kinds = ", ".join(type(x).__name__.replace("Light", "") for x in lights[:3])
            label = f"{count} ({kinds}...)"
            print(f"{label:>32} | {row[0] * 1e3:13.1f} {row[1] * 1e3:11.1f} "
                  f"{row[1] / row[0]:6.2f}")


if __name__ == "__main__":
    main()
