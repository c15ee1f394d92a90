"""Windows under Xvfb for the viewer and shader-window tests: the display, a running
`facet view` / `facet shader` process driven with xdotool and seen with xwd, and waits on
conditions (a title, a picture that changed and settled, a file), each with a timeout,
never a fixed sleep."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from xwd import read_xwd

ROOT = Path(__file__).resolve().parents[1]
TOOLS = ("Xvfb", "xdotool", "xwd")
W, H = 320, 240
POLL = 0.05  # seconds between looks at a condition


def until(condition, timeout: float = 20.0, what: str = "the condition"):
    """Wait until ``condition()`` is truthy (its value is returned); fail after ``timeout``."""
    end = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > end:
            raise AssertionError(f"timed out after {timeout:g} s waiting for {what}")
        time.sleep(POLL)


def _locked_by(pid: int, number: int) -> bool:
    """Whether display ``number``'s lock file names process ``pid``."""
    try:
        return int(Path(f"/tmp/.X{number}-lock").read_text().strip()) == pid
    except (OSError, ValueError):
        return False


def start_display():
    """An Xvfb display (``(name, process)``); the tests skip without the tools."""
    missing = [t for t in TOOLS if shutil.which(t) is None]
    if missing:
        pytest.skip(f"window tests need {', '.join(missing)} (Debian: xvfb xdotool x11-apps)")
    number = 90 + os.getpid() % 50
    end = time.monotonic() + 20
    while time.monotonic() < end:  # the first display number no other server holds
        socket_file, lock = Path(f"/tmp/.X11-unix/X{number}"), Path(f"/tmp/.X{number}-lock")
        if lock.exists() or socket_file.exists():
            number += 1
            continue
        proc = subprocess.Popen(["Xvfb", f":{number}", "-screen", "0", "800x600x24",
                                 "-nolisten", "tcp"], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        # Ours once its socket is there and the lock names it; a server that another test
        # started on the same number at the same moment loses the lock and exits.
        until(lambda f=socket_file, p=proc, n=number: (f.exists() and _locked_by(p.pid, n))
              or p.poll() is not None, 10, "Xvfb to start")
        if proc.poll() is None:
            break
        number += 1
    else:
        raise AssertionError("no X display number free for Xvfb within 20 s")
    return f":{number}", proc


def files(folder: Path, pattern: str, timeout: float = 30.0) -> list[Path]:
    """The files matching ``pattern`` once there is one (written atomically)."""
    return until(lambda: sorted(folder.glob(pattern)), timeout, f"a file {pattern}")


class Window:
    """A running `facet COMMAND ...` window (view by default, or shader), the first one on
    the display: no window manager, so it sits at (0, 0)."""

    def __init__(self, display, args, cwd, command="view", size=(W, H)):
        self.env = {**os.environ, "DISPLAY": display, "PYTHONPATH": str(ROOT / "app")}
        self.size = size
        if command == "view":
            if "--scene-size" in args:  # open at the scene file's size
                args = [a for a in args if a != "--scene-size"]
            elif "--size" not in args:
                args = [*args, "--size", f"{size[0]}x{size[1]}"]
        self.proc = subprocess.Popen([sys.executable, "-m", "facet", command, *args],
                                     cwd=cwd, env=self.env, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)
        name = "^facet shader" if command == "shader" else "^facet"
        out = self.xdotool("search", "--sync", "--onlyvisible", "--name", name, timeout=60)
        self.id = out.split()[0]
        self.xdotool("windowfocus", "--sync", self.id)
        if command == "view":  # the first picture is drawn once the title has the fps
            until(lambda: "fps" in self.title(), 30, "the first frame")

    def xdotool(self, *args, timeout=20):
        return subprocess.run(["xdotool", *args], env=self.env, capture_output=True, text=True,
                              timeout=timeout, check=True).stdout

    def grab(self) -> np.ndarray:
        dump = subprocess.run(["xwd", "-root", "-silent"], env=self.env, capture_output=True,
                              check=True).stdout
        w, h = self.size
        return read_xwd(dump)[:h, :w].astype(int)

    def screen(self, changed_from=None, until_=None, timeout: float = 20.0) -> np.ndarray:
        """The window's picture once it has settled (two grabs alike), and differs from
        ``changed_from`` / satisfies ``until_`` when given."""
        last = [None]

        def ready():
            image = self.grab()
            settled = last[0] is not None and np.array_equal(image, last[0])
            last[0] = image
            if not settled:
                return None
            if changed_from is not None and np.abs(image - changed_from).mean() <= 0.5:
                return None
            if until_ is not None and not until_(image):
                return None
            return image

        return _until_image(ready, timeout)

    def key(self, name):
        self.xdotool("key", name)

    def title(self) -> str:
        return self.xdotool("getwindowname", self.id).strip()

    def wait_title(self, condition, timeout: float = 30.0) -> str:
        """The title once ``condition(title)`` holds."""
        def check():
            title = self.title()
            return title if condition(title) else None
        return until(check, timeout, "the window title")

    def cpu_share(self, seconds: float = 3.0) -> float:
        """The share of one core the process used over a window of ``seconds``."""
        def cpu():
            fields = Path(f"/proc/{self.proc.pid}/stat").read_text().rsplit(")", 1)[1].split()
            return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

        start, t0 = cpu(), time.monotonic()
        time.sleep(seconds)  # a measuring window, not a wait for something to happen
        return (cpu() - start) / (time.monotonic() - t0)

    def quit(self, key: str = "q") -> int:
        self.key(key)
        return self.proc.wait(timeout=20)

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


def _until_image(ready, timeout):
    end = time.monotonic() + timeout
    while True:
        image = ready()
        if image is not None:
            return image
        if time.monotonic() > end:
            raise AssertionError(f"timed out after {timeout:g} s waiting for the picture")
        time.sleep(POLL)
