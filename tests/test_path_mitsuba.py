"""The path tracer against an independent renderer: models/cornell.toml (Lambertian walls,
a one-sided area lamp, a box and a mirror ball) rendered by Mitsuba 3 (tests/
mitsuba_scene.py; cached at 4096 paths per pixel in tests/data) and by facet, compared by
block means of linear radiance (16 x 16 pixels), not by single pixels."""

from pathlib import Path

import numpy as np
import pytest

import facet
import mitsuba_scene

ROOT = Path(__file__).resolve().parents[1]
SPP = 512
BLOCK = 16


def _blocks(image: np.ndarray) -> np.ndarray:
    n = image.shape[0] // BLOCK
    return image.reshape(n, BLOCK, n, BLOCK, 3).mean(axis=(1, 3))


def _facet_cornell(**kw) -> np.ndarray:
    scene = facet.load(ROOT / "models" / "cornell.toml")
    size = mitsuba_scene.CORNELL_SIZE
    with facet.Renderer(size, size) as r:
        return r.render(scene, scene.cameras["front"], engine="path", spp=SPP,
                        float_color=True, **kw).color[..., :3]


def test_the_cornell_box_matches_mitsuba():
    """At 512 paths per pixel a block's noise (mostly caustics through the mirror ball,
    which both renderers find by BSDF sampling alone) stays within 5% of its value
    (measured): blocks agree within 10% (or 0.01 where dark), the picture within 2%."""
    ours, ref = _facet_cornell(), mitsuba_scene.cornell_reference()
    np.testing.assert_allclose(ours.mean(axis=(0, 1)), ref.mean(axis=(0, 1)), rtol=0.02)
    a, b = _blocks(ours), _blocks(ref)
    bad = np.abs(a - b) > np.maximum(0.1 * b, 0.01)
    assert bad.sum() == 0, (np.argwhere(bad), a[bad], b[bad])


def test_the_comparison_can_fail():
    """Without bounced light (max_depth 0) the picture is darker than Mitsuba's in most
    blocks: the comparison sees it."""
    ours, ref = _facet_cornell(max_depth=0), mitsuba_scene.cornell_reference()
    a, b = _blocks(ours), _blocks(ref)
    assert (np.abs(a - b) > np.maximum(0.1 * b, 0.01)).mean() > 0.5


@pytest.mark.skipif(not mitsuba_scene.available(), reason="mitsuba is not installed "
                    "(pip install mitsuba): the cached reference is used as it is")
def test_the_cached_reference_is_what_mitsuba_renders():
    fresh = mitsuba_scene.render(facet.load(ROOT / "models" / "cornell.toml"),
                                 facet.load(ROOT / "models" / "cornell.toml")
                                 .cameras["front"], mitsuba_scene.CORNELL_SIZE,
                                 mitsuba_scene.CORNELL_SIZE, 256, seed=7)
    a, b = _blocks(fresh), _blocks(mitsuba_scene.cornell_reference())
    assert (np.abs(a - b) <= np.maximum(0.1 * b, 0.01)).all()


def test_glass_and_a_mirror_under_a_sky_match_mitsuba():
    """A smooth glass ball (Snell's refraction, the exact Fresnel factor), a mirror ball
    and a box on a floor under a constant sky (tests/mitsuba_scene.glass_scene)."""
    scene, camera = mitsuba_scene.glass_scene()
    size = mitsuba_scene.CORNELL_SIZE
    with facet.Renderer(size, size) as r:
        ours = r.render(scene, camera, engine="path", spp=256, float_color=True,
                        lights="scene",
                        environment={"color": list(mitsuba_scene.GLASS_SKY)}).color[..., :3]
    ref = np.load(mitsuba_scene.GLASS_REFERENCE)
    np.testing.assert_allclose(ours.mean(axis=(0, 1)), ref.mean(axis=(0, 1)), rtol=0.02)
    a, b = _blocks(ours), _blocks(ref)
    bad = np.abs(a - b) > np.maximum(0.05 * b, 0.01)
    assert bad.sum() == 0, (np.argwhere(bad), a[bad], b[bad])
