"""Headless backends: OSMesa draws the same bytes as EGL (the example scene with shadows,
MSAA and every channel; a batch run), a machine without EGL falls back to OSMesa and
``facet info`` says so, and a wrong backend name is one error. Skips with the reason where
libOSMesa is not installed (Debian/Ubuntu: libosmesa6; Mesa 25.1 and later have none)."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from facet.formats import load_scene
from facet.gl import osmesa
from facet.gl.context import create_headless
from facet.options.render import OUTPUTS
from facet.render.frame import CHANNELS
from facet.render.renderer import Renderer

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(
    osmesa.library() is None,
    reason=f"libOSMesa is not installed ({osmesa.INSTALL_HINT}; Mesa 25.1+ ships none)")


def _render(backend: str):
    scene = load_scene(ROOT / "models" / "example.toml")
    with Renderer(160, 120, msaa=4, backend=backend, shadows=True) as r:
        assert r.info["backend"] == backend
        frame = r.render(scene, scene.camera("main"), outputs=OUTPUTS)
        return {k: np.array(getattr(frame, k)) for k in ("color", *CHANNELS)}


def test_osmesa_draws_the_bytes_egl_draws():
    egl, mesa = _render("egl"), _render("osmesa")
    assert egl["color"].std() > 10  # a picture, not a cleared frame
    for key in egl:
        assert egl[key].tobytes() == mesa[key].tobytes(), key


def test_a_batch_through_osmesa_writes_the_files_egl_writes(tmp_path, monkeypatch):
    import json

    import trimesh

    from facet.batch import render_dataset

    (tmp_path / "m").mkdir()
    for i, mesh in enumerate([trimesh.creation.icosphere(2), trimesh.creation.box()]):
        mesh.export(tmp_path / "m" / f"{i}.ply")
    manifest = tmp_path / "d.jsonl"
    manifest.write_text("\n".join(json.dumps(j) for j in [
        {"defaults": {"size": [40, 40], "views": {"plan": "random", "count": 2, "seed": 3}}},
        {"model": "m/0.ply"}, {"model": "m/1.ply"}]) + "\n")
    render_dataset(manifest, tmp_path / "egl")
    monkeypatch.setenv("FACET_GL_BACKEND", "osmesa")  # the workers inherit it
    assert render_dataset(manifest, tmp_path / "osmesa")["done"] == 2
    files = [p for p in (tmp_path / "egl").rglob("*.*") if p.suffix in (".png", ".npy")]
    assert len(files) == 2 * 2 * 3
    for a in files:
        b = tmp_path / "osmesa" / a.relative_to(tmp_path / "egl")
        assert a.read_bytes() == b.read_bytes(), a


def _facet(args, **env):
    return subprocess.run([sys.executable, "-m", "facet", *args], capture_output=True,
                          text=True, timeout=60,
                          env={**os.environ, "PYTHONPATH": str(ROOT / "app"), **env})


def test_without_egl_facet_falls_back_to_osmesa_and_says_so(tmp_path):
    no_egl = {"GLCONTEXT_LINUX_LIBEGL": "/nonexistent/libEGL.so"}  # as if EGL were absent
    run = _facet(["info"], **no_egl)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines()[0].split() == ["backend", "osmesa"]
    assert run.stderr.count("\n") == 1 and "rendering through OSMesa" in run.stderr
    # Asked for EGL alone, the same machine gets one error naming what to install.
    run = _facet(["info"], FACET_GL_BACKEND="egl", **no_egl)
    assert run.returncode != 0 and "Traceback" not in run.stderr
    assert "through EGL" in run.stderr and "libegl1" in run.stderr
    # And the default scene rendered by the fallback is the one EGL draws.
    from PIL import Image

    for name, env in (("osmesa", no_egl), ("egl", {})):
        run = _facet(["render", "-o", str(tmp_path / f"{name}.png"), "--size", "96x64"], **env)
        assert run.returncode == 0, run.stderr
    a, b = (np.asarray(Image.open(tmp_path / f"{n}.png")) for n in ("osmesa", "egl"))
    assert a.std() > 10 and np.array_equal(a, b)


def test_a_wrong_backend_name_is_one_error(monkeypatch):
    from facet.errors import InputError

    with pytest.raises(InputError, match="unknown OpenGL backend 'vulkan'; use one of auto"):
        create_headless(backend="vulkan")
    monkeypatch.setenv("FACET_GL_BACKEND", "nope")
    with pytest.raises(InputError, match="FACET_GL_BACKEND: unknown"):
        create_headless()
