"""Transparency benchmark: the OIT test scene (overlapping transparent quads) scaled up to
many layers at 1024x1024, next to the same quads drawn opaque.

    python benchmarks/transparency.py
"""

from __future__ import annotations

import statistics
import time

import numpy as np


def main() -> None:
    from facet.geometry.camera import Camera
    from facet.render.renderer import Renderer
    from facet.scene import Material, Mesh, Scene

    camera = Camera.look_at((0, 0, 5), (0, 0, 0), ortho_height=4.0, near=1, far=9)
    rng = np.random.default_rng(0)
    print("\nTransparency: 1024x1024, no MSAA, overlapping quads, colour (median of 7)")
    print(f"{'layers':>8} | {'opaque ms':>10} {'OIT ms':>8} {'ratio':>6}")
    with Renderer(1024, 1024, msaa=0) as r:  # one sample: the OIT passes alone
        for layers in (2, 8, 32):
            times = {}
            for opacity in (1.0, 0.4):
                scene = Scene(ambient=0.0)
                for i in range(layers):
                    x, y = rng.uniform(-1, 1, 2)
                    z = 1.0 - 2.0 * i / layers
                    pos = [[x - 1, y - 1, z], [x + 1, y - 1, z], [x + 1, y + 1, z],
                           [x - 1, y + 1, z]]
                    scene.add(Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4),
                              Material(color=rng.uniform(0, 1, 3), opacity=opacity))
                r.render(scene, camera, shading="unlit", outputs=("color",))
                samples = []
                for _ in range(7):
                    t = time.perf_counter()
                    r.render(scene, camera, shading="unlit", outputs=("color",))
                    samples.append(time.perf_counter() - t)
                times[opacity] = statistics.median(samples)
            print(f"{layers:>8} | {times[1.0] * 1e3:10.1f} {times[0.4] * 1e3:8.1f} "
                  f"{times[0.4] / times[1.0]:6.2f}")


if __name__ == "__main__":
    main()
