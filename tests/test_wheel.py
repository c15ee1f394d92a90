"""Packaging: the wheel carries the shaders and models; installed into a fresh virtual
environment (outside the checkout) it renders."""

import os
import subprocess
import sys
import sysconfig
import venv
import zipfile
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_wheel_installs_and_renders(tmp_path):
    pytest.importorskip("hatchling", reason="building the wheel needs hatchling (dev extra)")
    dist = tmp_path / "dist"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
                    "-q", "-w", str(dist), str(ROOT)], check=True, capture_output=True)
    wheel = next(dist.glob("facet_render-*.whl"))  # (the distribution: facet-render)
    names = set(zipfile.ZipFile(wheel).namelist())
    for needed in ("facet/glsl/lib/lighting.glsl", "facet/glsl/mesh/phong.frag",
                   "facet/models/default.obj", "facet/cli/__init__.py"):
        assert needed in names

    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    subprocess.run([str(py), "-m", "pip", "install", "-q", "--no-deps", "--no-index",
                    str(wheel)], check=True, capture_output=True)
    # Dependencies come from this test environment's site-packages (no network needed);
    # facet itself must come from the wheel.
    site = subprocess.run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()"
                           "['purelib'])"], capture_output=True, text=True, check=True)
    Path(site.stdout.strip(), "deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")

    work = tmp_path / "elsewhere"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    where = subprocess.run([str(py), "-c", "import facet.gl.glsl_source as g, facet; "
                            "print(facet.__file__); print(g.glsl_root())"],
                           cwd=work, capture_output=True, text=True, env=env, check=True)
    pkg_file, glsl_dir = where.stdout.split()
    assert pkg_file.startswith(str(env_dir)) and glsl_dir.startswith(str(env_dir))
    res = subprocess.run([str(env_dir / "bin" / "facet"), "render", "-o", "w.png", "--size",
                          "80x60"], cwd=work, capture_output=True, text=True, env=env)
    assert res.returncode == 0, res.stderr
    img = np.asarray(Image.open(work / "w.png"))
    assert img.shape == (60, 80, 3) and img.max() > 150 and (img.sum(axis=2) == 0).mean() > 0.3
