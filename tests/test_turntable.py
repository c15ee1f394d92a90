"""Turntables: orbit cameras, the Python iterator, and GIF / MP4 / PNG-sequence / dataset
round trips from the CLI."""

import imageio.v3 as iio
import numpy as np
import pytest

from facet.cli import main
from facet.geometry.camera import Camera
from facet.render.turntable import orbit_cameras, turntable
from facet.scene import Scene

from conftest import sphere_mesh


def test_orbit_cameras_keep_distance_and_step_evenly():
    cam = Camera.look_at((0, 1, 3), (0, 0, 0))
    cams = orbit_cameras(cam, (0, 0, 0), 8)
    eyes = np.array([c.eye for c in cams])
    assert np.allclose(np.linalg.norm(eyes, axis=1), np.linalg.norm(cam.eye))
    assert np.allclose(eyes[:, 1], 1)  # about the world's y axis
    angles = np.degrees(np.arctan2(eyes[:, 0], eyes[:, 2]))
    assert np.allclose(np.diff(np.unwrap(angles, period=360)), 45)
    for c in cams:  # every camera still looks at the centre
        assert np.allclose(np.cross(c.forward, -c.eye / np.linalg.norm(c.eye)), 0, atol=1e-9)


def test_turntable_iterator(renderer):
    scene = Scene()
    scene.add(sphere_mesh(2), transform=np.diag([1.0, 1.0, 0.3, 1.0]))  # a flattened disc
    frames = list(turntable(renderer(32, 32), scene, 4, outputs=("ids",)))
    assert len(frames) == 4
    areas = [int((f.object_ids == 0).sum()) for f in frames]
    assert areas[0] != areas[1] and areas[0] == pytest.approx(areas[2], abs=3)


@pytest.mark.parametrize("target,reader", [("spin.gif", "gif"), ("spin.mp4", "mp4"),
                                           ("frames/{:04d}.png", "png")])
def test_cli_turntable_round_trip(tmp_path, monkeypatch, target, reader):
    monkeypatch.chdir(tmp_path)
    assert main(["render", "--turntable", "6", "-o", target, "--size", "48x32", "-q"]) == 0
    if reader == "png":
        files = sorted((tmp_path / "frames").glob("*.png"))
        assert [f.name for f in files] == [f"{i:04d}.png" for i in range(6)]
        frames = np.stack([iio.imread(f) for f in files])
    else:
        frames = iio.imread(tmp_path / target, index=None)
    assert frames.shape[:3] == (6, 32, 48)
    assert not list(tmp_path.glob(".*"))  # no temporary files left
    # Each frame is the render of its orbit camera (the file's encoding aside: PNG exact,
    # GIF a 256-colour palette, MP4 lossy), in order, the view moving between them.
    from facet.formats.source import open_scene
    from facet.paths import default_model
    from facet.render.renderer import Renderer

    with Renderer() as r:
        expected = np.stack([f.color[..., :3] for f in turntable(
            r, open_scene(default_model()), 6, size=(48, 32), outputs=("color",))])
    error = np.abs(frames[..., :3].astype(int) - expected).mean(axis=(1, 2, 3))
    limit = {"png": 0.0, "gif": 0.5, "mp4": 4.0}[reader]
    assert error.max() <= limit, error
    moved = np.abs(expected[0].astype(int) - expected[1]).mean()
    assert moved > 2 * max(limit, 1.0), moved


def test_a_turntable_orbits_the_options_up_axis(renderer):
    """The orbit's axis is the world's up of the options (a z-up scan turns about z), for
    the Python iterator, the CLI and the viewer's t key alike (they all call it)."""
    scene = Scene()
    scene.add(sphere_mesh(2), transform=np.diag([1.0, 0.6, 0.3, 1.0]))
    for up, axis in (("z", 2), ("-x", 0), ("y", 1)):
        frames = list(turntable(renderer(16, 16), scene, 5, up=up, outputs=("ids",)))
        eyes = np.array([f.camera.eye for f in frames])
        assert np.ptp(eyes[:, axis]) < 1e-9 < np.ptp(eyes, axis=0).max(), (up, eyes)


def test_cli_turntable_dataset(tmp_path):
    out = tmp_path / "ds"
    assert main(["render", "--turntable", "3", "--outputs", "color,depth,ids", "--out-dir",
                 str(out), "--size", "32x32", "-q"]) == 0
    for i in range(3):
        for name in ("color.png", "depth.npy", "ids.npy", "camera.json"):
            assert (out / f"{i:04d}_{name}").is_file()
    d0, d1 = np.load(out / "0000_depth.npy"), np.load(out / "0001_depth.npy")
    assert d0.shape == (32, 32) and not np.array_equal(d0, d1)


@pytest.mark.parametrize("args,message", [
    (["--turntable", "0", "-o", "x.gif"], "--turntable needs 1..100000 frames"),
    (["--turntable", "4", "-o", "x.avi"], "written as .gif, .mp4 or a numbered image pattern"),
    (["--turntable", "4", "-o", "frames/{:04d}.bmp"], "must number image files"),
    (["--turntable", "4", "-o", "x.gif", "--bits", "16"], "16-bit colour cannot go"),
    (["--turntable", "4", "-o", "x.gif", "--fps", "0"], "--fps must be in"),
])
def test_bad_turntables(tmp_path, monkeypatch, capsys, args, message):
    monkeypatch.chdir(tmp_path)
    code = main(["render", *args])
    err = capsys.readouterr().err
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("quiet", [False, True])
def test_progress_bar_on_a_terminal_only(tmp_path, quiet):
    """On a terminal a turntable shows a tqdm bar on stderr; --quiet silences it; when stderr
    is not a terminal (a pipe) nothing is printed there."""
    import os
    import pty
    import subprocess
    import sys
    from pathlib import Path

    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1] / "app")}
    cmd = [sys.executable, "-m", "facet", "render", "--turntable", "5", "-o", "s.gif",
           "--size", "24x24", *(["-q"] if quiet else [])]
    import fcntl
    import struct
    import termios

    master, slave = pty.openpty()
    # A real terminal has a size; a fresh pty is 0 x 0, which tqdm draws as nothing.
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))
    proc = subprocess.Popen(cmd, cwd=tmp_path, env=env, stdout=subprocess.DEVNULL,
                            stderr=slave)
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 4096)
        except OSError:
            break
        if not data:
            break
        chunks.append(data)
    os.close(master)
    assert proc.wait() == 0
    text = b"".join(chunks).decode(errors="replace")
    if quiet:
        assert text.strip() == ""
    else:
        assert "turntable" in text and "/5 [" in text
    piped = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True)
    assert piped.returncode == 0 and piped.stderr == ""


def test_python_m_turntable_dataset_uses_a_writer_process(tmp_path):
    """The dataset writer is a spawned process, which re-imports the main module: with
    ``python -m facet`` that must not start a second render."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1] / "app")}
    res = subprocess.run([sys.executable, "-m", "facet", "render", "--turntable", "2",
                          "--outputs", "color,ids", "--out-dir", "ds", "--size", "24x24"],
                         cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    names = sorted(p.name for p in (tmp_path / "ds").iterdir())
    assert names == sorted(f"{i:04d}_{n}" for i in range(2)
                           for n in ("color.png", "ids.npy", "ids.png", "camera.json"))
    assert len(res.stdout.split()) == 8
