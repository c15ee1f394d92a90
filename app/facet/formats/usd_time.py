"""A stage's time-sampled transforms as a facet Rig (facet.scene.animation), so that
``--time`` and ``Scene.at`` pose a USD stage as they pose a glTF animation (no GL).

Every part hangs on a node of its own; a part whose prim (or an ancestor) has
time-sampled xformOps gets one clip's channels, its full placement sampled at every time
code any of them has and split into translation, rotation and scale (linear between codes,
rotations along the shorter arc: where the file turns by an Euler op, the path between
two codes can differ a little from USD's own interpolation of each op); the others stand
fixed. Time ``t`` seconds is time code ``startTimeCode + t x timeCodesPerSecond``. A
camera whose prim moves is posed the same way. A mesh whose points are time-sampled
carries one morph target per code (facet.formats.usd); its node's weights go from one
code's target to the next, linearly (USD's interpolation of points); its normals stay the
rest pose's, said once. A part whose visibility (or an ancestor's) is time-sampled hangs
below a node whose scale steps between 1 and 0 at those codes (held, as USD holds a token;
a zero scale hides a part in every engine, facet.scene.staging).
"""

from __future__ import annotations

import numpy as np

from ..scene.animation import Binding, Channel, Clip, Rig, Sampler


def _codes(prim) -> set[float]:
    """The time codes of the xformOps of ``prim`` and its ancestors."""
    from pxr import Sdf, UsdGeom

    codes: set[float] = set()
    stage, path = prim.GetStage(), prim.GetPath()
    while path != Sdf.Path.absoluteRootPath and not path.isEmpty:  # up the path, so
        at = stage.GetPrimAtPath(path)  # (an instance proxy's parents are proxies too)
        if at and at.IsA(UsdGeom.Xformable):
            for op in UsdGeom.Xformable(at).GetOrderedXformOps():
                codes.update(op.GetTimeSamples())
        path = path.GetParentPath()
    return codes


def visibility_codes(prim) -> list[float]:
    """The time codes at which ``prim``'s computed visibility may change (its own and its
    ancestors' visibility samples, sorted), or [] when none has more than one sample."""
    from pxr import Sdf, UsdGeom

    codes: set[float] = set()
    varies = False
    stage, path = prim.GetStage(), prim.GetPath()
    while path != Sdf.Path.absoluteRootPath and not path.isEmpty:
        at = stage.GetPrimAtPath(path)
        if at and at.IsA(UsdGeom.Imageable):
            samples = UsdGeom.Imageable(at).GetVisibilityAttr().GetTimeSamples()
            codes.update(samples)
            varies = varies or len(samples) > 1
        path = path.GetParentPath()
    return sorted(codes) if varies else []


