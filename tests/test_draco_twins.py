"""Draco-compressed twins (tests/draco_twin.py: DracoPy's encoder) of the skinned and
morphing Khronos samples in ../shared/gltf move like the files they were made from: the
joints and weights are decoded from the Draco stream by their unique ids, the morph targets
read from their accessors, and all three engines draw twin and original alike."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import facet
from draco_twin import draco_twin
from facet.errors import FacetWarning

from conftest import SHARED_GLTF, shared_model

MOVING = ["RiggedSimple", "RiggedFigure", "AnimatedMorphCube", "BoxAnimated"]
TIMES = (0.0, 0.4, 1.1)


def _posed(scene, t: float) -> np.ndarray:
    """Every vertex of ``scene`` at ``t`` seconds, in world space, part after part."""
    return np.concatenate([o.mesh.positions @ o.transform[:3, :3].T + o.transform[:3, 3]
                           for o in scene.at(t).objects])


@pytest.mark.parametrize("name", MOVING)
def test_a_draco_twin_moves_as_its_original(tmp_path, name):
    source = shared_model(f"{name}/{name}.glb", SHARED_GLTF)
    twin = draco_twin(source, tmp_path / f"{name}.gltf")
    original = facet.open_scene(source)
    with warnings.catch_warnings():
        warnings.simplefilter("error", FacetWarning)  # nothing left out, nothing "at rest"
        compressed = facet.open_scene(twin)
    size = float(np.ptp(_posed(original, 0.0), axis=0).max())
    moved = 0.0
    for t in TIMES:
        a, b = _posed(original, t), _posed(compressed, t)
        assert a.shape == b.shape
        np.testing.assert_allclose(b, a, atol=1e-3 * size)  # 16-bit positions
        moved = max(moved, float(np.abs(a - _posed(original, 0.0)).max()))
    assert moved > 1e-3 * size  # (the samples do move: the comparison means something)


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_every_engine_draws_a_skinned_draco_twin_as_its_original(tmp_path, renderer,
                                                                  engine):
    source = shared_model("RiggedFigure/RiggedFigure.glb", SHARED_GLTF)
    twin = draco_twin(source, tmp_path / "figure.gltf")
    pictures = []
    for path in (source, twin):
        scene = facet.open_scene(path).at(0.7)
        camera = facet.Camera.frame(scene.bounds, direction=(0, 0, -1))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FacetWarning)  # (the tracers' own notes)
            pictures.append(renderer(48, 48).render(
                scene, camera, engine=engine, spp=4 if engine == "path" else None,
                float_color=True, outputs=("color",)).color[..., :3])
    a, b = pictures
    assert a.std() > 0.01  # a figure, not a blank picture
    assert np.abs(a - b).mean() < 0.01, np.abs(a - b).mean()
