"""``facet render``'s progress line for the work before the samples: loading a large model
and preparing it for an engine (its hierarchy, its upload) each show their seconds so far
on a terminal, and nothing shows with --quiet or when stderr is not a terminal
(FACET_PROGRESS_DELAY=0: the line from the first tick, not after 2 s)."""

import os
import pty
import re
import subprocess

import numpy as np
import pytest
import trimesh

from test_sample_budget import FACET, _read_until

from conftest import ROOT


@pytest.fixture(scope="module")
def big_obj(tmp_path_factory):
    """An OBJ of 327,680 triangles (13 MB: about a second to load here)."""
    path = tmp_path_factory.mktemp("big") / "big.obj"
    ico = trimesh.creation.icosphere(subdivisions=7)
    v, f = np.asarray(ico.vertices), np.asarray(ico.faces) + 1
    with open(path, "w") as out:
        np.savetxt(out, v, fmt="v %.6f %.6f %.6f")
        np.savetxt(out, f, fmt="f %d %d %d")
    return path


def _render(path, out, *extra, terminal: bool):
    env = dict(os.environ, PYTHONPATH=str(ROOT / "app"), FACET_PROGRESS_DELAY="0")
    args = [*FACET, "render", str(path), "-o", str(out), "--engine", "path", "--spp", "2",
            "--size", "64x64", *extra]
    if not terminal:
        return subprocess.run(args, capture_output=True, text=True, env=env, timeout=300)
    master, slave = pty.openpty()
    proc = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=slave, stderr=slave,
                            env=env)
    os.close(slave)
    shown = _read_until(master, "\0", 300)  # (all it shows, until it exits)
    proc.wait(60)
    os.close(master)
    return proc.returncode, shown


def test_loading_and_preparing_a_large_model_show_progress_on_a_terminal(big_obj, tmp_path):
    code, shown = _render(big_obj, tmp_path / "a.png", terminal=True)
    assert code == 0, shown
    assert re.search(r"\x1b\[Kfacet: loading big\.obj \(1\d MB\), \d+\.\d s", shown), shown
    assert re.search(r"facet: rendering 327,680 triangles \(path\), \d+\.\d s", shown), shown
    assert "\x1b[K" + str(tmp_path / "a.png") in shown, shown  # (the line cleared first)


def test_no_progress_with_quiet_or_without_a_terminal(big_obj, tmp_path):
    code, shown = _render(big_obj, tmp_path / "b.png", "-q", terminal=True)
    assert code == 0 and "loading" not in shown and "rendering" not in shown, shown
    done = _render(big_obj, tmp_path / "c.png", terminal=False)
    assert done.returncode == 0, done.stderr
    assert "loading" not in done.stderr and "\x1b[K" not in done.stderr, done.stderr
