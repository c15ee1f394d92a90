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


# Extensions facet does not draw yet, said by name: a file that requires one is refused in
# one line, one that only uses it draws with one warning line naming it.
REFUSED: dict[str, str] = {}  # (IridescenceSuzanne was, until the film was drawn)
WARNED = {"AnisotropyStrengthTest": "KHR_materials_anisotropy"}


@pytest.mark.skipif(not MODELS, reason=f"the shared glTF models are absent ({SHARED_GLTF})")
@pytest.mark.parametrize("name", sorted(REFUSED) + sorted(WARNED))
def test_a_sample_model_facet_cannot_draw_all_of_says_what(renderer, name):
    """What facet cannot draw of a file is named, never dropped silently."""
    if name in REFUSED:
        with pytest.raises(facet.FacetError, match=REFUSED[name]):
            facet.load(_path(name))
        return
    with pytest.warns(facet.FacetWarning, match=WARNED[name]):
        scene = facet.load(_path(name))
    assert (renderer(48, 48).render(scene, outputs=("ids",)).object_ids >= 0).sum() > 20


@pytest.mark.skipif(not MODELS, reason=f"the shared glTF models are absent ({SHARED_GLTF})")
@pytest.mark.parametrize("name", [m for m in MODELS if m not in REFUSED and m not in WARNED])
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
