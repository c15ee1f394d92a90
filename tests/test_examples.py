"""The gallery's examples (examples/*.py) run as written from a fresh folder and make the
pictures the documentation shows (docs/examples/, the golden tolerance; `make docs` checks
the same through tools/gallery.py, which holds the comparison)."""

import sys

import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "tools"))
import gallery  # noqa: E402


@pytest.mark.parametrize("script", gallery.scripts(), ids=lambda p: p.stem)
def test_an_example_makes_its_picture(script, tmp_path, renderer):
    if "llvmpipe" not in renderer(8, 8).info["renderer"]:
        pytest.skip("the stored pictures are made on llvmpipe")
    picture = gallery.run(script, tmp_path)
    assert gallery.problems(picture, gallery.STORED / picture.name) is None


def test_the_gallery_page_is_current():
    """docs/gallery.md is what tools/gallery.py writes from the scripts' docstrings."""
    assert (ROOT / "docs" / "gallery.md").read_text() == gallery.page()


def test_a_blank_or_different_picture_is_caught(tmp_path):
    import numpy as np
    from PIL import Image

    stored = gallery.STORED / "quickstart.png"
    blank = tmp_path / "blank.png"
    Image.new("RGB", (32, 32), (255, 255, 255)).save(blank)
    assert gallery.problems(blank, stored) == "blank"
    shifted = tmp_path / "shifted.png"
    Image.fromarray(np.roll(np.asarray(Image.open(stored).convert("RGB")), 8, axis=1)).save(
        shifted)
    assert "of pixels differ" in gallery.problems(shifted, stored)
