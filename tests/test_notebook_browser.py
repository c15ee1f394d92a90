"""The notebook widget end to end: JupyterLab on 127.0.0.1 (started and stopped here), a
notebook that calls ``facet.show`` on a model, run in headless Chromium (Debian's, driven by
Selenium). A drag on the widget must change the picture, and the picture the page shows once
the view is still must be the headless render of the kernel's new camera (golden tolerance,
edges masked as in tests/test_notebook_widget.py)."""

import json
import time

import numpy as np
import pytest

from browser import camera_from, canvas_pixels, chromium, quit_chromium, wait_for
from conftest import ROOT
from test_golden import MAX_DIFFERING
from test_notebook_widget import same_picture

pytest.importorskip("jupyter_rfb", reason="the notebook extra (jupyter_rfb) is not installed")
pytest.importorskip("jupyterlab", reason="JupyterLab is not installed (the dev extra has it)")

MODEL = str(ROOT / "models" / "default.obj")
RUN = "[data-command='notebook:run-cell-and-select-next']"
STILL = 0.6  # seconds a picture must stay unchanged to count as the still (lossless) one


def _settled(driver, element, previous=None) -> np.ndarray:
    """The picture ``element`` shows once it is jupyter_rfb's lossless one (a PNG: the
    widget sends JPEG while moving, PNG 0.3 s after), differs from ``previous`` and stayed
    put for STILL seconds (a JPEG that stays put a while under load is not the still one)."""
    state = {"last": None, "since": 0.0}

    def still():
        kind = driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "fetch(arguments[0].src).then((r) => r.blob()).then((b) => done(b.type))"
            ".catch(() => done(''))", element)
        now = canvas_pixels(driver, element)
        if kind != "image/png" or (previous is not None and now.shape == previous.shape
                                   and np.array_equal(now, previous)):
            state["last"] = None
            return None
        if state["last"] is None or now.shape != state["last"].shape or \
                not np.array_equal(now, state["last"]):
            state["last"], state["since"] = now, time.monotonic()
            return None
        return now if time.monotonic() - state["since"] >= STILL else None
    return wait_for(still, "the widget's still (lossless) picture")


def _run_cell(driver, index: int) -> None:
    """Select cell ``index`` and run it (the toolbar's run button, by its command id)."""
    cells = driver.find_elements("css selector", ".jp-Notebook .jp-Cell")
    cells[index].find_element("css selector", ".jp-InputPrompt").click()
    driver.find_element("css selector", RUN).click()


def open_notebook(driver, lab, name: str) -> None:
    """Wait until the page shows notebook ``name`` with its run button and the server says
    its kernel is idle and connected (the REST API: no page text)."""
    wait_for(lambda: driver.find_elements("css selector", RUN) and
             driver.find_elements("css selector", ".jp-Notebook .jp-Cell"), "the notebook")
    wait_for(lambda: lab.kernel_ready(name), "the notebook's kernel (idle, connected)")


def test_a_drag_in_the_notebook_widget_gives_the_headless_picture(tmp_path):
    from selenium.webdriver import ActionChains

    from facet.viewing.session import Session

    from jupyter_lab import JupyterLab, notebook

    camera_file = tmp_path / "camera.json"
    notebook(tmp_path / "view.ipynb", [
        f"import facet\nw = facet.show({MODEL!r}, size=(400, 300))\nw",
        "import json\nw_, h_ = w.session.surface_size\n"
        f"open({str(camera_file)!r}, 'w').write(json.dumps(w.camera().describe(w_, h_)))"])
    lab = JupyterLab(tmp_path)
    driver = chromium()
    try:
        driver.get(lab.url("view.ipynb"))
        open_notebook(driver, lab, "view.ipynb")
        _run_cell(driver, 0)
        img = wait_for(lambda: driver.find_elements("css selector", "img.renderview-view"),
                       "the widget")[0]
        before = _settled(driver, img)
        assert before.std() > 10  # a picture, not a blank widget
        ActionChains(driver).move_to_element_with_offset(img, -60, 0).click_and_hold() \
            .move_by_offset(30, 10).move_by_offset(30, 10).release().perform()
        after = _settled(driver, img, before)
        _run_cell(driver, 1)
        camera = json.loads(wait_for(lambda: camera_file.exists() and camera_file.read_text(),
                                     "the kernel to write its camera"))
    finally:
        quit_chromium(driver)
        lab.stop()
    assert same_picture(after, before) > 0.01  # it turned
    assert (camera["width"], camera["height"]) == (after.shape[1], after.shape[0])
    with Session(MODEL) as s:
        s.resize(camera["width"], camera["height"])
        ref = s.renderer.render(s.shown_scene(), camera_from(camera),
                                s.options(outputs=("color",))).color
    assert same_picture(after, ref) <= MAX_DIFFERING
