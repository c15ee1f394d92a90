"""``facet view --serve``: the viewer served to a web page over a WebSocket. The protocol
from a Python client (token, pictures JPEG while moving then PNG when still, refinement,
the camera of each picture), the command's errors, and end to end in headless Chromium:
drag on the page and find the picture changed and equal to the headless render of the new
camera (golden tolerance, edges masked as in tests/test_notebook_widget.py), keys, and two
tabs seeing one session. Servers bind 127.0.0.1 and are stopped by the tests."""

import asyncio
import io
import json
import re
import signal
import subprocess
import sys
import urllib.error
import urllib.request

import numpy as np
import pytest
from PIL import Image

from browser import camera_from, canvas_pixels, chromium, quit_chromium, wait_for
from conftest import ROOT
from test_golden import MAX_DIFFERING
from test_notebook_widget import same_picture

pytest.importorskip("websockets", reason="the serve extra (websockets) is not installed")

FACET = [sys.executable, "-m", "facet"]
MODEL = str(ROOT / "models" / "default.obj")


class Served:
    """``facet view --serve 127.0.0.1:0`` in a subprocess, stopped on exit."""

    def __init__(self, *args, model: str = MODEL, cwd=None):
        self.proc = subprocess.Popen([*FACET, "view", model, "--serve", "127.0.0.1:0", *args],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                     cwd=cwd)
        line = self.proc.stdout.readline()
        found = re.search(r"http://\S+", line)
        if not found:
            self.stop()
            raise AssertionError(f"no URL printed: {line!r} {self.proc.stderr.read()!r}")
        self.url = found.group(0)
        self.hint = self.proc.stdout.readline()
        self.ws = self.url.replace("http://", "ws://").replace("/?", "/ws?")

    def stop(self) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            return self.proc.wait(20)
        finally:
            if self.proc.poll() is None:
                self.proc.kill()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()


@pytest.fixture(scope="module")
def served():
    with Served() as s:
        yield s


def _status(url: str) -> int:
    try:
        with urllib.request.urlopen(url, timeout=20) as r:
            return r.status
    except urllib.error.HTTPError as exc:
        return exc.code


def test_the_page_needs_the_token_and_says_how_to_reach_it(served):
    assert served.url.startswith("http://127.0.0.1:") and "?token=" in served.url
    port = served.url.split(":")[2].split("/")[0]
    assert f"ssh -L {port}:127.0.0.1:{port}" in served.hint
    base = served.url.split("?")[0]
    assert _status(served.url) == 200
    assert _status(base) == 403 and _status(base + "?token=wrong") == 403
    assert _status(served.ws.replace("ws://", "http://").split("?")[0] + "?token=x") == 403
    assert _status(base + "nothing-here") == 404


async def _pictures(url, events, count, timeout=60, until_lossless=False):
    """Send ``events``, then collect ``count`` (meta, picture) pairs (at least, and up to
    a lossless one after them, when ``until_lossless``)."""
    from PIL import Image
    from websockets.asyncio.client import connect

    out = []
    async with connect(url) as ws:
        for event in events:
            await ws.send(json.dumps(event))
        while len(out) < count or (until_lossless and not out[-1][0]["lossless"]):
            meta = json.loads(await asyncio.wait_for(ws.recv(), timeout))
            data = await asyncio.wait_for(ws.recv(), timeout)
            out.append((meta, np.array(Image.open(io.BytesIO(data)).convert("RGB"))))
            await ws.send(json.dumps({"type": "frame_feedback", "index": meta["index"]}))
    return out


async def watch(url, size, react, timeout=60):
    """A page of ``size`` (w, h) that confirms every picture and calls
    ``react(meta, pixels, ws)`` with each (pixels (H, W, 3) int): it returns what ``react``
    first returns that is not None."""
    from PIL import Image
    from websockets.asyncio.client import connect

    async with connect(url) as ws:
        await ws.send(json.dumps({"type": "resize", "width": size[0], "height": size[1]}))
        while True:
            meta = json.loads(await asyncio.wait_for(ws.recv(), timeout))
            data = await asyncio.wait_for(ws.recv(), timeout)
            await ws.send(json.dumps({"type": "frame_feedback", "index": meta["index"]}))
            pixels = np.asarray(Image.open(io.BytesIO(data)).convert("RGB")).astype(int)
            result = await react(meta, pixels, ws)
            if result is not None:
                return result


