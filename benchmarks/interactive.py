"""Interaction benchmark: the viewer through the notebook widget (JupyterLab + jupyter_rfb)
and through the served page (`facet view --serve`), each in headless Chromium at 800x600 on
the bunny, next to the same viewer in a glfw window under Xvfb.

Latency: a real (trusted) mouse move, dispatched through Chromium's DevTools input, to the
page showing the new picture (the page's own clock: performance.now() at the move, and when
the picture element changed), one move at a time, median. Frames per second: moves sent as
fast as they go for a few seconds, pictures shown per second. The window: a scripted orbit's
frame time (draw + swap, no vsync), which is its latency and 1/fps. Asserts nothing; parts
whose tools are missing are skipped with the reason.

    python benchmarks/interactive.py
"""

from __future__ import annotations

import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "tests"))
BUNNY = HERE.parents[1] / "shared" / "models" / "stanford-bunny.obj"
W, H = 800, 600
MOVES, SECONDS = 20, 4.0

# Page-side instruments: when a trusted move arrived, and when the picture element changed.
PROBE = """
const target = arguments[0], attr = arguments[1];
window.__lat = []; window.__t0 = null; window.__frames = 0;
window.addEventListener('pointermove', (e) => {
  if (e.isTrusted && window.__t0 === null) window.__t0 = performance.now() }, true);
new MutationObserver(() => {
  window.__frames += 1;
  if (window.__t0 !== null) {
    window.__lat.push(performance.now() - window.__t0); window.__t0 = null }
}).observe(target, {attributes: true, attributeFilter: [attr]});
"""


def _mouse(driver, kind: str, x: float, y: float) -> None:
    driver.execute_cdp_cmd("Input.dispatchMouseEvent", {
        "type": kind, "x": x, "y": y, "button": "left", "buttons": 1, "clickCount": 1})


def drive(driver, element, attr: str) -> tuple[float, float]:
    """(median latency in ms, pictures per second) of drags on ``element``."""
    from browser import wait_for

    driver.execute_script(PROBE, element, attr)
    r = driver.execute_script("const r = arguments[0].getBoundingClientRect();"
                              "return [r.left, r.top, r.width, r.height];", element)
    x, y = r[0] + r[2] / 2, r[1] + r[3] / 2
    _mouse(driver, "mouseMoved", x, y)
    _mouse(driver, "mousePressed", x, y)
    driver.execute_script("window.__t0 = null; window.__lat = []")  # hovering draws nothing
    for i in range(MOVES):  # one move, then wait for its picture
        _mouse(driver, "mouseMoved", x + 6 * (i + 1), y + 1)
        wait_for(lambda: driver.execute_script("return window.__t0 === null"),
                 f"the picture of move {i + 1}")
    latency = statistics.median(driver.execute_script("return window.__lat"))
    start = driver.execute_script("return window.__frames")
    t, i = time.monotonic(), 0
    while time.monotonic() - t < SECONDS:  # moves as fast as they go
        i += 1
        _mouse(driver, "mouseMoved", x + 150 * ((i % 40) / 40 - 0.5), y + 1)
    fps = (driver.execute_script("return window.__frames") - start) / (time.monotonic() - t)
    _mouse(driver, "mouseReleased", x, y)
    return latency, fps


def served(driver) -> tuple[float, float]:
    from browser import wait_for

    proc = subprocess.Popen([sys.executable, "-m", "facet", "view", str(BUNNY), "--serve",
                             "127.0.0.1:0"], stdout=subprocess.PIPE, text=True)
    try:
        url = re.search(r"http://\S+", proc.stdout.readline()).group(0)
        driver.get(url)
        driver.execute_script(f"document.getElementById('view').style.cssText = "
                              f"'position:absolute;left:0;top:0;width:{W}px;height:{H}px'")
        canvas = driver.find_element("id", "canvas")
        wait_for(lambda: canvas.get_attribute("width") == str(W)
                 and canvas.get_attribute("data-lossless") == "1", "the first picture")
        return drive(driver, canvas, "data-frame")
    finally:
        proc.terminate()
        proc.wait(20)


