"""Runs stopped from outside: SIGINT (Ctrl-C, to the whole process group), SIGTERM
(timeout, docker, systemd) and SIGKILL. No process is left behind, the caller's pipes
close, no temporary file stays (after SIGKILL the next run removes what the killed one
left), files under final names are complete, and nothing prints a traceback."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from processes import own_session

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT / "app")}


def _children(pid: int) -> set[int]:
    """Every descendant of ``pid`` (from /proc)."""
    found, todo = set(), [pid]
    while todo:
        p = todo.pop()
        for task in Path(f"/proc/{p}/task").glob("*"):
            try:
                kids = (task / "children").read_text().split()
            except OSError:
                continue
            for k in map(int, kids):
                if k not in found:
                    found.add(k)
                    todo.append(k)
    return found


def _gone(pids, timeout: float = 10.0) -> bool:
    end = time.time() + timeout
    while time.time() < end:
        alive = []
        for pid in pids:
            try:
                os.kill(pid, 0)
                state = Path(f"/proc/{pid}/stat").read_text().split()[2]
                if state != "Z":
                    alive.append(pid)
            except (ProcessLookupError, FileNotFoundError):
                pass
        if not alive:
            return True
        time.sleep(0.1)
    return False


def _run(args, sig, tmp_path, wait_for, poll: float = 0.1, group: bool = False):
    proc = subprocess.Popen([sys.executable, "-m", "facet", *args], env=ENV,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=own_session, cwd=tmp_path)
    end = time.time() + 60
    while not wait_for() and time.time() < end and proc.poll() is None:
        time.sleep(poll)
    assert proc.poll() is None, proc.communicate()
    kids = _children(proc.pid)
    if sig == signal.SIGINT or group:
        os.killpg(proc.pid, sig)  # as a terminal's Ctrl-C does (or docker, systemd)
    else:
        os.kill(proc.pid, sig)
    out, err = proc.communicate(timeout=30)  # returns only once every pipe holder is gone
    assert _gone(kids), f"left behind: {kids}"
    return proc.returncode, err.decode()


def _temps(folder: Path) -> list[Path]:
    return [p for p in folder.rglob(".*") if p.is_file()]


@pytest.mark.slow
@pytest.mark.parametrize("sig,status", [(signal.SIGINT, 130), (signal.SIGTERM, 143),
                                        (signal.SIGKILL, -9)])
def test_a_dataset_turntable_stopped_from_outside(tmp_path, sig, status):
    out = tmp_path / "out"
    code, err = _run(["render", "--turntable", "400", "--size", "64x64", "--out-dir",
                      str(out), "-q"], sig, tmp_path,
                     lambda: len(list(out.glob("*_color.png"))) >= 3)
    assert code == status and "Traceback" not in err
    if sig != signal.SIGKILL:
        assert not _temps(out)
    for png in out.glob("*.png"):  # every file under a final name is whole
        assert png.read_bytes().endswith(b"IEND\xaeB`\x82")
    # The next run into the same folder cleans what a killed one could not.
    subprocess.run([sys.executable, "-m", "facet", "render", "--turntable", "2", "--size",
                    "32x32", "--out-dir", str(out), "-q"], env=ENV, check=True, cwd=tmp_path,
                   timeout=120)
    assert not _temps(out)


SIGNALS = [signal.SIGINT, signal.SIGTERM, signal.SIGKILL]


@pytest.mark.slow
@pytest.mark.parametrize("sig", SIGNALS)
@pytest.mark.parametrize("kind", ["gif", "pattern", "shader"])
def test_videos_patterns_and_shader_sequences_stopped_from_outside(tmp_path, kind, sig):
    if kind == "gif":
        target = tmp_path / "spin.gif"
        args = ["render", "--turntable", "2000", "--size", "64x64", "-o", str(target)]
        started = lambda: bool(_temps(tmp_path))  # noqa: E731 - the video is being written
    else:
        target = tmp_path / "frames" / "{:05d}.png"
        if kind == "pattern":
            args = ["render", "--turntable", "2000", "--size", "48x48", "-o", str(target)]
        else:
            shader = tmp_path / "s.frag"
            shader.write_text("void mainImage(out vec4 c, in vec2 p) { c = vec4(0.5); }\n")
            args = ["shader", str(shader), "--time", "0:400", "--fps", "30", "--size",
                    "32x32", "-o", str(target)]
        started = lambda: len(list((tmp_path / "frames").glob("*.png"))) >= 3  # noqa: E731
    code, err = _run(args, sig, tmp_path, started)
    assert code == (-9 if sig == signal.SIGKILL else 128 + sig), err
    assert "Traceback" not in err, err
    if sig != signal.SIGKILL:
        assert not _temps(tmp_path)
        if kind == "gif":
            assert not target.exists()  # a video is whole or absent
    for png in (tmp_path / "frames").glob("*.png"):
        assert png.read_bytes().endswith(b"IEND\xaeB`\x82")  # whole, under final names


@pytest.mark.slow
def test_a_two_worker_batch_stopped_mid_write_leaves_no_temporary_file(tmp_path):
    """SIGTERM to every process of the run (as docker and systemd send it) while a worker
    writes a view's arrays: the workers die mid-file, and what they were writing is
    removed (their temporary files had no chance to be renamed)."""
    for i in range(4):
        (tmp_path / f"m{i}.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                            "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    out = tmp_path / "ds"
    code, err = _run(["batch", "m*.obj", "-o", str(out), "--workers", "2", "--views", "200",
                      "--size", "2048x2048", "--outputs", "depth,normals,position", "-q"],
                     signal.SIGTERM, tmp_path,
                     lambda: any(".npy.facet-" in p.name for p in _temps(out)), poll=0.002,
                     group=True)
    assert code == 143 and "Traceback" not in err, err
    assert not [p for p in _temps(out) if ".facet-" in p.name]