def test_pictures_are_jpeg_while_moving_then_lossless_when_still(served):
    resize = {"type": "resize", "width": 160, "height": 120, "pixel_ratio": 1}
    got = asyncio.run(_pictures(served.ws, [resize], 2, until_lossless=True))
    # The page's first picture may come before its size arrived: one more JPEG then.
    (moving, picture), (still, lossless) = got[-2], got[-1]
    assert [m["mime"] for m, _ in got] == ["image/jpeg"] * (len(got) - 1) + ["image/png"]
    assert not moving["lossless"] and still["lossless"] and len(got) <= 3
    assert picture.shape == lossless.shape == (120, 160, 3)
    assert np.abs(picture.astype(int) - lossless).mean() < 4  # the same view, compressed


def test_a_refining_engine_sends_pictures_until_it_converges(served):
    events = [{"type": "resize", "width": 96, "height": 72, "pixel_ratio": 1},
              {"type": "key_down", "key": "e"}]  # raster -> trace: 4 samples a pixel
    got = asyncio.run(_pictures(served.ws, events, 6, until_lossless=True))
    traced = [m for m, _ in got if m["state"]["engine"] == "trace"]
    samples = [m["state"]["samples"] for m in traced]
    assert samples[-5:] == [1, 2, 3, 4, 4] and traced[-1]["lossless"]
    assert {m["state"]["of"] for m in traced} == {4}
    # the status line says the same (the page shows it under the picture)
    assert [int(re.search(r"(\d+)/4 samples", m["status"]).group(1)) for m in traced] == samples
    asyncio.run(_pictures(served.ws, [{"type": "key_down", "key": "e"},
                                      {"type": "key_down", "key": "e"}], 1))  # back to raster


def test_the_s_key_writes_into_the_screenshots_folder_not_the_working_one(tmp_path):
    """``--screenshots DIR``: the s key's PNG and its camera JSON land in DIR; the server's
    working directory gets nothing."""
    shots, work = tmp_path / "shots", tmp_path / "work"
    shots.mkdir()
    work.mkdir()
    with Served("--screenshots", str(shots), cwd=work) as s:
        asyncio.run(_pictures(s.ws, [{"type": "resize", "width": 80, "height": 60},
                                     {"type": "key_down", "key": "s"}], 2))
        wait_for(lambda: list(shots.glob("facet-*.png")), "the screenshot", 30)
    png = next(shots.glob("facet-*.png"))
    assert png.with_suffix(".json").is_file() and Image.open(png).size == (80, 60)
    assert list(work.iterdir()) == []


def test_a_screenshots_folder_that_is_not_one_is_refused_in_one_line(tmp_path):
    res = subprocess.run([*FACET, "view", MODEL, "--serve", "127.0.0.1:0", "--screenshots",
                          str(tmp_path / "missing")], capture_output=True, text=True,
                         timeout=120, cwd=tmp_path)
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "screenshots:" in lines[0] and "missing" in lines[0], lines
    assert "Traceback" not in res.stderr and list(tmp_path.iterdir()) == []


def test_the_served_viewer_reloads_its_file_when_it_changes(tmp_path):
    import trimesh

    path = tmp_path / "model.ply"
    trimesh.creation.box().export(path)
    statuses: list[str] = []
    changed = []

    async def react(meta, pixels, ws):
        statuses.append(meta["status"])
        if meta["lossless"] and meta["state"]["triangles"] == 1280:
            return statuses  # the new model, drawn and still
        if meta["lossless"] and not changed:  # the box shown: now change the file
            trimesh.creation.icosphere(subdivisions=3).export(path)
            changed.append(True)
        return None

    with Served(model=str(path)) as s:
        statuses = asyncio.run(watch(s.ws, (64, 48), react))
    assert "12 triangles" in statuses[0] and "1,280 triangles" in statuses[-1]


def test_the_served_viewer_reloads_the_users_shader_when_it_changes(tmp_path):
    """``--frag`` edited while a page watches: the page shows the new shader's picture (the
    shader check made the GL context current in a block of its own inside the frame's, and
    leaving it left the frame's drawing without one: "cannot create vertex array")."""
    shader = tmp_path / "mine.frag"
    solid = "#version 330 core\nout vec4 f_color;\nvoid main() {{ f_color = {}; }}\n"
    shader.write_text(solid.format("vec4(1.0, 0.0, 0.0, 1.0)"))

    changed = []

    async def react(meta, pixels, ws):
        assert not meta["state"]["error"], meta["status"]
        if not meta["lossless"]:
            return None
        if changed and (pixels[..., 1] - pixels[..., 0]).max() > 200:
            return pixels  # the new shader, drawn and still
        if not changed:  # red shown: now change the shader
            assert (pixels[..., 0] - pixels[..., 1]).max() > 200
            shader.write_text(solid.format("vec4(0.0, 1.0, 0.0, 1.0)"))
            changed.append(True)
        return None

    with Served("--frag", str(shader)) as s:
        asyncio.run(watch(s.ws, (64, 48), react))
        s.stop()
        log = s.proc.stderr.read()
    assert "Traceback" not in log and "shaders reloaded" in log, log


