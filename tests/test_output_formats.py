"""Single renders and sequences in other image formats: JPEG, WebP and TIFF through Pillow
(the 8-bit picture; --quality for the lossy ones), OpenEXR and Radiance HDR keeping the
render's linear float colour (the render keeps float colour for them); bad targets and
values are one line each, nothing written."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import facet
from facet.cli import main

from conftest import ROOT

MODEL = str(ROOT / "models" / "default.obj")


def _render(tmp_path, name, *extra):
    out = tmp_path / name
    assert main(["render", MODEL, "-o", str(out), "--size", "64x48", "--msaa", "0", "-q",
                 *extra]) == 0
    return out


@pytest.mark.parametrize("name, tolerance", [("x.jpg", 4.0), ("x.webp", 4.0),
                                             ("x.tif", 0.0)])
def test_eight_bit_formats_hold_the_png_picture(tmp_path, name, tolerance):
    png = np.asarray(Image.open(_render(tmp_path, "x.png")).convert("RGB")).astype(int)
    other = np.asarray(Image.open(_render(tmp_path, name)).convert("RGB")).astype(int)
    assert np.abs(other - png).mean() <= tolerance


def test_quality_trades_size_for_fidelity(tmp_path):
    low = _render(tmp_path, "low.jpg", "--quality", "10")
    high = _render(tmp_path, "high.jpg", "--quality", "98")
    assert low.stat().st_size < high.stat().st_size


def test_float_formats_keep_the_linear_float_colour(tmp_path):
    """The EXR holds what Renderer.render(float_color=True) returns, exactly; the HDR the
    same within its shared-exponent precision."""
    import OpenEXR

    scene = facet.load(MODEL)
    with facet.Renderer(64, 48) as r:
        want = r.render(scene, r.camera(scene, r.options(scene, size=(64, 48))),
                        float_color=True, msaa=0).color
    exr = _render(tmp_path, "x.exr")
    channels = OpenEXR.File(str(exr)).channels()
    got = channels["RGBA"].pixels if "RGBA" in channels else \
        np.stack([channels[c].pixels for c in "RGBA"], axis=-1)
    np.testing.assert_array_equal(got, want)
    assert want[..., :3].max() > 0.2
    hdr = _render(tmp_path, "x.hdr")
    import imageio.v3 as iio

    back = iio.imread(str(hdr), plugin="opencv", flags=-1)
    # RGBE: an 8-bit mantissa per channel under the pixel's largest channel's exponent.
    step = want[..., :3].max(axis=-1, keepdims=True) / 128.0 + 1e-6
    assert np.all(np.abs(back - want[..., :3]) <= step)


def test_sequences_number_any_of_the_formats(tmp_path):
    assert main(["render", MODEL, "-o", str(tmp_path / "f_{:02d}.jpg"), "--turntable", "2",
                 "--size", "32x24", "-q"]) == 0
    assert main(["render", MODEL, "-o", str(tmp_path / "g_{:02d}.exr"), "--turntable", "2",
                 "--size", "32x24", "-q"]) == 0
    assert sorted(p.name for p in tmp_path.glob("[fg]_*.*") if p.suffix != ".json") == [
        "f_00.jpg", "f_01.jpg", "g_00.exr", "g_01.exr"]


def test_a_transparent_picture_in_jpeg_says_so(tmp_path, capsys):
    _render(tmp_path, "t.jpg", "--background", "0,0,0,0")
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "JPEG has no alpha" in err[0]


@pytest.mark.parametrize("args, words", [
    (["-o", "{tmp}/x.bmp"], "unsupported image format '.bmp'"),
    (["-o", "{tmp}/x.jpg", "--quality", "0"], "--quality must be in 1..100"),
    (["-o", "{tmp}/x.jpg", "--bits", "16"], "16-bit colour is written as PNG"),
])
def test_bad_output_choices_are_one_line(tmp_path, capsys, args, words):
    args = [a.format(tmp=tmp_path) for a in args]
    assert main(["render", MODEL, "--size", "16x16", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert not any(p.suffix in (".bmp", ".jpg") for p in tmp_path.iterdir())


def test_frame_save_takes_the_formats(tmp_path):
    scene = facet.load(MODEL)
    with facet.Renderer(32, 24) as r:
        frame = r.render(scene)
        frame.save(tmp_path / "a.webp", quality=80)
        with pytest.raises(facet.InputError, match="float_color=True"):
            frame.save(tmp_path / "a.exr")
        r.render(scene, float_color=True).save(tmp_path / "a.exr")
    assert (tmp_path / "a.webp").stat().st_size > 0 and (tmp_path / "a.exr").is_file()
