"""A soak of both remote fronts in headless Chromium: ``facet view --serve`` and the notebook
widget in JupyterLab, each driven for SOAK_SECONDS by a seeded random sequence of what a
person does to them: drags (orbit, shift-drag pan), the wheel, every key the page's key map
documents, resizes (the window; the widget's own resize handle), engine switches and page
reloads. Then, once the picture is still, it must be the headless render of the front's
state: the served viewer's against a fresh session that replays the keys sent and takes the
page's camera; the widget's against a render of the kernel's session state through a
renderer of its own (another GL context in the kernel). No exception may reach the server's
or the kernel's log, nor the notebook's output, nor a dropped-event line.

FACET_SOAK_SECONDS sets the length (a longer soak by hand: FACET_SOAK_SECONDS=300) and
FACET_SOAK_SEED another sequence; FACET_SOAK_DEBUG=x.png writes the widget's last picture
beside its reference. The soak ends in the rasterizer, refining 64 supersamples, without
the wireframe overlay (their keys pressed again as needed; ``_to_the_end``): a one-pixel
line lands a row apart in a front's picture (drawn unflipped) and in the offscreen render
(flipped), GL's line rule not being symmetric under a flip (tests/test_present.py checks
the overlay's edges in both)."""

from __future__ import annotations

import json
import os
import random
import time

import numpy as np
import pytest

from browser import WAIT, camera_from, canvas_pixels, chromium, quit_chromium, wait_for
from conftest import ROOT
from test_golden import MAX_DIFFERING
from test_notebook_widget import same_picture

pytest.importorskip("websockets", reason="the serve extra (websockets) is not installed")

SOAK_SECONDS = float(os.environ.get("FACET_SOAK_SECONDS", "20"))
SEED = int(os.environ.get("FACET_SOAK_SEED", "0"))
MODEL = str(ROOT / "models" / "default.obj")
# Every key of the page's key map (facet.viewing.keys.help_text("page")) but t, S, l and
# 1-9: those are pressed once each, at a known moment (a turntable or a 2x screenshot takes
# a minute with the path tracer; l freezes the lights where the camera is, which the replay
# must know).
RANDOM_KEYS = list("fromwaxebp,.[]h?s") + ["e", "e", "m", "a"]
ONCE_KEYS = ("t", "S", "1")
# Keys that change nothing drawn (files written, help shown): left out of the replay.
NOT_REPLAYED = set("sSth?")
BAD_LINES = ("Traceback", "internal error", "dropped a", "Exception in", "Error:")
# The kernel's errors in JupyterLab's log (its own, a websocket closed by a reload with a
# traceback of tornado's, are not the widget's): a frame of facet's, moderngl's or
# jupyter_rfb's, or ipykernel's line for a message handler that raised.
KERNEL_LINES = ("/facet/", "moderngl", "jupyter_rfb", "Exception in comm", "Exception in "
                "message handler", "FacetError", "InputError")


def _keys_are_documented():
    from facet.viewing.keys import help_text

    shown = {line.split()[0] for line in help_text("page").splitlines()[1:]}
    wanted = set(RANDOM_KEYS) | set(ONCE_KEYS) | {"l"}
    return wanted, shown


def test_the_soak_presses_every_key_the_page_documents():
    wanted, shown = _keys_are_documented()
    documented = {k for k in shown if len(k) == 1} | {"1"}  # ("1-9": the cameras)
    assert documented <= wanted | {"drag", "wheel"}, documented - wanted


def _visible(driver, element):
    """The part of ``element`` inside the window, 6 pixels in, as offsets from its centre
    (where Selenium measures moves from): (x0, x1, y0, y1), or None off screen. A resized
    or scrolled element may stick out of the window, and a move out of it is refused."""
    left, top, width, height, view_w, view_h = driver.execute_script(
        "const r = arguments[0].getBoundingClientRect();"
        "return [r.left, r.top, r.width, r.height, window.innerWidth, window.innerHeight]",
        element)
    cx, cy = left + width / 2, top + height / 2
    lo_x, hi_x = max(-width / 2, -cx) + 6, min(width / 2, view_w - cx) - 6
    lo_y, hi_y = max(-height / 2, -cy) + 6, min(height / 2, view_h - cy) - 6
    return (lo_x, hi_x, lo_y, hi_y) if hi_x > lo_x and hi_y > lo_y else None


