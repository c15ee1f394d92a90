"""Shared fixtures: renderers over real headless EGL (cached per size), the GL error check
after each test, small meshes, and the real-world models folder; the suite's hermetic
check (tests/hermetic.py) and the persistent caches it keeps in the environment."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SHARED_MODELS = ROOT.parent / "shared" / "models"
SHARED_GLTF = ROOT.parent / "shared" / "gltf"  # Khronos glTF samples
sys.path.insert(0, str(Path(__file__).resolve().parent))  # tests/reference.py

# Caches that outlive a run live in the environment (.venv), never in the home folder nor
# the checkout: Mesa's compiled shaders (a warm cache halves the suite's time on llvmpipe)
# and Hypothesis's examples and tables. Set before any GL context, and inherited by every
# process the tests start (the CLI, servers, JupyterLab's kernel). Mesa makes no parent
# folder (it says so on stderr, once per process, and caches nothing).
CACHES = Path(sys.prefix) / "cache"
os.environ.setdefault("MESA_SHADER_CACHE_DIR", str(CACHES / "mesa-shader-cache"))
os.environ.setdefault("HYPOTHESIS_STORAGE_DIRECTORY", str(CACHES / "hypothesis"))
# The tools the tests drive write into $HOME whatever they are told (Dr.Jit's kernel cache
# under Mitsuba, Ray's token, Chromium's crash folder, IPython's profile): the tests run with
# a home of their own in the environment (kept: Dr.Jit's cache stays warm); tests/hermetic.py
# watches the user's real one (FACET_USER_HOME, set by the first process, inherited).
os.environ.setdefault("FACET_USER_HOME", str(Path.home()))
os.environ["HOME"] = str(CACHES / "home")
for _folder in ("MESA_SHADER_CACHE_DIR", "HYPOTHESIS_STORAGE_DIRECTORY", "HOME"):
    Path(os.environ[_folder]).mkdir(parents=True, exist_ok=True)

from hermetic import hermetic_test, pytest_sessionfinish, pytest_sessionstart  # noqa: E402, F401


def _hypothesis_profile() -> None:
    try:
        from hypothesis import settings
        from hypothesis.configuration import set_hypothesis_home_dir
        from hypothesis.database import DirectoryBasedExampleDatabase
    except ImportError:
        return
    home = Path(os.environ["HYPOTHESIS_STORAGE_DIRECTORY"])
    set_hypothesis_home_dir(home)  # (its tables: constants, unicode data)
    settings.register_profile("facet", database=DirectoryBasedExampleDatabase(
        str(home / "examples")))
    settings.load_profile("facet")


_hypothesis_profile()


SLOW_TESTS = Path(__file__).with_name("slow_tests.txt")  # the slow tier (tools/tiers.py)


@pytest.hookimpl(tryfirst=True)  # (before -m "not slow" deselects)
def pytest_collection_modifyitems(config, items):
    """Mark the slow tier's tests (tests/slow_tests.txt, made from measured durations)."""
    listed = {line.strip() for line in SLOW_TESTS.read_text().splitlines()
              if line.strip() and not line.startswith("#")}
    for item in items:
        if item.nodeid in listed:
            item.add_marker(pytest.mark.slow)


def pytest_addoption(parser):
    parser.addoption("--regen-golden", action="store_true",
                     help="rewrite tests/golden/*.png from the current renderer (llvmpipe only)")


# What ../shared is, for every skip that needs it.
SHARED_NOTE = ("../shared, beside the repository, holds the real-world corpora the tests use "
               "when present (meshes, Khronos glTF samples, Shadertoy shaders, each with its "
               "licence); a plain clone has none, and these tests skip")


def shared_model(name: str, folder: Path = SHARED_MODELS) -> Path:
    """A file of ../shared (models/, or gltf/ with ``folder=SHARED_GLTF``); the test skips
    with the reason when the folder is absent."""
    path = folder / name
    if not path.is_file():
        pytest.skip(f"real-world file {name} not found in {folder}: {SHARED_NOTE}")
    return path


@pytest.fixture(scope="session")
def _renderer_pool():
    from facet.render.renderer import Renderer

    pool: dict[tuple[int, int, int], Renderer] = {}

    def get(width: int, height: int, msaa: int = 0) -> Renderer:
        key = (width, height, msaa)
        if key not in pool:
            pool[key] = Renderer(width, height, msaa=msaa)
        return pool[key]

    yield get
    for r in pool.values():
        r.close()


@pytest.fixture
def renderer(_renderer_pool):
    """``renderer(w, h, msaa=0)`` -> a Renderer; after the test, GL must report no error."""
    used = []

    def get(width: int, height: int, msaa: int = 0):
        r = _renderer_pool(width, height, msaa)
        used.append(r)
        return r

    yield get
    for r in used:
        assert r.gl_error() == "GL_NO_ERROR"


def bare_env(**extra) -> dict:
    """A child's environment as a user's clean shell gives it (PATH, facet's source on
    PYTHONPATH) with the test session's home and caches (a child given no HOME finds the
    user's through the password file, and Mesa would cache there: tests/hermetic.py)."""
    session = ("HOME", "FACET_USER_HOME", "MESA_SHADER_CACHE_DIR",
               "HYPOTHESIS_STORAGE_DIRECTORY")
    return {"PYTHONPATH": str(ROOT / "app"), "PATH": "/usr/bin:/bin",
            **{k: os.environ[k] for k in session}, **extra}


RAY_STARTS = 3  # tries at starting the local Ray cluster (each bounded by Ray at 30 s)


@pytest.fixture(scope="session")
def ray_cluster():
    """A local Ray cluster, started once per test process and shut down at its end; the
    batch runner uses the running one (facet.batch.ray_runner). Ray gives its raylet 30 s
    to register, which a loaded 2-core machine can miss: a start that timed out is tried
    again, RAY_STARTS times at most."""
    ray = pytest.importorskip("ray", reason="the ray extra is not installed")
    for attempt in range(RAY_STARTS):
        try:
            ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False,
                     configure_logging=False)
            break
        except Exception as exc:  # (Ray raises a bare Exception for this one)
            ray.shutdown()
            if "timed out during startup" not in str(exc) or attempt == RAY_STARTS - 1:
                raise
    yield ray
    ray.shutdown()


def both_ways(owner, attribute: str, render) -> tuple:
    """``render()`` with the class flag ``owner.attribute`` on, then off (restored on after):
    the two ways of a choice that must draw alike."""
    out = {}
    for on in (True, False):
        setattr(owner, attribute, on)
        try:
            out[on] = render()
        finally:
            setattr(owner, attribute, True)
    return out[True], out[False]


def sphere_mesh(subdivisions: int = 6, radius: float = 1.0):
    """A fine icosphere with exact sphere normals (positions / radius)."""
    import trimesh

    from facet.scene.mesh import Mesh

    ico = trimesh.creation.icosphere(subdivisions=subdivisions)
    v = np.asarray(ico.vertices) / np.linalg.norm(ico.vertices, axis=1, keepdims=True)
    return Mesh(v * radius, ico.faces, v, name="icosphere")


def quad_mesh(size: float = 1.0, z: float = 0.0):
    """A square in the z = ``z`` plane facing +z, side 2 * size."""
    from facet.scene.mesh import Mesh

    s = size
    pos = [[-s, -s, z], [s, -s, z], [s, s, z], [-s, s, z]]
    return Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4, name="quad")
