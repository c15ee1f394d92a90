"""The documentation's gallery: run every script in examples/, check each picture against the
stored one in docs/examples/ (non-blank, and within the golden tolerance of
tests/test_golden.py), and write docs/gallery.md from the scripts' docstrings.

    python tools/gallery.py OUT_DIR            # run, check, write the page (make docs)
    python tools/gallery.py OUT_DIR --regen    # run and store the pictures anew

Exit status 1 when a picture is blank or differs (each named, with its share of pixels).
"""

from __future__ import annotations

import argparse
import ast
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
STORED = ROOT / "docs" / "examples"
PAGE = ROOT / "docs" / "gallery.md"
sys.path.insert(0, str(ROOT / "tests"))
from test_golden import CHANNEL_TOL, MAX_DIFFERING  # noqa: E402 (one tolerance table)

MIN_STD = 4.0  # a picture with less spread than this (0-255) is blank


ORDER = ("quickstart", "depth_and_ids", "engines", "trimesh_scene", "colormap", "point_cloud",
         "splats", "animation", "usd_stage", "robot")  # the gallery's order; others by name


def scripts() -> list[Path]:
    found = [p for p in EXAMPLES.glob("*.py") if not p.name.startswith("_")]
    return sorted(found, key=lambda p: (ORDER.index(p.stem) if p.stem in ORDER else len(ORDER),
                                        p.name))


def run(script: Path, out: Path) -> Path:
    """Run one example from a folder of its own; returns its picture."""
    picture = out / f"{script.stem}.png"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "app")}
    subprocess.run([sys.executable, str(script), str(picture)], cwd=out, env=env, check=True,
                   timeout=600)
    return picture


def problems(picture: Path, stored: Path) -> str | None:
    """Why ``picture`` is not the stored one (None: it is)."""
    image = np.asarray(Image.open(picture).convert("RGB"))
    if image.std() < MIN_STD:
        return "blank"
    if not stored.exists():
        return f"no stored picture {stored.relative_to(ROOT)} (make it with --regen)"
    want = np.asarray(Image.open(stored).convert("RGB"))
    if want.shape != image.shape:
        return f"size {image.shape[1]}x{image.shape[0]}, stored {want.shape[1]}x{want.shape[0]}"
    share = float((np.abs(image.astype(int) - want).max(axis=2) > CHANNEL_TOL).mean())
    if share > MAX_DIFFERING:
        return f"{share:.2%} of pixels differ by more than {CHANNEL_TOL}/255"
    return None


def page() -> str:
    """docs/gallery.md: each example's docstring, picture and code."""
    rows = ["# Gallery", "",
            "Each example is a script in `examples/`; `make docs` runs them all and checks "
            "every picture against the one shown here (the golden tolerance of the test "
            "suite). Run one yourself: `python examples/quickstart.py out.png`.", ""]
    for script in scripts():
        doc = ast.get_docstring(ast.parse(script.read_text())) or script.stem
        title, _, rest = doc.partition("\n")
        rows += [f"## {title.rstrip('.')}", "", rest.strip(), "",
                 f"![{script.stem}](examples/{script.stem}.png)", "",
                 "```python", f'--8<-- "examples/{script.name}"', "```", ""]
    return "\n".join(rows).rstrip() + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="folder for the pictures made now")
    parser.add_argument("--regen", action="store_true", help="store the pictures anew")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    failed = []
    for script in scripts():
        picture = run(script, args.out.resolve())
        stored = STORED / picture.name
        if args.regen:
            STORED.mkdir(exist_ok=True)
            stored.write_bytes(picture.read_bytes())
        problem = problems(picture, stored)
        print(f"{script.name}: {problem or 'ok'}")
        if problem:
            failed.append(script.name)
    PAGE.write_text(page())
    if failed:
        print(f"gallery: {len(failed)} picture(s) differ: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
