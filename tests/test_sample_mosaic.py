"""Small pictures draw the path tracer's samples several at a time, stacked one above
the other in one taller picture (facet.render.sequence: llvmpipe's 64-pixel tiles left a
core idle). The samples are the same ones: the same random streams and pixel shifts, so
the picture is the one drawn sample by sample (to float rounding), and spp counts them."""

import numpy as np
import pytest

import facet
from facet.render.path.engine import PathEngine

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("spp, size, per", [(7, (24, 24), 1), (20, (24, 24), 1),
                                            (22, (128, 128), 4), (6, (160, 96), 2)])
def test_a_mosaic_draws_the_picture_sample_by_sample_draws(spp, size, per, monkeypatch):
    """Stacked parts (small pictures) and several paths run one after the other in each
    fragment (two rasterizer threads: 128 x 128 draws 4 parts of 4, then 3 parts of 2;
    160 x 96 its 6 samples as 3 parts of 2; 24 x 24 16 parts of 1) draw the samples that
    single draws draw."""
    monkeypatch.setenv("LP_NUM_THREADS", "2")
    scene = facet.load(ROOT / "models" / "cornell.toml")
    out = {}
    stacked = []
    draw_mosaic = PathEngine.draw_mosaic

    def counted(self, scene, states, *args):
        stacked.append((len(states), args[-1]))
        return draw_mosaic(self, scene, states, *args)

    for mosaic in (True, False):
        PathEngine.mosaic = mosaic
        PathEngine.draw_mosaic = counted
        stacked.clear()
        try:
            with facet.Renderer(*size) as r:
                frame = r.render(scene, scene.cameras["front"], spp=spp, float_color=True,
                                 outputs=("color", "spp"))
                out[mosaic] = frame
                assert bool(stacked) == mosaic  # (each way was taken)
                if mosaic:
                    assert stacked[0][1] == per  # (paths one after the other a fragment)
        finally:
            PathEngine.mosaic = True
            PathEngine.draw_mosaic = draw_mosaic
    np.testing.assert_allclose(out[True].color, out[False].color, rtol=1e-4, atol=1e-6)
    assert (out[True].spp == spp).all() and (out[False].spp == spp).all()
    assert out[True].color[..., :3].mean() > 0.05  # a lit room


@pytest.mark.parametrize("threads, size, parts", [
    ("2", (128, 128), (4, 4)), ("2", (256, 256), (1, 8)), ("2", (64, 64), (16, 1)),
    ("2", (1024, 768), (1, 8)), ("0", (128, 128), (2, 8)), ("16", (256, 256), (8, 2))])
def test_a_mosaic_gives_each_rasterizer_thread_its_tiles(threads, size, parts, monkeypatch):
    """A draw fills at least eight of llvmpipe's 64 x 64 tiles for each of its threads
    (LP_NUM_THREADS, 0: one), at most 16 samples at once, paths one after the other in a
    fragment (up to the engine's eight) before more parts."""
    from types import SimpleNamespace

    from facet.render.sequence import _mosaic_parts

    monkeypatch.setenv("LP_NUM_THREADS", threads)
    scene = facet.load(ROOT / "models" / "cornell.toml")
    opts = SimpleNamespace(width=size[0], height=size[1])
    assert _mosaic_parts(PathEngine, scene, opts, False, None) == parts


def test_one_program_draws_one_sample_and_a_mosaic():
    """A picture's first call compiles what its later ones use: one sample (a window's
    frame, a render at spp=1) and a stack of them are one program (a second variant cost
    the first stacked draw a compile: about 0.1 s, seconds where llvmpipe's disk cache has
    not seen it)."""
    scene = facet.load(ROOT / "models" / "cornell.toml")
    with facet.Renderer(24, 24) as r:
        r.render(scene, scene.cameras["front"], spp=1, float_color=True)
        programs = set(r._engines["path"].rays.programs)
        r.render(scene, scene.cameras["front"], spp=6, float_color=True)
        assert set(r._engines["path"].rays.programs) == programs


def test_a_mosaic_target_is_laid_out_as_the_sample_target():
    """llvmpipe compiles a program again for each framebuffer layout it draws into: a
    mosaic without the depth buffer the single sample's target has cost the first stacked
    draw of every new program a second compile (1.5 s for the path tracer's, with Mesa's
    shader cache cold: MESA_SHADER_CACHE_DISABLE=true)."""
    scene = facet.load(ROOT / "models" / "cornell.toml")
    with facet.Renderer(24, 24) as r:
        r.render(scene, scene.cameras["front"], spp=16)  # (one mosaic of 16)
        acc = r._surfaces.accumulator
        target = acc.mosaic(16)
        assert len(target.color_attachments) == len(acc.sample.color_attachments)
        assert (target.depth_attachment is None) == (acc.sample.depth_attachment is None)
