"""Robots in a scene posed by joint values (no GL): ``Scene.posed`` and ``Scene.joints``,
and ``Scene.add`` of a loaded scene (a robot, a stage), which keeps the rigs that move it.

A robot (a URDF, facet.formats.urdf.Articulation) stands in ``scene.animated`` as a rig
with no clips whose parts are fixed at their links' poses; posing it again is a view of
the scene whose robots' rigs are configured anew and whose parts are moved with them, so
a posed scene renders, animates and poses again like any other."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import InputError


def robots(scene) -> list:
    """The scene's robots: its Animated entries whose rigs take joint values."""
    return [a for a in getattr(scene, "animated", ()) if hasattr(a.rig, "configured")]


def joint_ranges(scene) -> dict[str, tuple[float, float]]:
    """{joint: (lower, upper)} of every joint of the scene's robots that takes a value
    (radians, metres; a continuous joint's is (-pi, pi))."""
    out: dict = {}
    for a in robots(scene):
        out.update(a.rig.ranges())
    return out


def posed(scene, joints: dict):
    """``scene`` with its robots' joints set to ``joints`` {name: value} (the others as
    they were): a view. A name no robot has, or a scene with no robot, is an error."""
    found = robots(scene)
    if not found:
        raise InputError("joints: this scene has no robot to pose (a URDF, "
                         "facet.load('robot.urdf'))")
    known = joint_ranges(scene)
    unknown = [name for name in joints if name not in known and not any(
        name in a.rig.kinematics.joint_map for a in found)]
    if unknown:
        names = list(known)
        shown = ", ".join(names[:12]) + (f" and {len(names) - 12} more" if len(names) > 12
                                         else "")
        raise InputError(f"joints: no joint named {unknown[0]!r}; the scene's robots have "
                         f"{shown or 'no movable joints'}")
    from .animation import Animated

    by_id = {o.id: k for k, o in enumerate(scene.objects)}
    objects, animated = list(scene.objects), []
    for a in scene.animated:
        if a in found:
            rig = a.rig.configured(joints)
            a = Animated(rig, a.objects, a.placement, a.cameras)
            for oid, m in zip(a.objects, rig.placements(), strict=True):
                k = by_id[oid]
                objects[k] = replace(objects[k], transform=a.placement @ m)
        animated.append(a)
    view = scene.view(objects=objects)
    view.animated = animated
    return view


def random_configurations(scene, count: int, seed: int) -> list[dict]:
    """``count`` configurations of the scene's robots, each joint uniform in its range
    (seeded)."""
    ranges = joint_ranges(scene)
    if not ranges:
        raise InputError("random_joints: this scene has no robot joint that takes a value")
    lo, hi = (np.array(x, float) for x in zip(*ranges.values(), strict=True))
    values = np.random.default_rng(seed).uniform(lo, hi, (count, len(ranges)))
    return [dict(zip(ranges, map(float, row), strict=True)) for row in values]


def add_scene(target, source, transform) -> list[int]:
    """``source``'s objects placed in ``target`` by ``transform`` (4x4 or None), with the
    rigs that move them (a robot poses again there, an animation plays): their new ids.
    Lights, cameras, an environment and splats stay behind, said in one line."""
    import warnings

    from ..errors import FacetWarning
    from ..geometry import transforms as T
    from .animation import Animated

    base = np.eye(4) if transform is None else np.asarray(transform, dtype=np.float64)
    if base.shape != (4, 4) or not np.all(np.isfinite(base)):
        raise InputError(f"transform must be a finite 4x4 matrix, got shape {base.shape}")
    T.normal_matrix(base)
    ids: dict[int, int] = {}
    for o in source.objects:
        ids[o.id] = target._next_id()
        target.objects.append(replace(o, id=ids[o.id], transform=base @ o.transform,
                                      transform_end=None if o.transform_end is None
                                      else base @ o.transform_end))
    for a in source.animated:
        target.animated.append(Animated(a.rig, [ids[i] for i in a.objects],
                                        base @ a.placement))
    left = [what for what, has in (("lights", source.lights), ("cameras", source.cameras),
                                   ("environment", source.environment is not None),
                                   ("splats", getattr(source, "splats", ()))) if has]
    if left:
        warnings.warn(f"Scene.add: the added scene's {', '.join(left)} are not added with "
                      "its objects (add_light, add_camera, Scene.environment)",
                      FacetWarning, stacklevel=3)
    return list(ids.values())