def _drag(driver, element, rng: random.Random) -> None:
    """A drag of a few moves that stays on the element (and in the window)."""
    from selenium.webdriver import ActionChains
    from selenium.webdriver.common.keys import Keys

    visible = _visible(driver, element)
    if visible is None:
        return  # (not on screen: nothing to drag)
    lo_x, hi_x, lo_y, hi_y = visible
    mid_x, mid_y = (lo_x + hi_x) / 2, (lo_y + hi_y) / 2
    half_w, half_h = (hi_x - lo_x) / 2, (hi_y - lo_y) / 2
    x = mid_x + rng.uniform(-half_w, half_w) * 0.6
    y = mid_y + rng.uniform(-half_h, half_h) * 0.6
    pan = rng.random() < 0.3
    chain = ActionChains(driver, duration=20)
    if pan:
        chain.key_down(Keys.SHIFT)
    chain.move_to_element_with_offset(element, int(x), int(y)).click_and_hold()
    for _ in range(rng.randint(1, 4)):
        nx = min(max(x + rng.randint(-40, 40), lo_x), hi_x)
        ny = min(max(y + rng.randint(-30, 30), lo_y), hi_y)
        chain.move_by_offset(int(nx) - int(x), int(ny) - int(y))
        x, y = int(nx), int(ny)
    chain.release()
    if pan:
        chain.key_up(Keys.SHIFT)
    chain.perform()


def _wheel(driver, element, rng: random.Random) -> None:
    from selenium.webdriver import ActionChains
    from selenium.webdriver.common.actions.wheel_input import ScrollOrigin

    visible = _visible(driver, element)
    if visible is None:
        return
    lo_x, hi_x, lo_y, hi_y = visible
    x = min(max(rng.randint(-50, 50), lo_x), hi_x)
    y = min(max(rng.randint(-40, 40), lo_y), hi_y)
    origin = ScrollOrigin.from_element(element, int(x), int(y))
    ActionChains(driver).scroll_from_origin(origin, 0, rng.choice((-240, -120, 120, 240))) \
        .perform()


def _press(driver, key: str) -> None:
    from selenium.webdriver import ActionChains

    ActionChains(driver).send_keys(key).perform()


def _to_the_end(pressed: list[str]) -> list[str]:
    """The keys that bring a soak's state to its end: the rasterizer (three engines, the
    rasterizer first), no wireframe overlay, and 64 jittered supersamples (the last of four
    anti-aliasing modes, 4x MSAA first), which a still view adds one a frame: the sum of
    frames is what must come out as the headless picture (the widget's came out 2-3% darker
    while its frames were drawn on several threads at once). ``r`` turns the wireframe off
    (it resets shading, wireframe and background): only the ``w`` after the last one count."""
    since_reset = pressed[len(pressed) - pressed[::-1].index("r"):] if "r" in pressed \
        else pressed
    return ["e"] * (-pressed.count("e") % 3) + ["w"] * (since_reset.count("w") % 2) + \
        ["a"] * ((3 - pressed.count("a")) % 4)


def _soak(driver, rng, element, focus, resize, reload, pressed: list[str]) -> dict:
    """Random actions for SOAK_SECONDS; ``element()`` the picture's element now,
    ``focus()`` gives the keys to it, ``resize(rng)`` and ``reload()`` do those; the keys
    sent are appended to ``pressed``. Returns how many of each action ran."""
    counts = {"drag": 0, "wheel": 0, "key": 0, "resize": 0, "reload": 0}
    end = time.monotonic() + SOAK_SECONDS
    while time.monotonic() < end:
        what = rng.choices(list(counts), weights=(30, 20, 40, 6, 4))[0]
        el = element()
        if what == "drag":
            _drag(driver, el, rng)
        elif what == "wheel":
            _wheel(driver, el, rng)
        elif what == "key":
            focus()
            key = rng.choice(RANDOM_KEYS)
            _press(driver, key)
            pressed.append(key)
        elif what == "resize":
            resize(rng)
        else:
            reload()
        counts[what] += 1
    return counts


