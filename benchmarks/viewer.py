"""Viewer benchmark: frame time of `facet view` on the bunny at 1280x720 during a scripted
orbit under Xvfb, next to the headless frame time (render + colour readback) of the same
frames. Starts its own Xvfb; skipped without it.

    python benchmarks/viewer.py
"""

from __future__ import annotations

import os
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parents[1] / "shared" / "models"
SIZE, FRAMES = (1280, 720), 40


def measure() -> None:
    """Runs inside the Xvfb display (see main)."""
    import facet
    from facet.render.renderer import Renderer
    from facet.window.viewer import Viewer

    scene = facet.Scene()
    scene.add(facet.Mesh.load(SHARED / "stanford-bunny.obj"))
    with Viewer(scene, SIZE, msaa=4) as v:
        v.glfw.swap_interval(0)  # no vsync: measure the work, not the display rate
        v.draw()
        window, cameras = [], []
        for _ in range(FRAMES):
            v.control.orbit((640, 360), (652, 362), *SIZE)  # a steady drag to the right
            cameras.append(v.camera())
            t = time.perf_counter()
            v.draw()
            v.ctx.finish()
            window.append(time.perf_counter() - t)
        fb = v.glfw.get_framebuffer_size(v.window)
    headless = []
    with Renderer(*fb, msaa=4) as r:  # the same frames, same lights, offscreen
        r.render(scene, cameras[0], outputs=("color",))
        for cam in cameras:  # the default lights follow the camera in both
            t = time.perf_counter()
            r.render(scene, cam, outputs=("color",))
            headless.append(time.perf_counter() - t)
    tw, th = statistics.median(window), statistics.median(headless)
    print(f"\nViewer: bunny (69k faces), {fb[0]}x{fb[1]}, 4x MSAA, scripted orbit of {FRAMES} "
          "frames under Xvfb (median)")
    print(f"{'':>34} | {'ms':>6} {'fps':>6}")
    print(f"{'headless (render + readback)':>34} | {th * 1e3:6.1f} {1 / th:6.1f}")
    print(f"{'window (draw + swap to Xvfb)':>34} | {tw * 1e3:6.1f} {1 / tw:6.1f}   "
          f"ratio {tw / th:.2f}")


def main() -> None:
    if not (SHARED / "stanford-bunny.obj").is_file():
        print("\nViewer: skipped (bunny not found)")
        return
    if shutil.which("Xvfb") is None:
        print("\nViewer: skipped (Xvfb not installed: apt-get install xvfb)")
        return
    number = 80 + os.getpid() % 9
    xvfb = subprocess.Popen(["Xvfb", f":{number}", "-screen", "0", "1600x1000x24"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):
            if Path(f"/tmp/.X11-unix/X{number}").exists():
                break
            time.sleep(0.05)
        env = {**os.environ, "DISPLAY": f":{number}"}
        subprocess.run([sys.executable, __file__, "--inside"], env=env, check=True)
    finally:
        xvfb.terminate()
        xvfb.wait()


if __name__ == "__main__":
    measure() if "--inside" in sys.argv else main()
