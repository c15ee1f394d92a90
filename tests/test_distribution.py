"""The distribution's name: `facet` on the package index is an unrelated project (a
service manager for asyncio), so every `pip install 'facet[...]'` facet printed or
documented installed that one. facet is distributed as `facet-render` (`import facet` and
the `facet` command unchanged), and every install hint in app/, docs/ and the README
names it."""

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HINT = re.compile(r"pip install (?:-e )?['\"]?([A-Za-z0-9_.-]+)\[([a-z,]+)\]")


def _project():
    with open(ROOT / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["project"]


def test_the_distribution_is_not_the_unrelated_facet():
    project = _project()
    assert project["name"] == "facet-render"
    assert project["scripts"]["facet"] == "facet.cli:main"


def test_every_install_hint_names_the_distribution_and_a_real_extra():
    project = _project()
    extras = set(project["optional-dependencies"])
    files = [*(ROOT / "app").rglob("*.py"), *(ROOT / "docs").rglob("*.md"),
             ROOT / "README.md"]
    hints = []
    for path in files:
        for name, wanted in HINT.findall(path.read_text(encoding="utf-8")):
            if name in (".", "ray"):  # a clone's own ('.[serve]'), Ray's own ray[client]
                continue
            hints.append((path.name, name, wanted))
            assert name == project["name"], f"{path}: pip install '{name}[{wanted}]'"
            assert set(wanted.split(",")) <= extras, f"{path}: no extra {wanted!r}"
    assert len(hints) >= 10  # (the hints exist: exr, hdr, serve, notebook, denoise, ray)
