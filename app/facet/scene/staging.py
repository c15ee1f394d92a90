"""The scene as one render's options stage it (no GL): its animations at ``time`` (with the
``animation`` that plays; facet.scene.animation) and its glTF material ``variant``
(KHR_materials_variants). Every front renders through ``staged``, so a time or a variant
means the same from Python, scene files, the command line, datasets and the viewer."""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from ..errors import FacetWarning, InputError
from .animation import pose_scene


def staged(scene, opts):
    """``scene`` posed at ``opts.time`` and dressed in ``opts.variant``: a view sharing
    what does not change; ``scene`` itself when nothing does. With a ``shutter`` open for
    some seconds the view remembers how to pose itself later in it (``moving``: motion
    blur that follows the animation, facet.render.antialias)."""
    posed = without_collapsed(pose_scene(scene, opts.time, opts.animation))
    if opts.shutter > 0 and posed is not scene and getattr(scene, "animated", None):
        posed.moving = (scene, opts.time, opts.shutter, opts.animation)
    return dressed(posed, opts.variant)


def collapsed(objects) -> np.ndarray:
    """(N,) bool: which ``objects``' transforms squash them to nothing (a scale of 0 on
    some axis: how glTF files hide a part, often by an animation); no surface to draw."""
    if not objects:
        return np.zeros(0, bool)
    m = np.array([o.transform for o in objects], dtype=np.float64)[:, :3, :3]
    with np.errstate(all="ignore"):
        size = np.abs(m).max(axis=(1, 2))
        det = np.abs(np.linalg.det(np.nan_to_num(m)))
    return ~np.isfinite(m).all(axis=(1, 2)) | (size == 0.0) | (det <= 1e-12 * size ** 3)


def without_collapsed(scene):
    """``scene`` without its collapsed objects (a view; ``scene`` itself when none is): a
    zero scale hides a part in every engine, as glTF means it."""
    hidden = collapsed(scene.objects)
    if not hidden.any():
        return scene
    return scene.view(objects=[o for o, h in zip(scene.objects, hidden, strict=True)
                               if not h])


def at_shutter(scene, fraction: float):
    """The objects of ``scene`` (a staged view with ``moving``) at ``fraction`` of its
    shutter, its other settings (lights, background) kept: a view."""
    source, time, shutter, which = scene.moving
    posed = without_collapsed(pose_scene(source, time + fraction * shutter, which))
    view = scene.view(objects=posed.objects)
    return view


def variant_names(scene) -> list[str]:
    """The KHR_materials_variants names of the scene's meshes, in file order."""
    names: dict[str, None] = {}
    for o in scene.objects:
        for name in getattr(o.mesh, "variants", None) or ():
            names[name] = None
    return list(names)


def dressed(scene, variant: str | None):
    """``scene`` with each object that wears its file's own material wearing that file's
    material for ``variant`` instead (where the file gives one for it)."""
    if variant is None or getattr(scene, "dressed_in", None) == variant:
        return scene
    names = variant_names(scene)
    if not names:
        warnings.warn(f"variant {variant!r}: this scene has no material variants "
                      "(KHR_materials_variants); drawn as it is", FacetWarning, stacklevel=3)
        return scene
    if variant not in names:
        raise InputError(f"variant {variant!r}: no such material variant (variants: "
                         f"{', '.join(names)})")
    objects = [replace(o, material=o.mesh.variants[variant])
               if o.material is o.mesh.material and variant in (o.mesh.variants or {})
               else o for o in scene.objects]
    view = scene.view(objects=objects)
    view.dressed_in = variant
    return view