def test_q_in_a_page_says_in_one_line_that_the_server_stays(tmp_path):
    with Served() as s:
        keys = [{"type": "resize", "width": 32, "height": 24},
                {"type": "key_down", "key": "q"}, {"type": "key_down", "key": "Escape"},
                {"type": "key_down", "key": "o"}]  # then a change: a picture after them
        got = asyncio.run(_pictures(s.ws, keys, 1, until_lossless=True))
        assert s.proc.poll() is None  # still serving
        s.stop()
        err = s.proc.stderr.read()
    assert err.count("q and Esc do not stop a served viewer") == 1, err
    assert got[-1][0]["camera"]["model"] == "orthographic"


def test_a_bad_address_and_a_busy_port_are_one_line_each(served):
    bad = subprocess.run([*FACET, "view", MODEL, "--serve", "localhost:99999"],
                         capture_output=True, text=True, timeout=60)
    assert bad.returncode == 2 and "expected [HOST:]PORT" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1
    port = served.url.split(":")[2].split("/")[0]
    busy = subprocess.run([*FACET, "view", MODEL, "--serve", f"127.0.0.1:{port}"],
                          capture_output=True, text=True, timeout=60)
    assert busy.returncode == 2 and "cannot listen on 127.0.0.1:" in busy.stderr
    assert len(busy.stderr.strip().splitlines()) == 1 and "Traceback" not in busy.stderr


def _headless(camera_description, picture_shape):
    """The headless render of the described camera, as the served session draws."""
    from facet.viewing.session import Session

    h, w = picture_shape[:2]
    with Session(MODEL) as s:
        s.resize(w, h)
        return s.renderer.render(s.shown_scene(), camera_from(camera_description),
                                 s.options(outputs=("color",))).color


def _settled(driver, canvas, after: int) -> int:
    """The index of the first lossless picture after picture ``after``."""
    def ready():
        index = int(canvas.get_attribute("data-frame") or 0)
        return index if index > after and canvas.get_attribute("data-lossless") == "1" \
            else 0
    return wait_for(ready, f"a still picture after picture {after}")


def _shows(driver, canvas, condition, what: str) -> np.ndarray:
    """The canvas's still (lossless) picture once ``condition(camera, pixels)`` holds."""
    def check():
        if canvas.get_attribute("data-lossless") != "1":
            return None
        pixels = canvas_pixels(driver, canvas)
        camera = json.loads(canvas.get_attribute("data-camera"))
        return pixels if condition(camera, pixels) else None
    return wait_for(check, what)


@pytest.fixture
def browser():
    driver = chromium()
    yield driver
    quit_chromium(driver)


def test_dragging_in_a_browser_orbits_to_the_headless_picture(browser):
    from selenium.webdriver import ActionChains

    with Served() as s:
        browser.get(s.url)
        canvas = browser.find_element("id", "canvas")
        _settled(browser, canvas, 0)
        before = canvas_pixels(browser, canvas)
        start = json.loads(canvas.get_attribute("data-camera"))
        assert before.std() > 10  # a picture, not a blank page
        ActionChains(browser).move_to_element_with_offset(canvas, -60, 0).click_and_hold() \
            .move_by_offset(30, 10).move_by_offset(30, 10).release().perform()
        after = _shows(browser, canvas, lambda camera, _: camera["world_to_camera_opengl"]
                       != start["world_to_camera_opengl"], "the turned view")
        camera = json.loads(canvas.get_attribute("data-camera"))
        assert same_picture(after, before) > 0.01  # it turned
        assert same_picture(after, _headless(camera, after.shape)) <= MAX_DIFFERING
        assert s.stop() in (0, -signal.SIGTERM, 128 + signal.SIGTERM)


def test_keys_in_the_page_and_two_tabs_seeing_one_session(browser):
    with Served() as s:
        browser.get(s.url)
        canvas = browser.find_element("id", "canvas")
        _settled(browser, canvas, 0)
        canvas.send_keys("o")  # orthographic
        _shows(browser, canvas, lambda camera, _: camera["model"] == "orthographic",
               "the orthographic camera")
        one = browser.current_window_handle
        browser.switch_to.new_window("tab")
        browser.get(s.url)
        other = browser.find_element("id", "canvas")
        _settled(browser, other, 0)
        assert json.loads(other.get_attribute("data-camera"))["model"] == "orthographic"
        other.send_keys("b")  # background: seen in both tabs
        mine = _shows(browser, other, lambda _, pixels: pixels[0, 0].any(),
                      "the new background")
        browser.switch_to.window(one)
        theirs = _shows(browser, canvas, lambda _, pixels: pixels[0, 0].any(),
                        "the new background in the first tab")
        assert mine.shape == theirs.shape and np.array_equal(mine, theirs)


