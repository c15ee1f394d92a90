"""Tier 3: golden images made on Mesa llvmpipe (the CI renderer).

One tolerance table for all; a failing comparison writes the rendered image and a diff
(amplified 8x) to facet-test-failures/ in the system's temporary folder (the message names
it; the suite writes nothing into the checkout). Goldens are rewritten only with ``pytest
--regen-golden``. On other renderers the comparison is skipped (tiers 1-2 still run).
Each test's docstring says what a person should see in its golden image.
"""

import tempfile
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from facet.formats import load_scene
from facet.geometry.camera import Camera
from facet.scene import Mesh, Scene, Texture, primitives
from facet.scene.light import camera_rig
from facet.scene.material import Material

ROOT = Path(__file__).resolve().parents[1]
GOLDEN = Path(__file__).resolve().parent / "golden"
FAILURES = Path(tempfile.gettempdir()) / "facet-test-failures"
# The tolerance table: a pixel differs when any channel is off by more than CHANNEL_TOL;
# at most MAX_DIFFERING of the pixels may differ. 1% leaves room for anti-aliased edge pixels,
# which change with the rasterisation order (a window is drawn upright, offscreen images
# upside down for top-down readback: ~0.7% of pixels of the knot at 320x240).
CHANNEL_TOL = 3
MAX_DIFFERING = 0.01
SIZE = (160, 120)


@pytest.fixture
def golden(request, renderer):
    r = renderer(*SIZE, 4)
    if "llvmpipe" not in r.info["renderer"]:
        pytest.skip(f"golden images are made on llvmpipe; this is {r.info['renderer']}")

    def check(name: str, image: np.ndarray) -> None:
        path = GOLDEN / f"{name}.png"
        image = np.ascontiguousarray(image[..., :3])
        if request.config.getoption("--regen-golden"):
            Image.fromarray(image).save(path)
            return
        assert path.exists(), f"no golden {path.name}; create it with pytest --regen-golden"
        want = np.asarray(Image.open(path).convert("RGB"))
        diff = np.abs(image.astype(int) - want).max(axis=2)
        share = float((diff > CHANNEL_TOL).mean())
        if share > MAX_DIFFERING:
            FAILURES.mkdir(parents=True, exist_ok=True)
            Image.fromarray(image).save(FAILURES / f"{name}.png")
            Image.fromarray(np.clip(diff * 8, 0, 255).astype(np.uint8)).save(
                FAILURES / f"{name}-diff.png")
        assert share <= MAX_DIFFERING, (f"{name}: {share:.2%} of pixels differ by more than "
                                        f"{CHANNEL_TOL}/255; see {FAILURES}")

    return r, check


def _knot_scene():
    scene = Scene()
    scene.add(Mesh.load(ROOT / "models" / "default.obj"))
    camera = Camera.frame(scene.bounds, aspect=SIZE[0] / SIZE[1])
    for light in camera_rig(camera.view):
        scene.add_light(light)
    return scene, camera


def test_golden_example_scene(golden):
    """The bundled example scene from its main camera: a checkered floor, a wooden table top
    with a red glossy ball and a sheared blue box, the orange knot front right and a
    checkered ring on the left, against a dark blue-grey sky."""
    r, check = golden
    scene = load_scene(ROOT / "models" / "example.toml")
    check("example-main", r.render(scene, scene.camera("main"), outputs=("color",)).color)


@pytest.mark.parametrize("shading", ["phong", "blinn", "gouraud", "flat", "unlit", "normals"])
def test_golden_shading_models(golden, shading):
    """The orange torus knot, lit by the key and fill rig: smooth highlights (phong, blinn
    broader), per-vertex highlights (gouraud), facets (flat), one flat orange (unlit), and
    rainbow world normals (normals)."""
    r, check = golden
    scene, camera = _knot_scene()
    check(f"knot-{shading}", r.render(scene, camera, shading=shading,
                                      outputs=("color",)).color)


def test_golden_textured_primitives(golden):
    """A checkered sphere (8x8 squares, poles at top and bottom), a checkered cube and a
    checkered torus in a row, under one white directional light from the upper left."""
    r, check = golden
    scene = Scene(ambient=0.15, background=(0.2, 0.2, 0.25))
    tex = Material(color=(1, 1, 1), ks=0.2, texture=Texture.checker())
    scene.add(primitives.sphere(0.8), tex, np.array(
        [[1, 0, 0, -2.0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]))
    scene.add(primitives.cube(1.2), tex)
    scene.add(primitives.torus(0.6, 0.2), tex, np.array(
        [[1, 0, 0, 2.0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]]))
    from facet.scene import DirectionalLight

    scene.add_light(DirectionalLight((1, -1, -1)))
    camera = Camera.look_at((0.5, 1.5, 6), (0, 0, 0), fov_y=40)
    check("textured-primitives", r.render(scene, camera, outputs=("color",)).color)
