"""Dataset runs (facet.batch): resuming, a bad model among good ones, identical files
whatever the worker count or cluster, a run stopped from outside, workers that die or
cannot render, on local processes and on a local Ray cluster."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from facet.batch import render_dataset
from facet.cli import main
from facet.errors import InputError
from processes import own_session

from batch_data import child_pids, make_models, write_manifest

ROOT = Path(__file__).resolve().parents[1]


def test_resume_bad_models_and_identical_files_across_worker_counts(tmp_path, capsys):
    models = make_models(tmp_path / "models", 4)
    (tmp_path / "models" / "bad.obj").write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    jobs = [{"model": f"models/{m.name}"} for m in models]
    jobs.insert(2, {"model": "models/bad.obj"})
    manifest = write_manifest(tmp_path, jobs, {"size": [48, 48], "views": {"plan": "random",
                                                                       "count": 2}})
    code = main(["batch", str(manifest), "-o", str(tmp_path / "one"), "-q"])
    assert code == 1  # a job failed: exit 1, the others done
    assert "4 done, 1 failed" in capsys.readouterr().err
    index = [json.loads(line) for line in (tmp_path / "one" / "index.jsonl").open()]
    bad = next(r for r in index if r["job"] == "bad")
    assert bad["status"] == "failed" and "NaN or infinite" in bad["error"]
    # A rerun skips what is finished; the index keeps one line per job, the skipped ones
    # with the record of the run that rendered them.
    assert main(["batch", str(manifest), "-o", str(tmp_path / "one"), "-q"]) == 1
    assert "0 done, 1 failed, 4 skipped" in capsys.readouterr().err
    again = [json.loads(line) for line in (tmp_path / "one" / "index.jsonl").open()]
    assert sorted(r["job"] for r in again) == sorted(r["job"] for r in index)
    assert {r["job"]: r["status"] for r in again} == {r["job"]: r["status"] for r in index}
    # Two workers write byte-identical files.
    assert main(["batch", str(manifest), "-o", str(tmp_path / "two"), "--workers", "2",
                 "-q"]) == 1
    capsys.readouterr()
    for m in models:
        for a in sorted((tmp_path / "one" / m.stem).rglob("*.*")):
            b = tmp_path / "two" / a.relative_to(tmp_path / "one")
            assert a.read_bytes() == b.read_bytes(), a


@pytest.mark.slow
def test_a_run_stopped_from_outside_resumes(tmp_path):
    models = make_models(tmp_path / "models", 6)
    # m00 has 600 views: the run is still on it when this test, looking late on a loaded
    # machine, stops it (with 30 views a look ~1 s late could find the whole run done).
    long = {"views": {"plan": "sphere", "count": 600}}
    manifest = write_manifest(tmp_path, [{"model": f"models/{m.name}",
                                          **(long if m.stem == "m00" else {})}
                                         for m in models],
                              {"size": [128, 128], "views": {"plan": "sphere", "count": 30}})
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    proc = subprocess.Popen([sys.executable, "-m", "facet", "batch", str(manifest), "-o",
                             str(out), "-q"], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, preexec_fn=own_session)
    end = time.time() + 60
    while time.time() < end and len(list(out.glob("*/images/*.png"))) < 10:
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and b"Traceback" not in err
    for png in out.rglob("*.png"):
        assert png.read_bytes().endswith(b"IEND\xaeB`\x82")  # whole under final names
    finished = [d for d in out.iterdir() if (d / "transforms.json").is_file()]
    assert len(finished) < 6
    assert main(["batch", str(manifest), "-o", str(out), "-q"]) == 0  # resumes
    assert all((out / m.stem / "transforms.json").is_file() for m in models)
    assert not [p for p in out.rglob("*") if ".facet-" in p.name]


@pytest.mark.slow
def test_a_local_ray_cluster_writes_the_same_files(tmp_path, ray_cluster):
    models = make_models(tmp_path / "models", 5)
    manifest = write_manifest(tmp_path, [{"model": f"models/{m.name}"} for m in models],
                              {"size": [48, 48], "views": {"plan": "random", "count": 3,
                                                          "seed": 11}})
    local = render_dataset(manifest, tmp_path / "local")
    on_ray = render_dataset(manifest, tmp_path / "ray", ray=True)
    assert local["done"] == on_ray["done"] == 5 and on_ray["failed"] == 0
    files = sorted(p.relative_to(tmp_path / "local")
                   for p in (tmp_path / "local").rglob("*.*") if p.suffix in (".png", ".npy"))
    assert len(files) == 5 * 3 * 3
    for rel in files:
        assert (tmp_path / "local" / rel).read_bytes() == (tmp_path / "ray" / rel).read_bytes()


def test_a_gpu_that_does_not_exist_stops_the_run_with_one_error(tmp_path, capsys):
    """--gpus 99: the workers cannot make their renderer; the run stops at once with the
    EGL device's error (not a CPU in its place, not a pool restarting workers for ever)."""
    make_models(tmp_path / "models", 2)
    manifest = write_manifest(tmp_path, [{"model": "models/m00.ply"}, {"model": "models/m01.ply"}])
    start = time.time()
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "--gpus", "99",
                 "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "on EGL device 99" in err and "Traceback" not in err
    assert time.time() - start < 30
    assert not list((tmp_path / "out").rglob("*.png"))