def _trs(m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(translation, quaternion x y z w, scale) of an affine 4x4 without shear."""
    a = m[:3, :3]
    s = np.linalg.norm(a, axis=0)
    if np.linalg.det(a) < 0:
        s[0] = -s[0]
    r = a / np.where(s != 0, s, 1)
    w = np.sqrt(max(0.0, 1 + r[0, 0] + r[1, 1] + r[2, 2])) / 2
    x = np.sqrt(max(0.0, 1 + r[0, 0] - r[1, 1] - r[2, 2])) / 2
    y = np.sqrt(max(0.0, 1 - r[0, 0] + r[1, 1] - r[2, 2])) / 2
    z = np.sqrt(max(0.0, 1 - r[0, 0] - r[1, 1] + r[2, 2])) / 2
    x = np.copysign(x, r[2, 1] - r[1, 2])
    y = np.copysign(y, r[0, 2] - r[2, 0])
    z = np.copysign(z, r[1, 0] - r[0, 1])
    return m[:3, 3].copy(), np.array([x, y, z, w]), s


def time_rig(stage, placed: list, cameras: dict, notes: list) -> Rig | None:
    """The Rig of a stage's moving parts, or None when nothing moves. ``placed``: per part
    (its prim or None, 4x4 geometry -> prim, its morph Deformation of moving points or
    None); ``cameras``: {name: (prim, Camera)}."""
    from pxr import Usd, UsdGeom

    from .usd_geometry import matrix as _matrix

    tcps = stage.GetTimeCodesPerSecond()
    if not tcps > 0:  # (pxr's time sample queries do not return on such a stage)
        notes.append(f"timeCodesPerSecond is {tcps:g}: the stage is drawn at its default "
                     "time, its time samples not played")
        return None
    moving = [sorted(_codes(prim)) if prim is not None else [] for prim, _, _ in placed]
    cam_codes = {name: sorted(_codes(prim)) for name, (prim, _) in cameras.items()}
    morphed = [deform is not None for _, _, deform in placed]
    shown = [visibility_codes(prim) if prim is not None else [] for prim, _, _ in placed]
    if not any(moving) and not any(cam_codes.values()) and not any(morphed) \
            and not any(shown):
        return None
    start = stage.GetStartTimeCode()
    caches: dict[float, object] = {}

    def world(prim, code):
        if code not in caches:
            caches[code] = UsdGeom.XformCache(Usd.TimeCode(code))
        return _matrix(caches[code].GetLocalToWorldTransform(prim))

    n = len(placed) + len(cameras)
    hiders = [node for node, codes in enumerate(shown) if codes]  # one node above each
    total = n + len(hiders)
    parents = np.full(total, -1)
    rest_t = np.zeros((total, 3))
    rest_r, rest_s = np.tile([0, 0, 0, 1.0], (total, 1)), np.ones((total, 3))
    fixed, channels, bindings, weights = {}, [], [], {}
    for k, node in enumerate(hiders):
        parents[node] = n + k
        prim = placed[node][0]
        seen = np.array([[float(UsdGeom.Imageable(prim).ComputeVisibility(Usd.TimeCode(c))
                                != UsdGeom.Tokens.invisible)] * 3 for c in shown[node]])
        rest_s[n + k] = seen[0]
        channels.append(Channel(n + k, "scale", Sampler(
            (np.array(shown[node]) - start) / tcps, seen, "STEP")))
    default = UsdGeom.XformCache(Usd.TimeCode(start))  # (the time the stage was read at)
    for node, ((prim, local, deform), codes) in enumerate(zip(placed, moving, strict=True)):
        bindings.append(Binding(part=node, node=node, skin=None, deform=deform))
        if deform is not None:  # one target per time code of its points
            points = UsdGeom.PointBased(prim).GetPointsAttr().GetTimeSamples()
            count = len(points)
            weights[node] = np.zeros(count)
            channels.append(Channel(node, "weights", Sampler(
                (np.array(points) - start) / tcps, np.eye(count))))
        if prim is None:
            fixed[node] = local
            continue
        if not codes:
            fixed[node] = _matrix(default.GetLocalToWorldTransform(prim)) @ local
            continue
        samples = [_trs(world(prim, c) @ local) for c in codes]
        times = (np.array(codes) - start) / tcps
        t, r, s = (np.array(x) for x in zip(*samples, strict=True))
        rest_t[node], rest_r[node], rest_s[node] = t[0], r[0], s[0]
        channels += [Channel(node, "translation", Sampler(times, t)),
                     Channel(node, "rotation", Sampler(times, r)),
                     Channel(node, "scale", Sampler(times, s))]
    rig_cameras = {}
    for k, (name, (prim, camera)) in enumerate(cameras.items()):
        node = len(placed) + k
        codes = cam_codes[name]
        frame = _matrix(default.GetLocalToWorldTransform(prim))
        rig_cameras[name] = (node, camera)
        if not codes:
            fixed[node] = _unscaled(frame)
            continue
        samples = [_trs(_unscaled(world(prim, c))) for c in codes]
        times = (np.array(codes) - start) / tcps
        t, r, s = (np.array(x) for x in zip(*samples, strict=True))
        rest_t[node], rest_r[node], rest_s[node] = t[0], r[0], s[0]
        channels += [Channel(node, "translation", Sampler(times, t)),
                     Channel(node, "rotation", Sampler(times, r))]
    if any(morphed):
        notes.append("time-sampled points move with their normals at rest")
    order = [*range(n, total), *range(n)]  # (the hiding nodes first: parents first)
    return Rig(parents, order, (rest_t, rest_r, rest_s), fixed, weights,
               [Clip("stage", tuple(channels))], [], bindings, rig_cameras)


def _unscaled(m: np.ndarray) -> np.ndarray:
    out = m.copy()
    norms = np.linalg.norm(out[:3, :3], axis=0)
    out[:3, :3] /= np.where(norms > 0, norms, 1)
    return out
