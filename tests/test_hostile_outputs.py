"""Where facet writes and what it opens, whatever the folders hold: only inside the output
folder it was given (no symbolic link in it leads out, FIFOs are never outputs), only
inside --confine's folder (every opener, and "outside" reads the same as "missing"), and a
window system that never answers is a one-line error within the wait budget, stoppable by
SIGTERM while it waits."""

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from hostile import ROOT, facet, refused, x_socket

TRIANGLE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
FRAG = "void mainImage(out vec4 c, in vec2 p) { c = vec4(1.0); }\n"


@pytest.fixture
def folders(tmp_path):
    (tmp_path / "m.obj").write_text(TRIANGLE)
    (tmp_path / "ds").mkdir()
    (tmp_path / "elsewhere").mkdir()
    return tmp_path


def _batch(tmp_path, *extra):
    return facet("batch", "m.obj", "-o", "ds", "--views", "1", "--size", "8x8", "-q",
                 *extra, cwd=tmp_path)


def test_a_job_folder_linked_elsewhere_is_not_written_through(folders):
    (folders / "ds" / "m").symlink_to(folders / "elsewhere")
    code, err = _batch(folders)
    assert code == 1, err  # the job failed, and the index says why
    record = json.loads((folders / "ds" / "index.jsonl").read_text())
    assert record["status"] == "failed" and "leads outside the output folder" in \
        record["error"], record
    assert list((folders / "elsewhere").iterdir()) == []


@pytest.mark.parametrize("existing", [True, False])
def test_an_index_linked_elsewhere_is_not_written_through(folders, existing):
    target = folders / "elsewhere" / "index.jsonl"
    if existing:
        target.write_text('{"job": "x", "model": "y", "status": "done"}\n')
    (folders / "ds" / "index.jsonl").symlink_to(target)
    refused(_batch(folders), "index.jsonl", "leads outside the output folder")
    assert target.exists() == existing and (not existing or "x" in target.read_text())
    assert not (folders / "ds" / "m").exists()


def test_fifos_are_never_outputs_nor_read_as_finished_jobs(folders):
    os.mkfifo(folders / "out.png")
    refused(facet("render", "m.obj", "-o", "out.png", "--size", "8x8", cwd=folders),
            "named pipe")
    os.mkfifo(folders / "ds" / "index.jsonl")
    refused(_batch(folders), "index.jsonl", "named pipe")
    os.unlink(folders / "ds" / "index.jsonl")
    (folders / "ds" / "m").mkdir()
    os.mkfifo(folders / "ds" / "m" / "transforms.json")
    code, err = _batch(folders)  # the job fails (the index says why); the run ends
    assert code == 1, err
    assert "transforms.json: is a named pipe" in (folders / "ds" / "index.jsonl").read_text()
    assert not os.path.isfile(folders / "ds" / "m" / "transforms.json")


# -- confinement: every opener, and one message for "outside" and "missing" ----------------
OPENERS = {
    "--common": lambda p: ["shader", "in/s.frag", "--common", f"{p}.glsl", "-o", "in/o.png"],
    "--list-uniforms": lambda p: ["shader", "--list-uniforms", f"{p}.glsl"],
    "include": lambda p: ["shader", "in/inc.frag", "-o", "in/o.png"],
    "project common": lambda p: ["shader", "in/p.toml", "-o", "in/o.png"],
    "channel": lambda p: ["shader", "in/s.frag", "--channel", f"0={p}.png", "-o", "in/o.png"],
    "environment": lambda p: ["render", "in/m.obj", "--env", f"{p}.png", "-o", "in/o.png"],
    "scene mesh": lambda p: ["render", "in/s.toml", "-o", "in/o.png"],
    "manifest model": lambda p: ["batch", "in/m.jsonl", "-o", "in/ds"],
    "view plan file": lambda p: ["batch", "in/v.jsonl", "-o", "in/ds"],
    "the input itself": lambda p: ["render", f"{p}.obj", "-o", "in/o.png"],
}


def _confined_inputs(root: Path, name: str) -> None:
    """Files inside ``root/in`` that reach for ``root/NAME.*`` outside it."""
    inside = root / "in"
    inside.mkdir(exist_ok=True)
    (inside / "m.obj").write_text(TRIANGLE)
    (inside / "s.frag").write_text(FRAG)
    (inside / "inc.frag").write_text(f'#include "../{name}.glsl"\n' + FRAG)
    (inside / "p.toml").write_text(f'common = "../{name}.glsl"\n[image]\nshader = "s.frag"\n')
    (inside / "s.toml").write_text(f'[[objects]]\nmesh = "../{name}.obj"\n')
    (inside / "m.jsonl").write_text(json.dumps({"model": f"../{name}.obj"}) + "\n")
    (inside / "v.jsonl").write_text(json.dumps({"model": "m.obj", "views": {
        "plan": "cameras", "file": f"../{name}.json"}}) + "\n")


