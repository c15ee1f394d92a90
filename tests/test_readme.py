"""The documented commands run as written (the README's and every docs/ page's): every
`facet ...` line of their shell blocks parses
(no unknown option, no usage error), every file it reads is in the repository, and every
one that writes files and needs nothing this machine lacks (a window, GPUs, a Ray
cluster) runs from a fresh folder holding the repository's files, exits 0 and writes."""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

README = ROOT / "README.md"
# The documented commands: the README's and every page of the documentation site's.
PAGES = [README, *sorted((ROOT / "docs").rglob("*.md"))]
NEEDS = ("--ray", "--gpus")  # a cluster, several GPUs


def commands() -> list[list[str]]:
    """Each `facet ...` / `python -m facet ...` line of the README's sh blocks, as argv
    after the program name (continued lines joined, comments dropped)."""
    out = []
    blocks = [b for page in PAGES for b in re.findall(r"```sh\n(.*?)```", page.read_text(),
                                                      re.S)]
    for block in blocks:
        for line in block.replace("\\\n", " ").splitlines():
            argv = shlex.split(line, comments=True)
            if argv[:1] == ["facet"]:
                argv = argv[1:]
            elif argv[:3] == ["python", "-m", "facet"]:
                argv = argv[3:]
            else:
                continue
            if argv not in out:
                out.append(argv)
    return out


def test_the_readme_has_commands():
    assert len(commands()) >= 20


def test_the_readme_is_short_and_its_links_exist():
    """The README is the front page (at most ~250 lines); the guide is in docs/."""
    text = README.read_text()
    assert len(text.splitlines()) <= 250
    for target in re.findall(r"\]\(([^)#:]+)\)", text):
        assert (ROOT / target).exists(), f"README links to {target}: not in the repository"


def _inputs(args) -> list[str]:
    """The files a parsed command reads."""
    found = []
    for name in ("model", "shader", "manifest", "frag", "vert", "texture", "env", "media",
                 "buffer_a", "buffer_b", "buffer_c", "buffer_d", "cube_a", "common"):
        value = getattr(args, name, None)
        if isinstance(value, str) and value not in ("checker", "sky"):
            found.append(value)
    return found


@pytest.mark.parametrize("argv", commands(), ids=" ".join)
def test_every_command_parses_and_its_files_exist(argv):
    from facet.cli import parse_args

    args, problem = parse_args(argv)
    assert problem is None, problem
    for name in _inputs(args):
        if any(c in name for c in "*?["):
            assert list(ROOT.glob(name)), name  # a glob matches something
        else:
            assert (ROOT / name).exists(), f"{name}: not in the repository"


def _runs_here(argv) -> bool:
    if any(a in NEEDS for a in argv) or argv[0] == "view":
        return False
    if argv[0] == "shader":  # without an output it opens a window
        return "-o" in argv or "--list-uniforms" in argv
    return argv[0] in ("render", "batch", "info")


@pytest.mark.slow
def test_the_commands_run_as_written(tmp_path):
    for name in ("models", "examples", "glsl"):
        (tmp_path / name).symlink_to(ROOT / name)
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    ran = 0
    def files():
        return {p: p.stat().st_mtime_ns for p in tmp_path.rglob("*") if p.is_file()}

    for argv in filter(_runs_here, commands()):
        before = files()
        run = subprocess.run([sys.executable, "-m", "facet", *argv], cwd=tmp_path, env=env,
                             capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, (argv, run.stderr)
        assert "Traceback" not in run.stderr, run.stderr
        if argv[0] != "info" and "--list-uniforms" not in argv:
            assert files().items() - before.items(), f"{argv} wrote nothing"
        ran += 1
    assert ran >= 15
    assert not [p for p in tmp_path.iterdir() if p.is_symlink() and not p.exists()]
    assert Path(tmp_path / "dataset" / "index.jsonl").is_file()


@pytest.mark.slow
def test_the_readmes_python_runs_as_written(tmp_path):
    """Each python block of the README that opens no window runs from a folder holding the
    repository's models, and the picture it saves is there."""
    blocks = [b for b in re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
              if "facet.show" not in b and "facet.view" not in b]
    assert blocks
    (tmp_path / "models").symlink_to(ROOT / "models")
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    for block in blocks:
        run = subprocess.run([sys.executable, "-c", block], cwd=tmp_path, env=env,
                             capture_output=True, text=True, timeout=300)
        assert run.returncode == 0, run.stderr
    assert (tmp_path / "torus.png").is_file()
