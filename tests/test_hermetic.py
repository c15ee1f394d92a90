"""The hermetic check itself (tests/hermetic.py): it sees a new file, in a new folder or
deep down, and leaves out only the environments and Python's bytecode; the tests run with a
home of their own, not the user's."""

import os
from pathlib import Path

import hermetic


def test_a_new_file_is_found_and_named_once_per_new_folder(tmp_path, monkeypatch):
    monkeypatch.setattr(hermetic, "CHECKOUT", tmp_path)
    monkeypatch.setattr(hermetic, "HOME", Path("/"))  # (not read: the checkout only)
    (tmp_path / "app").mkdir()
    before = hermetic.snapshot(hermetic.SHALLOW)
    (tmp_path / "facet-20261206-060121.png").write_bytes(b"x")  # a screenshot
    (tmp_path / "out" / "deep").mkdir(parents=True)
    (tmp_path / "out" / "deep" / "a.npy").write_bytes(b"x")
    (tmp_path / ".venv" / "cache").mkdir(parents=True)  # the environment: allowed
    (tmp_path / ".venv" / "cache" / "x").write_bytes(b"x")
    (tmp_path / "app" / "__pycache__").mkdir()  # Python's bytecode: allowed
    found = hermetic.new_entries(before, hermetic.snapshot(hermetic.SHALLOW))
    assert found == [str(tmp_path / "facet-20261206-060121.png"), str(tmp_path / "out")]


def test_the_full_listing_sees_what_the_shallow_one_cannot(tmp_path, monkeypatch):
    monkeypatch.setattr(hermetic, "CHECKOUT", tmp_path)
    monkeypatch.setattr(hermetic, "HOME", Path("/"))
    deep = tmp_path / "a" / "b" / "c"
    deep.mkdir(parents=True)
    shallow, full = hermetic.snapshot(hermetic.SHALLOW), hermetic.snapshot(None)
    (deep / "d.txt").write_text("x")
    assert hermetic.new_entries(shallow, hermetic.snapshot(hermetic.SHALLOW)) == []
    assert hermetic.new_entries(full, hermetic.snapshot(None)) == [str(deep / "d.txt")]


def test_the_tests_home_is_not_the_users():
    assert Path(os.environ["HOME"]) != hermetic.HOME
    assert Path(os.environ["HOME"]).is_relative_to(Path(os.environ["MESA_SHADER_CACHE_DIR"])
                                                   .parent)
    assert hermetic.HOME == Path(os.environ["FACET_USER_HOME"])