@pytest.mark.parametrize("opener", OPENERS)
def test_confinement_refuses_outside_and_missing_alike(tmp_path, opener):
    from PIL import Image

    (tmp_path / "present.glsl").write_text("float k = 1.0;\n")
    (tmp_path / "present.obj").write_text(TRIANGLE)
    (tmp_path / "present.json").write_text("{}")
    Image.new("RGB", (8, 4)).save(tmp_path / "present.png")
    lines = {}
    for name in ("present", "absent"):
        _confined_inputs(tmp_path, name)
        lines[name] = refused(facet(*OPENERS[opener](name), "--confine", "in",
                                    cwd=tmp_path), "outside the confinement folder")
    assert lines["present"].replace("present", "X") == lines["absent"].replace("absent", "X")
    assert not (tmp_path / "in" / "o.png").exists() and not (tmp_path / "in" / "ds").exists()


# -- a window system that never answers ----------------------------------------------------
@pytest.fixture
def silent_display(tmp_path):
    """An X display (:N on a unix socket in /tmp/.X11-unix) that accepts connections and
    never says a word."""
    name, server, path = x_socket(600)
    yield name
    server.close()
    path.unlink()


def test_a_silent_x_server_is_one_line_within_the_budget(tmp_path, silent_display):
    (tmp_path / "m.obj").write_text(TRIANGLE)
    start = time.monotonic()
    line = refused(facet("--budget", "wait_seconds=2", "view", "m.obj", cwd=tmp_path,
                         env={"DISPLAY": silent_display, "WAYLAND_DISPLAY": ""},
                         timeout=30), "did not answer within 2 s")
    assert time.monotonic() - start < 15, line


def test_sigterm_stops_a_viewer_waiting_for_a_silent_x_server(tmp_path, silent_display):
    (tmp_path / "m.obj").write_text(TRIANGLE)
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app"), "DISPLAY": silent_display,
           "WAYLAND_DISPLAY": "", "FACET_BUDGET_WAIT_SECONDS": "600"}
    proc = subprocess.Popen([sys.executable, "-m", "facet", "view", "m.obj"], cwd=tmp_path,
                            env=env, stderr=subprocess.PIPE, text=True)
    try:
        end = time.monotonic() + 30  # until it is waiting on the socket
        while time.monotonic() < end and not _connected(proc.pid):
            time.sleep(0.05)
        assert _connected(proc.pid), "the viewer never reached the display"
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=10)
    finally:
        proc.kill()
    assert proc.returncode == 143 and "Traceback" not in err, (proc.returncode, err)


def test_the_display_probe_stays_connected_until_glfw_has_connected(tmp_path):
    """An X server resets when its last client leaves, dropping connections still in their
    setup: a probe that hung up just before glfw connected made glfw fail at random ("Failed
    to open display" in CI). A stand-in server answers the probe and, when the next
    connection (glfw's) arrives, looks whether the probe is still there."""
    (tmp_path / "m.obj").write_text(TRIANGLE)
    name, server, path = x_socket(700)
    seen = {}

    def serve():
        probe, _ = server.accept()
        probe.recv(12)
        probe.sendall(b"\0")  # "failed": a live server, enough for the probe
        second, _ = server.accept()
        probe.setblocking(False)
        try:
            seen["probe open"] = probe.recv(1) != b""
        except BlockingIOError:  # nothing to read and not closed: still connected
            seen["probe open"] = True
        second.close()
        probe.close()

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        result = facet("view", "m.obj", cwd=tmp_path, timeout=30,
                       env={"DISPLAY": name, "WAYLAND_DISPLAY": ""})
        thread.join(timeout=10)
    finally:
        server.close()
        path.unlink()
    refused(result, "cannot open the display")
    assert seen == {"probe open": True}


def _connected(pid: int) -> bool:
    """Whether process ``pid`` holds a unix socket (its probe of the display)."""
    try:
        return any(os.readlink(f"/proc/{pid}/fd/{fd}").startswith("socket:")
                   for fd in os.listdir(f"/proc/{pid}/fd"))
    except OSError:
        return False
