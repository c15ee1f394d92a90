"""Headless Chromium for the browser tests (Debian's chromium and chromium-driver, driven by
Selenium): start it, wait on a page's conditions with a bound, read a canvas's pixels."""

from __future__ import annotations

import base64
import io
import os
import shutil
import tempfile
import time

import numpy as np
import pytest

CHROMIUM = ("/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome")
DRIVER = "/usr/bin/chromedriver"
WAIT = 60.0  # seconds any condition may take (llvmpipe, 2 cores, a JupyterLab start)
POLL = 0.05


def chromium():
    """A Selenium driver over headless Chromium, or skip with the reason."""
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed")
    binary = next((p for p in CHROMIUM if os.path.exists(p)), None)
    if binary is None or not os.path.exists(DRIVER):
        pytest.skip("Chromium and its driver are not installed (Debian: apt-get install "
                    "chromium chromium-driver; .ci/run does)")
    options = webdriver.ChromeOptions()
    options.binary_location = binary
    profile = tempfile.mkdtemp(prefix="facet-chromium-")
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic",
                 "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--disable-dev-shm-usage",
                 "--window-size=1000,800", f"--user-data-dir={profile}"):
        options.add_argument(flag)
    from selenium.webdriver.chrome.service import Service

    driver = webdriver.Chrome(options=options, service=Service(DRIVER))
    driver.facet_profile = profile
    return driver


def quit_chromium(driver) -> None:
    driver.quit()
    shutil.rmtree(driver.facet_profile, ignore_errors=True)


def wait_for(condition, what: str, timeout: float = WAIT):
    """``condition()``'s first true value within ``timeout`` seconds, else fail saying
    ``what`` did not happen."""
    end = time.monotonic() + timeout
    while True:
        value = condition()
        if value.size > 0 if isinstance(value, np.ndarray) else bool(value):
            return value
        if time.monotonic() > end:
            raise AssertionError(f"timed out after {timeout:.0f} s waiting for {what}")
        time.sleep(POLL)


def canvas_pixels(driver, element) -> np.ndarray:
    """What a canvas or image element shows, (H, W, 3) uint8, read in the page (lossless)."""
    from PIL import Image

    url = driver.execute_script(
        "const e = arguments[0];"
        "const w = e.naturalWidth || e.width, h = e.naturalHeight || e.height;"
        "const c = document.createElement('canvas'); c.width = w; c.height = h;"
        "c.getContext('2d').drawImage(e, 0, 0); return c.toDataURL('image/png');", element)
    data = base64.b64decode(url.split(",", 1)[1])
    return np.array(Image.open(io.BytesIO(data)).convert("RGB"))


def camera_from(description: dict):
    """A facet.Camera from Camera.describe's data (perspective or orthographic)."""
    from facet.geometry.camera import Camera

    if description["model"] == "orthographic":
        return Camera(description["world_to_camera_opengl"],
                      ortho_height=description["ortho_height"], near=description["near"],
                      far=description["far"])

    proj = np.array(description["projection_opengl"])
    fov_y = float(np.degrees(2 * np.arctan(1.0 / proj[1, 1])))
    return Camera(description["world_to_camera_opengl"], fov_y=fov_y,
                  near=description["near"], far=description["far"])