@pytest.mark.slow
def test_a_worker_killed_mid_run_does_not_stop_or_hang_the_run(tmp_path):
    """A worker process dies (as one killed for memory by a huge model would): the jobs it
    had are tried again, alone, and the run finishes with every job done."""
    # m00 and m05 have 600 views: one worker is on m00 and the other on a short job or on
    # m05 when this test, looking late on a loaded machine, kills a worker (with 40 views a
    # look ~1 s late could find no worker left, or m00 alone: it would fail as the culprit).
    long = {"views": {"plan": "sphere", "count": 600}}
    models, out, proc = _start_batch(tmp_path, 6, views=40, workers=2,
                                     own={"m00": long, "m05": long})
    end = time.time() + 60
    while time.time() < end and len(list(out.glob("*/images/*.png"))) < 5:
        time.sleep(0.05)
    workers = _workers(proc)
    assert workers, "no worker processes found"
    os.kill(workers[0], signal.SIGKILL)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err.decode()
    index = [json.loads(line) for line in (out / "index.jsonl").open()]
    assert {r["job"] for r in index if r["status"] == "done"} == {m.stem for m in models}
    assert all((out / m.stem / "transforms.json").is_file() for m in models)


@pytest.mark.slow
def test_ray_actors_that_cannot_render_stop_the_run_with_their_error(tmp_path, monkeypatch,
                                                                   ray_cluster):
    """An actor whose renderer cannot be made (here: a wrong backend name, as a bad GPU or
    a node without GL would) stops the run with that error, not retries and a vague
    "lost its worker"; more GPU actors than the cluster has GPUs is one error up front. The
    cluster was started before the setting: it reaches the actors from the driver."""
    make_models(tmp_path / "models", 2)
    manifest = write_manifest(tmp_path, [{"model": "models/m00.ply"}, {"model": "models/m01.ply"}])
    with pytest.raises(InputError, match=r"the Ray cluster has \d+ GPU"):
        render_dataset(manifest, tmp_path / "gpu", ray=True, gpus=[0], workers=64)
    monkeypatch.setenv("FACET_GL_BACKEND", "vulkan")  # (sent to the actors by the runner)
    with pytest.raises(InputError, match="unknown OpenGL backend 'vulkan'"):
        render_dataset(manifest, tmp_path / "out", ray=True)


