"""Viewer benchmark: frame time of `facet view` on the bunny at 1280x720 during a scripted
orbit under Xvfb, next to the headless frame time (render + colour readback) of the same
frames; and the window's frame time orbiting a 10M-point cloud next to a bare moderngl
GL_POINTS floor drawing the same points at the same size. Starts its own Xvfb; skipped
without it.

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
    cloud_orbit(int(os.environ.get("FACET_BENCH_POINTS", 10_000_000)))


def cloud_orbit(n: int, frames: int = 4) -> None:
    """The window orbiting an N-point cloud (default sizes: 3-pixel discs, eye-dome
    lighting, 4x MSAA), next to the GL_POINTS floor at the window's size."""
    import facet
    from facet.window.viewer import Viewer

    sys.path.insert(0, str(HERE))
    from points import PointsFloor, cloud

    positions, colors = cloud(n)
    scene = facet.Scene()
    scene.add(facet.Points(positions, colors))
    with Viewer(scene, SIZE, msaa=4) as v:
        v.glfw.swap_interval(0)
        v.draw()
        times = []
        for _ in range(frames):
            v.control.orbit((640, 360), (660, 362), *SIZE)
            t = time.perf_counter()
            v.draw()
            v.ctx.finish()
            times.append(time.perf_counter() - t)
        fb = v.glfw.get_framebuffer_size(v.window)
    floor = PointsFloor(positions, colors, fb)
    floor.frame()
    floor_times = []
    for _ in range(frames):
        t = time.perf_counter()
        floor.frame()
        floor_times.append(time.perf_counter() - t)
    floor.ctx.release()
    tw, tf = statistics.median(times), statistics.median(floor_times)
    print(f"\nViewer: {n:,}-point cloud, {fb[0]}x{fb[1]}, orbit of {frames} frames (median)")
    print(f"{'GL_POINTS floor (draw + readback)':>34} | {tf * 1e3:8.1f} ms")
    print(f"{'window (discs, EDL, 4x MSAA)':>34} | {tw * 1e3:8.1f} ms   ratio {tw / tf:.2f}")


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
