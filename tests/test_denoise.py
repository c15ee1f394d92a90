"""Denoising (the denoise option: Intel Open Image Denoise through pyoidn, guided by the
first hit's albedo and normals): a noisy path-traced Cornell box comes closer to a
converged one without changing its brightness; the exact channels are never touched; the
same seed gives the same picture; what cannot be denoised says so; without pyoidn, one
line naming the extra."""

import sys
from pathlib import Path

import numpy as np
import pytest

import facet
from facet.cli import main
from facet.errors import FacetWarning, InputError

pytest.importorskip("pyoidn", reason="denoising needs pyoidn: pip install 'facet-render[denoise]'")

CORNELL = Path(__file__).resolve().parents[1] / "models" / "cornell.toml"
SIZE = 32


def _path(spp, **kw):
    scene = facet.open_scene(CORNELL)
    with facet.Renderer(SIZE, SIZE) as r:
        return r.render(scene, engine="path", spp=spp, float_color=True, **kw)


def test_a_denoised_picture_is_nearer_the_converged_one_and_as_bright():
    # Compared as an 8-bit picture shows them (to 1): the lamp's radiance (about 17) would
    # weigh its few edge pixels, which the filter softens, above the rest of the box.
    reference = np.minimum(_path(512, seed=1).color[..., :3], 1)
    raw = np.minimum(_path(16).color[..., :3], 1)
    clean = np.minimum(_path(16, denoise=True).color[..., :3], 1)

    def rmse(x):
        return float(np.sqrt(((x - reference) ** 2).mean()))

    # (The raw picture samples the lamp as a light: 41% of its error goes. Before the
    # path tracer counted its emitters ahead of the first draw, a new renderer's first
    # picture sampled none, was noisier, and lost over half.)
    assert rmse(clean) < 0.65 * rmse(raw), (rmse(clean), rmse(raw))
    assert clean.mean() == pytest.approx(reference.mean(), rel=0.03)
    # block by block (8 x 8 pixels), the brightness stays where it was
    blocks = [x.reshape(4, 8, 4, 8, 3).mean(axis=(1, 3)) for x in (clean, reference)]
    np.testing.assert_allclose(blocks[0], blocks[1], atol=0.03)


def test_the_exact_channels_are_not_denoised_and_the_seed_still_decides():
    outputs = ("color", "depth", "ids", "normals")
    a = _path(4, outputs=outputs)
    b = _path(4, outputs=outputs, denoise=True)
    c = _path(4, outputs=outputs, denoise=True)
    for name in ("depth", "object_ids", "normals"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert np.abs(a.color - b.color).mean() > 1e-3  # it did something
    np.testing.assert_array_equal(b.color, c.color)


def test_other_engines_say_they_leave_their_picture():
    scene = facet.open_scene(CORNELL)
    with facet.Renderer(16, 16) as r, pytest.warns(FacetWarning,
                                                   match="raster engine's picture is left"):
        r.render(scene, engine="raster", denoise=True)


def test_without_pyoidn_it_is_one_line_naming_the_extra(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "pyoidn", None)  # import fails
    scene = facet.open_scene(CORNELL)
    with facet.Renderer(16, 16) as r, pytest.raises(InputError, match=r"facet-render\[denoise\]"):
        r.render(scene, engine="path", spp=1, denoise=True)
    out = tmp_path / "x.png"
    assert main(["render", str(CORNELL), "--engine", "path", "--spp", "1", "--denoise",
                 "-o", str(out), "--size", "16x16"]) == 2
    err = capsys.readouterr().err
    assert "facet-render[denoise]" in err and "Traceback" not in err and not out.exists()


def test_the_viewer_says_it_shows_the_picture_as_it_refines():
    from types import SimpleNamespace

    from facet.render.denoise import denoise_lines

    path = SimpleNamespace(radiance=True, name="path")
    (line,) = denoise_lines(path, SimpleNamespace(window=object()))
    assert "viewer" in line and "not denoised" in line
    assert denoise_lines(path, SimpleNamespace(window=None)) == []
