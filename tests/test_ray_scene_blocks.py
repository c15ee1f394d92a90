"""The ray scene's two ways of reading a scene's rows by texel fetches (facet.render.rays.scene,
a context without image load and store): a small scene's instance rows and top level from
uniform blocks, or every row from its texture. Both must draw the same picture, bit for bit,
in the path tracer, the Whitted tracer and the exact channels; a scene too large for the
blocks reads textures; and where the rows are images (cheaper still) no blocks are used."""

import numpy as np
import pytest

import facet
from facet.render.rays.scene import RayScene

from conftest import both_ways

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("engine", ["path", "trace"])
def test_blocks_and_textures_draw_the_same_picture(engine, monkeypatch):
    monkeypatch.setattr(RayScene, "use_images", False)
    scene = facet.load(ROOT / "models" / "cornell.toml")

    def render():
        with facet.Renderer(48, 48) as r:
            frame = r.render(scene, scene.cameras["front"], engine=engine, spp=4,
                             float_color=True, outputs=("color", "depth", "ids", "normals"))
            used = r._engines[engine].rays._in_blocks
            return frame.color, frame.depth, frame.object_ids, frame.normals, used

    a, b = both_ways(RayScene, "use_blocks", render)
    assert a[4] and not b[4]  # (each way was taken)
    for x, y in zip(a[:4], b[:4], strict=True):
        np.testing.assert_array_equal(x, y)
    assert a[0][..., :3].mean() > 0.05  # a lit room


def test_images_leave_the_blocks_unused():
    scene = facet.load(ROOT / "models" / "cornell.toml")
    with facet.Renderer(16, 16) as r:
        r.render(scene, scene.cameras["front"], engine="path", spp=1)
        rays = r._engines["path"].rays
        assert rays._in_blocks != rays.images


def test_a_scene_too_large_for_the_blocks_reads_textures():
    scene = facet.Scene()
    for i in range(80):  # 80 x 62 texels: over the 4096 of a 64 KiB block
        scene.add(facet.primitives.cube(0.9),
                  transform=facet.transforms.translate((i % 10, i // 10, 0)))
    with facet.Renderer(16, 16) as r:
        frame = r.render(scene, engine="path", spp=1, outputs=("color", "ids"))
        assert not r._engines["path"].rays._in_blocks
    assert len(np.unique(frame.object_ids[frame.object_ids >= 0])) > 40