HOLD_PNG = """
// Before the page's script: PNG decodes wait until window.__release() (a slow decode of a
// large still picture), and every picture index the canvas shows is recorded.
window.__held = 0; window.__shown = [];
let release; const gate = new Promise((r) => { release = r });
window.__release = () => release();
const decode = window.createImageBitmap.bind(window);
window.createImageBitmap = async (blob) => {
  if (blob.type === 'image/png') { window.__held += 1; await gate }
  return decode(blob);
};
document.addEventListener('DOMContentLoaded', () => {
  const c = document.getElementById('canvas');
  new MutationObserver(() => window.__shown.push(Number(c.dataset.frame)))
    .observe(c, {attributes: true, attributeFilter: ['data-frame']});
});
"""


def test_a_slow_decode_never_puts_an_older_picture_over_a_newer_one(browser):
    """Decoding finishes out of order (a still view's PNG is larger than the next moving
    JPEG): the page must not show the older picture after the newer one (it did: the
    canvas went back to the stale still picture)."""
    browser.execute_cdp_cmd("Page.addScriptToEvaluateOnNewDocument", {"source": HOLD_PNG})
    with Served() as s:
        browser.get(s.url)
        canvas = browser.find_element("id", "canvas")
        wait_for(lambda: browser.execute_script("return window.__held") >= 1,
                 "the still picture's decode to start")
        shown = int(canvas.get_attribute("data-frame") or 0)
        canvas.send_keys("b")  # a new background: a newer (JPEG) picture
        wait_for(lambda: int(canvas.get_attribute("data-frame") or 0) > shown + 1,
                 "the newer picture")
        browser.execute_script("window.__release()")
        _shows(browser, canvas, lambda _, pixels: pixels[0, 0].any(), "the new background")
        indices = browser.execute_script("return window.__shown")
    assert indices == sorted(indices), indices


def test_the_page_is_told_what_keys_say_and_what_engines_warn(tmp_path):
    """Messages reach the page, not only the server's terminal: h's key map (the page's: no
    "q quit", no files dropped onto a window), a key's result (the engine now drawing) and
    a warning of the render (the ray tracer draws no wireframe) travel as notices with the
    pictures."""
    with Served() as s:
        keys = [{"type": "resize", "width": 48, "height": 32},
                {"type": "key_down", "key": "h"}, {"type": "key_down", "key": "w"},
                {"type": "key_down", "key": "e"}]
        got = asyncio.run(_pictures(s.ws, keys, 2, until_lossless=True))
        s.stop()
        out = s.proc.stdout.read()
    notices = "\n".join(n for meta, _ in got for n in meta.get("notices", []))
    assert "facet view keys:" in notices and "quit" not in notices and "drop" not in notices
    assert "engine: trace" in notices
    assert "warning:" in notices and "wireframe" in notices
    assert "facet view keys" not in out  # (not printed on the server's terminal)


def test_the_served_viewer_shows_a_stage_and_a_posed_robot(tmp_path):
    """The served page opens an OpenUSD stage with its variant chosen and a URDF robot in
    the configuration the command line gives (the view front takes the stage and robot
    options as render does): the pictures follow the variant and the joints."""
    pytest.importorskip("pxr", reason="the usd extra is not installed")
    pytest.importorskip("yourdfpy", reason="the urdf extra is not installed")
    stage = tmp_path / "ball.usda"
    stage.write_text("""#usda 1.0
def Sphere "Ball" (
    variants = { string look = "blue" }
    prepend variantSets = "look"
)
{
    variantSet "look" = {
        "blue" {
            color3f[] primvars:displayColor = [(0.1, 0.2, 0.9)]
        }
        "red" {
            color3f[] primvars:displayColor = [(0.9, 0.1, 0.1)]
        }
    }
}
""")

    async def still(meta, pixels, ws):
        return pixels if meta["lossless"] else None

    def picture(model, *args):
        with Served(*args, model=str(model)) as s:
            return asyncio.run(watch(s.ws, (96, 72), still))

    blue = picture(stage)
    red = picture(stage, "--variant", "look=red")
    reddest = lambda p: (p[..., 0] - p[..., 2]).max()  # noqa: E731
    assert reddest(red) > 60 > reddest(blue)
    arm = ROOT / "models" / "arm" / "arm.urdf"
    rest = picture(arm, "--package-path", str(ROOT / "models"))
    bent = picture(arm, "--package-path", str(ROOT / "models"),
                   "--joints", "shoulder=1.2,elbow=-1.5")
    assert rest.std() > 10 and np.abs(rest - bent).mean() > 0.5
