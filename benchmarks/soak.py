"""Soak: many frames through one renderer, to show memory and speed stay flat.

    python benchmarks/soak.py [--frames N]      (default 100,000)

128x128 frames with colour, depth and ids read back, a camera that moves every frame and,
every 100 frames, a different scene (another mesh, material, light set and order). Prints
RSS and frames per second per tenth of the run; asserts nothing.
"""

from __future__ import annotations

import argparse
import random
import time

import numpy as np


def rss_mib() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096 / 2**20


def main() -> None:
    import facet
    from facet.render.renderer import Renderer
    from facet.scene import primitives

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=100_000)
    frames = ap.parse_args().frames
    rng = random.Random(1)
    meshes = [primitives.sphere(0.6), primitives.cube(0.9), primitives.torus(0.6, 0.2),
              primitives.cylinder(0.4, 1.0), primitives.cone(0.5, 1.0)]
    makers = [lambda: facet.DirectionalLight((-1, -1, -0.5), intensity=0.7),
              lambda: facet.PointLight((1, 2, 2), intensity=3.0),
              lambda: facet.SpotLight((0, 2, 2), (0, -1, -1), intensity=3.0)]

    def new_scene():
        scene = facet.Scene(ambient=rng.uniform(0.05, 0.2))
        for i in range(rng.randint(1, 3)):
            scene.add(rng.choice(meshes), facet.Material(color=[rng.random() for _ in "rgb"]),
                      facet.transforms.translate((i - 1.0, 0, 0)))
        for _ in range(rng.randint(1, 4)):
            scene.add_light(rng.choice(makers)())
        return scene

    tenth = max(frames // 10, 1)
    print(f"\nSoak: {frames:,} frames of 128x128 (colour, depth, ids read back), camera moving, "
          "a new scene every 100 frames")
    print(f"{'frames':>10} | {'RSS MiB':>8} | {'fps':>7}")
    with Renderer(128, 128, msaa=0) as r:
        scene = new_scene()
        start_rss, t = None, time.perf_counter()
        for i in range(frames):
            if i % 100 == 0:
                scene = new_scene()
            a = 2 * np.pi * i / 500
            camera = facet.Camera.look_at((4 * np.cos(a), 1.5, 4 * np.sin(a)), (0, 0, 0),
                                          near=0.5, far=20)
            frame = r.render(scene, camera, outputs=("color", "depth", "ids"))
            frame.settle()
            if i == tenth - 1:
                start_rss = rss_mib()  # after a tenth: programs compiled, pools filled
            if (i + 1) % tenth == 0:
                now = time.perf_counter()
                print(f"{i + 1:>10,} | {rss_mib():8.1f} | {tenth / (now - t):7.0f}")
                t = now
        print(f"RSS growth after the first tenth: {rss_mib() - start_rss:+.1f} MiB")


if __name__ == "__main__":
    main()