def widget(driver) -> tuple[float, float]:
    from browser import wait_for
    from jupyter_lab import JupyterLab, notebook

    root = Path(tempfile.mkdtemp(prefix="facet-bench-lab-"))
    notebook(root / "bench.ipynb", [f"import facet\nw = facet.show({str(BUNNY)!r}, "
                                    f"size=({W}, {H}))\nw"])
    lab = JupyterLab(root)
    try:
        driver.get(lab.url("bench.ipynb"))
        wait_for(lambda: "| Idle" in driver.find_element("css selector", "body").text,
                 "the kernel")
        run = "[data-command='notebook:run-cell-and-select-next']"
        wait_for(lambda: driver.find_elements("css selector", run), "the notebook")
        driver.find_element("css selector", ".jp-Cell .jp-InputPrompt").click()
        driver.find_element("css selector", run).click()
        img = wait_for(lambda: driver.find_elements("css selector", "img.renderview-view"),
                       "the widget")[0]
        wait_for(lambda: driver.execute_script("return arguments[0].naturalWidth", img) > 0,
                 "the first picture")
        time.sleep(1.0)  # let the first pictures (JPEG, then PNG) arrive before measuring
        return drive(driver, img, "src")
    finally:
        lab.stop()
        shutil.rmtree(root, ignore_errors=True)


def window() -> tuple[float, float] | None:
    """The glfw window's frame time on the same orbit, under a private Xvfb."""
    if shutil.which("Xvfb") is None:
        return None
    number = 90 + os.getpid() % 9
    xvfb = subprocess.Popen(["Xvfb", f":{number}", "-screen", "0", "1280x1024x24"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        from browser import wait_for

        wait_for(lambda: Path(f"/tmp/.X11-unix/X{number}").exists(), "Xvfb", 10)
        out = subprocess.run([sys.executable, __file__, "--window"], capture_output=True,
                             text=True, env={**os.environ, "DISPLAY": f":{number}"}, check=True)
        ms = float(out.stdout.split()[-1])
        return ms, 1000.0 / ms
    finally:
        xvfb.terminate()
        xvfb.wait()


def window_inside() -> None:
    from facet.window.viewer import Viewer

    with Viewer(str(BUNNY), (W, H)) as v:
        v.glfw.swap_interval(0)
        v.draw()
        times = []
        for _ in range(MOVES):
            v.move(*v._cursor)  # the same drag as the pages': 6 px to the right a move
            v.press(W / 2, H / 2, pan=False)
            v.move(W / 2 + 6, H / 2 + 1)
            v.release()
            t = time.perf_counter()
            v.draw()
            v.ctx.finish()
            times.append(time.perf_counter() - t)
    print(statistics.median(times) * 1e3)


def main() -> None:
    if not BUNNY.is_file():
        print("\nInteraction: skipped (../shared/models/stanford-bunny.obj not found)")
        return
    from browser import CHROMIUM, DRIVER

    rows = {}
    if any(os.path.exists(p) for p in CHROMIUM) and os.path.exists(DRIVER):
        import pytest

        from browser import chromium, quit_chromium

        for name, run in (("served page (facet view --serve)", served),
                          ("notebook widget (JupyterLab)", widget)):
            try:
                driver = chromium()
            except pytest.skip.Exception as exc:
                print(f"\nInteraction: {name} skipped ({exc})")
                continue
            try:
                rows[name] = run(driver)
            except Exception as exc:  # a missing extra: say so, measure the rest
                print(f"\nInteraction: {name} skipped ({type(exc).__name__}: {exc})")
            finally:
                quit_chromium(driver)
    else:
        print("\nInteraction: browser rows skipped (chromium / chromedriver not installed)")
    glfw_row = window()
    if glfw_row is not None:
        rows["glfw window (Xvfb, draw + swap)"] = glfw_row
    print(f"\nInteraction: bunny (69k faces), {W}x{H}, 4x MSAA, drag of {MOVES} moves "
          "(median latency), then moves as fast as they go for "
          f"{SECONDS:.0f} s (pictures per second)")
    print(f"{'':>36} | {'latency ms':>10} {'fps':>6}")
    for name, (latency, fps) in rows.items():
        print(f"{name:>36} | {latency:10.1f} {fps:6.1f}")


if __name__ == "__main__":
    window_inside() if "--window" in sys.argv else main()
