"""facet's resource budgets (facet.budgets): stated once, printed by `facet info`, listed
in the docs (docs/guide/untrusted-input.md), raised or lowered by `facet --budget NAME=VALUE`
and FACET_BUDGET_NAME, and each one enforced where the input meets it."""

import re
from pathlib import Path

from facet.budgets import BUDGETS
from hostile import facet, refused

from conftest import bare_env

ROOT = Path(__file__).resolve().parents[1]
CUBE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def test_info_prints_every_budget(tmp_path):
    code, _ = facet("info")
    assert code == 0
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-m", "facet", "--budget", "objects=7", "info"],
                         capture_output=True, text=True, check=True,
                         env=bare_env()).stdout
    printed = dict(re.findall(r"^budget\.(\w+)\s+(\d+)", out, re.M))
    assert printed == {name: str(7 if name == "objects" else default)
                       for name, (default, _) in BUDGETS.items()}


def test_the_docs_list_the_budgets_as_they_are():
    page = ROOT / "docs" / "guide" / "untrusted-input.md"
    text = page.read_text().split("## Budgets")[1].split("\n## ")[0]
    rows = dict(re.findall(r"^ *\| `(\w+)` \| ([^|]+) \|", text, re.M))
    assert set(rows) == set(BUDGETS)
    spelled = {"file_bytes": "2 GiB", "elements": "2^28", "shader_bytes": "1 MiB"}
    for name, (default, _) in BUDGETS.items():
        assert rows[name].split(" (")[0].strip() in (f"{default:,}", spelled.get(name)), name
    assert BUDGETS["file_bytes"][0] == 2 << 30 and BUDGETS["elements"][0] == 1 << 28
    assert BUDGETS["shader_bytes"][0] == 1 << 20


def test_budgets_are_raised_and_lowered_per_run(tmp_path):
    (tmp_path / "m.obj").write_text(CUBE)
    (tmp_path / "s.toml").write_text('[[objects]]\nprimitive = "cube"\n' * 3)
    refused(facet("--budget", "objects=2", "render", "s.toml", "-o", "o.png", cwd=tmp_path),
            "3 objects", "budget of 2")
    refused(facet("render", "s.toml", "-o", "o.png", cwd=tmp_path,
                  env={"FACET_BUDGET_OBJECTS": "2"}), "budget of 2")
    refused(facet("--budget", "pixels=100", "render", "m.obj", "--size", "20x20", "-o",
                  "o.png", cwd=tmp_path), "20x20", "megapixels")
    code, err = facet("--budget", "objects=3", "render", "s.toml", "-o", "o.png",
                      "--size", "16x16", cwd=tmp_path)
    assert code == 0, err
    refused(facet("--budget", "nope=3", "info"), "--budget 'nope=3'")
    refused(facet("--budget", "pixels=-3", "info"), "whole number >= 1")
    refused(facet("info", cwd=tmp_path, env={"FACET_BUDGET_DEPTH": "lots"}),
            "FACET_BUDGET_DEPTH")


def test_json_nesting_is_counted_before_parsing(tmp_path):
    """The depth budget holds JSON too: counted outside strings (brackets in names and
    escaped quotes do not count), so a document 1,001 deep is refused before the parser
    (whose own recursion guard stops near 1,000) and one 900 deep is read."""
    from facet.guard import json_depth

    assert json_depth('{"a": [1, {"b": "[[[\\" ]]"}]}') == 3
    assert json_depth('["]]]]", [[1]]]') == 3 and json_depth('["[[[[", [1]]') == 2
    assert json_depth(b"") == 0 and json_depth("[[]]", within=5) <= 5
    model = tmp_path / "m.obj"
    model.write_text(CUBE)
    for depth, ok in ((900, True), (1001, False)):
        extras = "[" * (depth - 3) + "]" * (depth - 3)  # inside {"jobs": [{..., "x": ...}]}
        (tmp_path / "m.json").write_text('{"jobs": [{"model": "m.obj", "views": 1, '
                                         f'"size": [8, 8], "colmap": false, "x": {extras}}}]}}')
        code, err = facet("batch", "m.json", "-o", "ds", "-q", cwd=tmp_path)
        if ok:  # read, then refused for its unknown key: past the depth check
            assert code == 2 and "unknown key 'x'" in err, err
        else:
            refused((code, err), "m.json", "more than 1,000 levels deep")