@pytest.mark.slow
def test_a_job_that_kills_its_worker_every_time_fails_alone(tmp_path):
    """A job whose worker dies each time it runs it (as a model too large for memory
    would; here the test kills the worker whenever the job writes a view) is found by
    running the suspects alone, fails with its one line, and the others are done."""
    # This loop can look late on a loaded machine (CI once saw m02 only after every other
    # job had finished: m02 was alone at its first death, and failed at once). So m02 has so
    # many views that no attempt at it ends before this loop sees it, and m03, which starts
    # beside it, has enough (about 5 s of rendering) to be still in flight when the loop
    # sees m02's first view late. m02's views cost nothing: each attempt dies at its first.
    models, out, proc = _start_batch(tmp_path, 5, views=30, workers=2,
                                     own={"m02": {"views": {"plan": "sphere", "count": 6000}},
                                          "m03": {"views": {"plan": "sphere", "count": 1000}}})
    killed, last = 0, 0.0
    end = time.time() + 120
    while proc.poll() is None and time.time() < end:
        view = out / "m02" / "images" / "0000.png"
        stamp = view.stat().st_mtime if view.exists() else 0.0
        if stamp > last:  # m02 is being rendered (again): its worker dies
            for k in _workers(proc):
                os.kill(k, signal.SIGKILL)
            killed, last = killed + 1, stamp
        time.sleep(0.01)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1 and b"Traceback" not in err, err.decode()
    assert killed >= 2  # in company first, then alone
    index = {r["job"]: r for r in map(json.loads, (out / "index.jsonl").open())}
    assert index["m02"]["status"] == "failed" and "worker process died" in index["m02"]["error"]
    assert all(index[m.stem]["status"] == "done" for m in models if m.stem != "m02")


def test_zero_workers_is_an_error(tmp_path, capsys):
    make_models(tmp_path / "models", 1)
    manifest = write_manifest(tmp_path, [{"model": "models/m00.ply"}])
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "--workers", "0"]) == 2
    assert "--workers must be at least 1, got 0" in capsys.readouterr().err


_STARTED: list = []  # the batches a test started: stopped at its end, however it ended


@pytest.fixture(autouse=True)
def _stop_started_batches():
    """A test that fails while its batch runs (a timeout) stops it and its workers: a
    hung run once outlived its test by an hour."""
    yield
    while _STARTED:
        proc = _STARTED.pop()
        if proc.poll() is None:
            for pid in [*child_pids(proc.pid), proc.pid]:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            proc.wait(timeout=30)


def _start_batch(tmp_path, n: int, views: int, workers: int, own: dict | None = None):
    """(models, output folder, process) of `facet batch` started on ``n`` generated models
    with ``views`` views each at 96x96 and ``workers`` worker processes; ``own``: a job's
    own settings, by model name."""
    models = make_models(tmp_path / "models", n)
    own = own or {}
    manifest = write_manifest(tmp_path, [{"model": f"models/{m.name}", **own.get(m.stem, {})}
                                         for m in models],
                              {"size": [96, 96], "views": {"plan": "sphere", "count": views}})
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    proc = subprocess.Popen([sys.executable, "-m", "facet", "batch", str(manifest), "-o",
                             str(out), "--workers", str(workers), "-q"], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    _STARTED.append(proc)
    return models, out, proc


def _workers(proc) -> list[int]:
    """The worker processes (spawned Pythons) of a running `facet batch`."""
    return [k for k in child_pids(proc.pid)
            if b"spawn_main" in Path(f"/proc/{k}/cmdline").read_bytes()]


@pytest.mark.slow
def test_a_script_without_a_main_guard(tmp_path):
    """One worker renders in the calling process, so a script without
    `if __name__ == "__main__":` (or a notebook) makes its dataset through `import facet`.
    More workers are spawned, and import the calling script again: such a script cannot
    start them, and the run stops at once saying so (not a pool retrying every job)."""
    make_models(tmp_path / "models", 3)
    manifest = write_manifest(tmp_path, [{"model": f"models/m0{i}.ply"} for i in range(3)],
                              {"size": [32, 32], "views": 2})
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    for workers, out in ((1, "one"), (2, "two")):
        script = tmp_path / f"make_{out}.py"
        script.write_text("import facet\n"
                          f"facet.batch.render_dataset({str(manifest)!r}, "
                          f"{str(tmp_path / out)!r}, workers={workers})\n")
        start = time.time()
        run = subprocess.run([sys.executable, str(script)], env=env, capture_output=True,
                             text=True, timeout=120)
        if workers == 1:
            assert run.returncode == 0, run.stderr
            assert len(list((tmp_path / out).rglob("images/*.png"))) == 3 * 2
        else:
            assert run.returncode != 0 and time.time() - start < 60
            assert 'if __name__ == "__main__":' in run.stderr.splitlines()[-1]
            assert not list((tmp_path / out).rglob("*.png"))