# -- facet view --serve ----------------------------------------------------------------------
def test_a_soak_of_the_served_viewer_ends_on_the_headless_picture(tmp_path):
    from facet.viewing.session import Session
    from test_serve import Served, _settled

    rng = random.Random(7 + SEED)
    driver = chromium()
    driver.set_window_size(700, 560)
    pressed: list[str] = []
    served = Served("--screenshots", str(tmp_path))  # (s, S and t write there)
    try:
        driver.get(served.url)
        canvas = lambda: driver.find_element("id", "canvas")  # noqa: E731 (new after reloads)
        frame = _settled(driver, canvas(), 0)
        start = json.loads(canvas().get_attribute("data-camera"))
        canvas().click()
        for key in ("l", *ONCE_KEYS):  # at a known camera, in the rasterizer
            _press(driver, key)
            frame = _settled(driver, canvas(), frame)

        def reload():
            driver.refresh()
            wait_for(lambda: driver.find_elements("id", "canvas") and
                     int(canvas().get_attribute("data-frame") or 0) > 0, "the reloaded page")

        def resize(rng):
            driver.set_window_size(rng.randint(420, 900), rng.randint(360, 700))

        counts = _soak(driver, rng, canvas, lambda: canvas().click(), resize, reload, pressed)
        print("served soak:", counts, "".join(pressed))
        # Back to the rasterizer (its still picture is exact up to the golden tolerance).
        for key in _to_the_end(pressed):  # (the rasterizer, no wireframe: module docstring)
            canvas().click()
            _press(driver, key)
            pressed.append(key)
        shown, camera = wait_for(_quiet(driver, canvas), "the page's still picture")
    finally:
        quit_chromium(driver)
        served.stop()
    log = served.proc.stderr.read()
    assert not [line for line in log.splitlines() if any(b in line for b in BAD_LINES)], log
    assert counts["reload"] and counts["resize"] and counts["key"] >= 5, counts
    with Session(MODEL) as s:
        s.set_camera(camera_from(start))
        s.char("l")
        for key in pressed:
            if key not in NOT_REPLAYED:
                s.char(key)
        s.resize(shown.shape[1], shown.shape[0])
        ref = s.renderer.render(s.shown_scene(), camera_from(camera),
                                s.options(outputs=("color",))).color
    assert s.options().engine == "raster"
    assert same_picture(shown, ref) <= MAX_DIFFERING, (counts, pressed)


FINAL_WAIT = 120.0  # seconds the widget may take to refine its final view (64 samples)
QUIET = 1.0  # seconds the page's lossless picture stays the last one: the server is done


def _final(state: dict) -> bool:
    """Whether a picture's state (the page's data-state, facet.viewing.core.ViewerCore.state)
    is the soak's final one: the rasterizer (the soak ends there), refined all it will. A
    busy server may leave an older still picture up for seconds: its state names the engine
    it was drawn with."""
    return state["engine"] == "raster" and state["samples"] == state["of"]


def _quiet(driver, canvas):
    """A condition: (pixels, camera) of the canvas's lossless picture of the final state
    (``_final``, by the canvas's data-state) once no newer one came for QUIET seconds (events
    still queued at the server would bring one)."""
    state = {"frame": None, "since": 0.0}

    def check():
        c = canvas()
        frame = c.get_attribute("data-frame")
        drawn = json.loads(c.get_attribute("data-state") or "null")
        if c.get_attribute("data-lossless") != "1" or frame != state["frame"] or \
                drawn is None or not _final(drawn):
            state["frame"], state["since"] = frame, time.monotonic()
            return None
        if time.monotonic() - state["since"] < QUIET:
            return None
        pixels = canvas_pixels(driver, c)
        camera = json.loads(c.get_attribute("data-camera"))
        return (pixels, camera) if c.get_attribute("data-frame") == frame else None
    return check


def _still_png(driver, view, ref: np.ndarray, last: dict):
    """A condition: the widget's picture once it is a PNG (jupyter_rfb's lossless one, sent
    when the kernel has drawn the last), stayed put for QUIET seconds and is the headless
    picture ``ref`` of the kernel's final state (a kernel still refining, or busy with the
    last cell, leaves an older still picture up for seconds). ``last["still"]`` keeps the
    last still PNG seen, for the message when none matches in time."""
    state = {"last": None, "since": 0.0}

    def check():
        img = view()
        kind = driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "fetch(arguments[0].src).then((r) => r.blob()).then((b) => done(b.type))"
            ".catch(() => done(''))", img)
        now = canvas_pixels(driver, img)
        if kind != "image/png" or state["last"] is None or \
                now.shape != state["last"].shape or not np.array_equal(now, state["last"]):
            state["last"], state["since"] = now, time.monotonic()
            return None
        if time.monotonic() - state["since"] < QUIET:
            return None
        last["still"] = now
        return now if now.shape == ref.shape[:2] + (3,) and \
            same_picture(now, ref) <= MAX_DIFFERING else None
    return check


