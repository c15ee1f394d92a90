"""When the path tracer's sum of samples stops (facet.render.budget): adaptive sampling
(``noise``), a time limit, the paths per pixel as an output channel, the options from every
front (Python, scene files, batch manifests, the command line), and the command line's
progress line and signals (SIGINT / SIGTERM stop a render within a second; --keep-partial
writes the picture reached)."""

import os
import pty
import re
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import facet
from facet.geometry.camera import Camera
from facet.scene.pbr import PbrMaterial

ROOT = Path(__file__).resolve().parents[1]
FACET = [sys.executable, "-m", "facet"]


def _half_lit():
    """A Lambertian floor lit by a small sphere lamp (noisy under BSDF bounces) on the
    left, the black background on the right (no noise at all)."""
    scene = facet.Scene()
    scene.add(facet.primitives.plane(2.0), PbrMaterial(base_color=(0.7,) * 3, metallic=0.0,
                                                       specular=0.0),
              facet.transforms.translate((-1.0, 0.0, 0.0)))
    lamp = PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0, specular=0.0, emissive=(1, 1, 1),
                       emissive_strength=20.0)
    scene.add(facet.shapes.Sphere(0.1), lamp, facet.transforms.translate((-1.0, 0.5, 0.0)))
    return scene, Camera.look_at((0, 3, 0.01), (0, 0, 0), fov_y=50, near=0.5, far=10)


def test_adaptive_sampling_spends_paths_where_the_noise_is():
    """With noise = 0.02 a black background stops at the 16 paths every pixel takes first,
    the lit floor takes more, and each pixel is the mean of its own paths: the picture
    agrees with one of 256 paths everywhere (within its noise), and spp says how many."""
    scene, camera = _half_lit()
    with facet.Renderer(32, 32) as r:
        full = r.render(scene, camera, engine="path", spp=256, float_color=True,
                        lights="scene", outputs=("color", "spp"))
        adaptive = r.render(scene, camera, engine="path", spp=256, noise=0.02,
                            float_color=True, lights="scene", outputs=("color", "spp"))
    assert (full.spp == 256).all()
    spp = adaptive.spp
    dark = full.color[..., :3].max(axis=-1) == 0
    assert dark[:, -8:].all() and (spp[:, -8:] == 16).all()  # the background: 16
    assert spp[~dark].mean() > 64 and spp.max() <= 256
    a, b = adaptive.color[..., :3], full.color[..., :3]
    np.testing.assert_allclose(a[~dark].mean(axis=0), b[~dark].mean(axis=0), rtol=0.02)
    assert (a[dark] == 0).all()


def test_a_time_limit_stops_the_sum_in_time():
    """No spp given: paths until the limit (within a sample's time), the same count in
    every pixel; the picture is their mean (as bright as a fixed count's)."""
    scene, camera = _half_lit()
    with facet.Renderer(32, 32) as r:
        r.render(scene, camera, engine="path", spp=1, float_color=True, lights="scene",
                 outputs=("color", "spp"))  # (compiled: what is measured is the sum)
        began = time.monotonic()
        frame = r.render(scene, camera, engine="path", time_limit=1.0, float_color=True,
                         lights="scene", outputs=("color", "spp"))
        took = time.monotonic() - began
        fixed = r.render(scene, camera, engine="path", spp=int(frame.spp[0, 0]),
                         float_color=True, lights="scene")
    assert took < 1.5, took
    n = frame.spp[0, 0]
    assert 4 <= n < 4096 and (frame.spp == n).all()
    np.testing.assert_allclose(frame.color[..., :3].mean(), fixed.color[..., :3].mean(),
                               rtol=0.1)


def test_a_progress_callback_sees_every_sample_and_may_stop_the_sum():
    scene, camera = _half_lit()
    seen = []

    def progress(done, total, seconds):
        seen.append((done, total))
        return done < 5

    with facet.Renderer(16, 16) as r:
        r.render(scene, camera, engine="path", spp=1, lights="scene",
                 outputs=("color", "spp"))  # (compiled)
        r.progress = progress
        frame = r.render(scene, camera, engine="path", spp=64, lights="scene",
                         outputs=("color", "spp"))
    # After each sample, and before each strip of one that is slow enough to be drawn in
    # strips (a loaded machine): the same count again (facet.render.budget).
    done = [d for d, _ in seen]
    assert seen[-1] == (5, 64) and sorted(set(done)) == [1, 2, 3, 4, 5], seen
    assert done == sorted(done)
    assert (frame.spp == 5).all()


