"""Small pictures draw the path tracer's samples several at a time, stacked one above
the other in one taller picture (facet.render.sequence: llvmpipe's 64-pixel tiles left a
core idle). The samples are the same ones: the same random streams and pixel shifts, so
the picture is the one drawn sample by sample (to float rounding), and spp counts them."""

import numpy as np
import pytest

import facet
from facet.render.path.engine import PathEngine

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("spp", [7, 20])
def test_a_mosaic_draws_the_picture_sample_by_sample_draws(spp):
    scene = facet.load(ROOT / "models" / "cornell.toml")
    out = {}
    for mosaic in (True, False):
        PathEngine.mosaic = mosaic
        try:
            with facet.Renderer(24, 24) as r:
                frame = r.render(scene, scene.cameras["front"], spp=spp, float_color=True,
                                 outputs=("color", "spp"))
                out[mosaic] = frame
                stacked = [dict(key[1]).get("MOSAIC") for key in
                           r._engines["path"].rays.programs]
                assert any(stacked) == mosaic  # (each way was taken)
        finally:
            PathEngine.mosaic = True
    np.testing.assert_allclose(out[True].color, out[False].color, rtol=1e-4, atol=1e-6)
    assert (out[True].spp == spp).all() and (out[False].spp == spp).all()
    assert out[True].color[..., :3].mean() > 0.05  # a lit room
