"""The suite is hermetic: no test leaves a new file in the checkout or in the user's home.

Two checks (tests/conftest.py installs both):

- after each test, a shallow listing (three levels) of the checkout and of the home folder
  is compared with the one taken before it: a new entry fails that test, naming it. Under
  pytest-xdist a test running beside it in another process may be the writer; the message
  says so;
- at the end of the session, the controller compares a full listing of both with the one
  taken at its start and fails the run on any new file (what the shallow check cannot see).

Allowed: the virtual environments (``.venv*``, where the persistent caches live: Mesa's
shader cache, pytest's, Hypothesis's examples, and the home the tests run with) and
Python's own ``__pycache__`` folders beside its sources. Everything else a test writes goes
under its ``tmp_path`` or the system's temporary folder.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

CHECKOUT = Path(__file__).resolve().parents[1]
# The user's home: the tests run with one of their own (tests/conftest.py), which is not it.
HOME = Path(os.environ.get("FACET_USER_HOME") or Path.home())
# Entries no check descends into or reports: the environments and Python's bytecode.
ALLOWED = ("__pycache__",)
SHALLOW = 3  # levels the per-test listing reads


def _allowed(name: str, root: Path, parent: str) -> bool:
    if name in ALLOWED or (root == CHECKOUT and not parent and name == ".git"):
        return True
    return root == CHECKOUT and not parent and name.startswith(".venv")


def listing(root: Path, depth: int | None = None) -> set[str]:
    """Every entry under ``root`` (relative paths), ``depth`` levels deep (None: all),
    leaving out what ALLOWED names; symbolic links are listed, not followed."""
    out: set[str] = set()
    stack = [("", 0)]
    while stack:
        parent, level = stack.pop()
        try:
            entries = list(os.scandir(root / parent))
        except OSError:  # (gone meanwhile, or unreadable)
            continue
        for entry in entries:
            if _allowed(entry.name, root, parent):
                continue
            rel = f"{parent}/{entry.name}" if parent else entry.name
            out.add(rel)
            try:
                is_dir = entry.is_dir(follow_symlinks=False)
            except OSError:
                is_dir = False
            if is_dir and (depth is None or level + 1 < depth):
                stack.append((rel, level + 1))
    return out


def _roots() -> dict[str, Path]:
    roots = {"the checkout": CHECKOUT}
    # (a home inside the checkout, or the checkout inside home, is read once each way; a
    # home that is / is not read: nothing of a user's is kept there)
    if HOME != Path("/") and HOME.is_dir():
        roots["the home folder"] = HOME
    return roots


def snapshot(depth: int | None) -> dict[str, set[str]]:
    return {name: listing(root, depth) for name, root in _roots().items()}


def new_entries(before: dict[str, set[str]], after: dict[str, set[str]]) -> list[str]:
    """The entries ``after`` has that ``before`` had not, as paths to show."""
    roots = _roots()
    found = []
    for name, entries in after.items():
        added = entries - before.get(name, set())
        # a new folder's contents are one finding: the folder
        tops = sorted(a for a in added if not any(a.startswith(b + "/") for b in added))
        found += [str(roots[name] / a) for a in tops]
    return found


def _worker(config) -> bool:
    return hasattr(config, "workerinput")


@pytest.fixture(autouse=True)
def hermetic_test(request):
    """Fails a test after which the checkout or the home folder has a new entry."""
    before = snapshot(SHALLOW)
    yield
    found = new_entries(before, snapshot(SHALLOW))
    if found:
        beside = " (or a test running beside it in another process)" \
            if _worker(request.config) else ""
        pytest.fail(f"{request.node.nodeid}{beside} left files outside its temporary folder: "
                    f"{', '.join(found)}; write under tmp_path, or pass the folder to the "
                    "code under test", pytrace=False)


def pytest_sessionstart(session):
    if not _worker(session.config):
        session.config._facet_listing = snapshot(None)


def pytest_sessionfinish(session, exitstatus):
    before = getattr(session.config, "_facet_listing", None)
    if before is None:
        return
    found = new_entries(before, snapshot(None))
    if found:
        sys.stderr.write("\nhermetic: the test session left files in the checkout or the home "
                         "folder (tests/hermetic.py):\n" +
                         "".join(f"  {path}\n" for path in found))
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