# -- the notebook widget ---------------------------------------------------------------------
def test_a_soak_of_the_notebook_widget_ends_on_the_headless_picture(tmp_path):
    pytest.importorskip("jupyter_rfb", reason="the notebook extra (jupyter_rfb) is not "
                        "installed")
    pytest.importorskip("jupyterlab", reason="JupyterLab is not installed (the dev extra has "
                        "it)")
    from selenium.webdriver import ActionChains

    from test_notebook_browser import _run_cell, _settled, open_notebook

    from jupyter_lab import JupyterLab, notebook

    ref_file, camera_file = tmp_path / "ref.npy", tmp_path / "camera.json"
    notebook(tmp_path / "soak.ipynb", [
        # a renderer of the user's own alive beside the widget (another GL context)
        f"import facet\nmine = facet.Renderer(64, 48)\nmine.render(facet.load({MODEL!r}))\n"
        f"w = facet.show({MODEL!r}, size=(420, 320))\nw",
        "w",
        # (ipykernel 7 applies a widget's messages on threads of its own: this cell may run
        # before the last keys are applied, so it waits for the state they lead to, bounded)
        "import json\nimport time\nimport numpy as np\ns = w.session\n"
        "end = time.monotonic() + 30\n"
        "while time.monotonic() < end and (s.options().engine, str(s.options().aa), "
        "s.options().wireframe) != ('raster', 'ssaa:jittered:64', False):\n"
        "    time.sleep(0.05)\n"
        "wp, hp = s.surface_size\n"
        "cam = w.camera()\nref = mine.render(s.shown_scene(), cam, "
        "s.options(outputs=('color',))).color\n"
        f"np.save({str(ref_file)!r}, ref)\n"

        f"open({str(camera_file)!r}, 'w').write(json.dumps({{**cam.describe(wp, hp), "
        "'state': [s.options().engine, str(s.options().aa), s.options().wireframe]}))"])
    rng = random.Random(11 + SEED)
    lab = JupyterLab(tmp_path)
    driver = chromium()
    pressed: list[str] = []
    try:
        driver.get(lab.url("soak.ipynb"))
        open_notebook(driver, lab, "soak.ipynb")
        _run_cell(driver, 0)

        def view(timeout=WAIT):
            img = wait_for(lambda: driver.find_elements("css selector", "img.renderview-view"),
                           "the widget", timeout)[-1]
            driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", img)
            return img

        def focus():
            ActionChains(driver).move_to_element(view()).click().perform()

        _settled(driver, view())
        focus()
        for key in ONCE_KEYS:
            _press(driver, key)
            _settled(driver, view())

        def resize(rng):
            handle = driver.find_elements("css selector", ".renderview-resizer")
            if handle:
                ActionChains(driver, duration=20).move_to_element(handle[-1]).click_and_hold() \
                    .move_by_offset(rng.randint(-80, 80), rng.randint(-60, 60)).release() \
                    .perform()

        def reload():
            driver.refresh()
            open_notebook(driver, lab, "soak.ipynb")
            # (the reloaded page shows the widget again; a run clicked before the page's
            # kernel connection took it is clicked again)
            for attempt in range(3):
                _run_cell(driver, 1)
                try:
                    view(timeout=20)
                    break
                except AssertionError:
                    if attempt == 2:
                        raise

        counts = _soak(driver, rng, view, focus, resize, reload, pressed)
        print("notebook soak:", counts, "".join(pressed))
        for key in _to_the_end(pressed):
            focus()
            _press(driver, key)
        # The kernel's state and its reference once the keys have been applied (the cell
        # waits for their state), then the page's picture once it is still.
        _run_cell(driver, 2)
        camera = json.loads(wait_for(lambda: camera_file.exists() and camera_file.read_text(),
                                     "the kernel's camera"))
        assert camera["state"] == ["raster", "ssaa:jittered:64", False], \
            f"the kernel's state after the keys: {camera['state']} ({''.join(pressed)})"
        ref, last = np.load(ref_file), {"still": None}
        try:
            shown = wait_for(_still_png(driver, view, ref, last), "the widget's still lossless "
                             "picture of the final state", timeout=FINAL_WAIT)
        except AssertionError:
            shown = last["still"]  # (compared below, for the message)
            assert shown is not None, "the widget showed no still lossless picture"
        outputs = "\n".join(e.text for e in driver.find_elements(
            "css selector", ".jp-OutputArea-output"))
    finally:
        quit_chromium(driver)
        lab.stop()
    log = (tmp_path / "jupyter.log").read_text()
    assert not [line for line in log.splitlines() if any(b in line for b in KERNEL_LINES)], log
    assert not [line for line in outputs.splitlines() if any(b in line for b in BAD_LINES)], \
        outputs
    assert counts["reload"] and counts["resize"] and counts["key"] >= 5, counts
    if os.environ.get("FACET_SOAK_DEBUG"):
        from PIL import Image

        Image.fromarray(np.hstack([shown, ref[..., :3]])).save(os.environ["FACET_SOAK_DEBUG"])
    assert (camera["width"], camera["height"]) == (shown.shape[1], shown.shape[0])
    assert same_picture(shown, ref) <= MAX_DIFFERING, (counts, pressed)
