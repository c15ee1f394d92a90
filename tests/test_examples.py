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


def test_the_engines_example_without_the_denoiser_says_one_line(tmp_path):
    """examples/engines.py (linked from the README's top table) without the denoise extra:
    its picture with more samples and one line saying so (it ended in a traceback)."""
    import subprocess

    out = tmp_path / "engines.png"
    code = ("import sys, runpy; sys.modules['pyoidn'] = None; "
            f"sys.argv = ['engines.py', {str(out)!r}]; "
            f"runpy.run_path({str(ROOT / 'examples' / 'engines.py')!r}, run_name='__main__')")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300, env={**__import__("os").environ,
                                           "PYTHONPATH": str(ROOT / "app")})
    assert run.returncode == 0 and "Traceback" not in run.stderr, run.stderr
    lines = [line for line in run.stderr.splitlines() if "engines.py:" in line]
    assert len(lines) == 1 and "denoise" in lines[0]
    assert out.is_file()