def test_the_options_from_every_front(tmp_path):
    (tmp_path / "s.toml").write_text('[render]\nnoise = 0.05\ntime_limit = 3\n'
                                     'outputs = ["color", "spp"]\n')
    scene = facet.load(tmp_path / "s.toml")
    assert scene.options["noise"] == 0.05 and scene.options["time_limit"] == 3.0
    for bad in ("noise = 0", "time_limit = -1", 'noise = "low"'):
        (tmp_path / "b.toml").write_text(f"[render]\n{bad}\n")
        with pytest.raises(facet.FacetError) as e:
            facet.load(tmp_path / "b.toml")
        assert "\n" not in str(e.value) and bad.split()[0] in str(e.value)
    from facet.batch.manifest import load_manifest

    (tmp_path / "m.toml").write_text('[defaults]\nnoise = 0.1\n[[jobs]]\nmodel = "a.obj"\n'
                                     'time_limit = 2\n')
    (tmp_path / "a.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    opts = load_manifest(tmp_path / "m.toml")[0].options
    assert opts["noise"] == 0.1 and opts["time_limit"] == 2.0


def test_the_rasterizer_says_it_takes_no_noise_threshold():
    scene, camera = _half_lit()
    with facet.Renderer(16, 16) as r, pytest.warns(facet.FacetWarning,
                                                   match="noise is the path tracer's"):
        r.render(scene, camera, noise=0.1, lights="scene")


def _long_render(tmp_path, *extra):
    """``facet render`` of the Cornell box at many paths, on a terminal (a pty): returns
    the process and the pty's reading end."""
    master, slave = pty.openpty()
    env = dict(os.environ, PYTHONPATH=str(ROOT / "app"))
    proc = subprocess.Popen([*FACET, "render", str(ROOT / "models" / "cornell.toml"), "-o",
                             str(tmp_path / "out.png"), "--spp", "4096", *extra],
                            stdin=subprocess.DEVNULL, stdout=slave, stderr=slave, env=env,
                            cwd=tmp_path)
    os.close(slave)
    return proc, master


def _read_until(master, text: str, limit: float) -> str:
    """What the pty shows until ``text`` appears (or ``limit`` seconds pass)."""
    seen, end = b"", time.monotonic() + limit
    while text.encode() not in seen and time.monotonic() < end:
        ready, _, _ = select.select([master], [], [], 0.2)
        if ready:
            try:
                seen += os.read(master, 4096)
            except OSError:
                break
    return seen.decode(errors="replace")


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
@pytest.mark.parametrize("keep", [False, True])
def test_a_signal_stops_a_render_within_a_second(tmp_path, sig, keep):
    """The progress line shows on a terminal once the render has run 2 s; the signal
    stops it within a second, exit status 128 + the signal; only --keep-partial writes
    the picture reached (else nothing is written)."""
    proc, master = _long_render(tmp_path, *(["--keep-partial"] if keep else []))
    try:
        shown = _read_until(master, "samples,", 60)
        assert "samples," in shown and "left" in shown, shown
        sent = time.monotonic()
        proc.send_signal(sig)
        proc.wait(timeout=10)
        assert time.monotonic() - sent < 1.0
        rest = _read_until(master, "\x00", 0.5)
    finally:
        proc.kill()
        proc.wait()
        os.close(master)
    assert proc.returncode == 128 + sig
    written = sorted(p.name for p in tmp_path.iterdir())
    if keep:
        assert written == ["out.json", "out.png"]
        assert f"stopped by {sig.name}" in rest, rest
        from PIL import Image

        picture = np.asarray(Image.open(tmp_path / "out.png"))[..., :3]
        assert picture.mean() > 20  # the room, lit (not a blank picture)
    else:
        assert written == [], written
        assert "Traceback" not in rest
        shown = re.sub(r"\x1b\[[0-9;]*[A-Za-z]|\r", "\n", rest)  # the line's clearing
        said = [line for line in shown.splitlines()  # (not the progress line's updates)
                if line.startswith("facet:") and "samples," not in line]
        assert len(said) == 1 and f"stopped by {sig.name}" in said[0] and \
            "nothing was written" in said[0] and "--keep-partial" in said[0], rest


def test_quiet_renders_show_no_progress(tmp_path):
    proc, master = _long_render(tmp_path, "-q", "--time-limit", "3")
    try:
        shown = _read_until(master, "samples,", 20)
        proc.wait(timeout=60)
    finally:
        proc.kill()
        proc.wait()
        os.close(master)
    assert proc.returncode == 0 and "samples," not in shown, shown
    assert (tmp_path / "out.png").exists()


def test_a_time_limit_on_a_single_pass_picture_says_so():
    """The rasterizer without supersampling draws one pass: a time limit cannot shorten it,
    and one line says so (it was silently ignored)."""
    scene, camera = _half_lit()
    with facet.Renderer(16, 16) as r, pytest.warns(facet.FacetWarning,
                                                   match="time_limit stops sums of samples"):
        r.render(scene, camera, time_limit=5.0, lights="scene")


def test_the_time_left_comes_from_the_measured_rate_and_only_once_stable():
    """The first sample carries compiling and uploading (4.6 s here), the rest take 0.6 s:
    the old estimate said about 2350 s left for a 305 s render; the time left is now said
    from the rate after the first sample, and only once two rates agree."""
    from facet.cli.progress import TimeLeft

    left = TimeLeft()
    times = [4.6 + 0.6 * k for k in range(6)]  # samples 1..6 done at these seconds
    said = [left.update(k + 1, 512, t) for k, t in enumerate(times)]
    assert said[:2] == [None, None]  # the first sample, then one rate: not yet
    assert said[2] == pytest.approx(0.6 * (512 - 3), rel=0.01)
    assert said[-1] == pytest.approx(0.6 * (512 - 6), rel=0.01)
    erratic = TimeLeft()  # rates that do not settle: nothing said
    assert [erratic.update(k, 100, t) for k, t in ((1, 1.0), (2, 1.5), (3, 4.0))] == \
        [None, None, None]


def test_the_seconds_shown_never_go_back_between_stages(monkeypatch, capsys):
    """The preparing stage showed "rendering ..., 4.7 s"; the sum then showed the
    renderer's own seconds (counted after its preparation, "1/512 samples, 4.6 s"): the
    line's seconds are now the stage's."""
    import time as clock

    from facet.cli import progress

    monkeypatch.setattr(progress, "DELAY", 0.0)
    monkeypatch.setattr(progress, "REFRESH", 0.0)
    line = progress.Ticker(True)
    with progress.SampleProgress(False, False, line=line) as watch:
        watch._start = clock.monotonic() - 4.7  # the stage began 4.7 s ago
        watch(1, 512, 0.1)  # the renderer's clock: 0.1 s into the sum
    shown = capsys.readouterr().err
    seconds = [float(s) for s in re.findall(r"samples, ([\d.]+) s", shown)]
    assert seconds and min(seconds) >= 4.7, shown
    assert "estimating the time left" in shown, shown
