"""Atomic output files (facet.image.writers): temporary names, and what dead runs left."""

import os
import subprocess
import sys

import numpy as np
from PIL import Image

from facet.image.writers import save_array, save_image


def test_left_overs_of_dead_runs_are_removed_and_live_ones_kept(tmp_path):
    """A run killed outright leaves ``.NAME.facet-PID-...`` files; the next run writing
    into that folder removes those whose process is gone (once per folder), never a live
    process's."""
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True).stdout.strip()
    stale = [tmp_path / f".a.png.facet-{dead}-x1.tmp", tmp_path / f".b.npy.facet-{dead}-x2.tmp"]
    live = tmp_path / f".c.png.facet-{os.getpid()}-x3.tmp"
    for p in (*stale, live):
        p.write_bytes(b"partial")
    image = np.full((3, 4, 3), 200, np.uint8)
    save_image(tmp_path / "new.png", image)
    assert not any(p.exists() for p in stale) and live.exists()
    save_array(tmp_path / "d.npy", np.arange(3.0))
    assert sorted(p.name for p in tmp_path.iterdir()) == [live.name, "d.npy", "new.png"]
    with Image.open(tmp_path / "new.png") as img:
        np.testing.assert_array_equal(np.asarray(img), image)
