"""Every Khronos sample model of ../shared/gltf loads without a warning line and draws
something in the rasterizer without one, at its first animation time and halfway through
its animations (animations, skins, morph targets, instancing, points and lines included)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import facet

from conftest import SHARED_GLTF

MODELS = sorted(p.parent.name for p in SHARED_GLTF.glob("*/*.gl*")) if SHARED_GLTF.is_dir() \
    else []


def _path(name):
    return next(p for p in sorted((SHARED_GLTF / name).glob("*.gl*")))


@pytest.mark.skipif(not MODELS, reason=f"the shared glTF models are absent ({SHARED_GLTF})")
@pytest.mark.parametrize("name", MODELS)  # (every one: none is refused or drawn in part)
def test_every_sample_model_loads_and_draws_without_warnings(renderer, name):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = facet.load(_path(name))
        r = renderer(48, 48)
        times = [0.0]
        if scene.animations:
            times.append(max(a.rig.duration() for a in scene.animated) / 2)
        for t in times:
            ids = r.render(scene, time=t, outputs=("ids",)).object_ids
            assert (ids >= 0).sum() > 20, (name, t)
    assert len(np.unique(ids)) > 1
