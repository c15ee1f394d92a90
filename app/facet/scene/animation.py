"""Animation, skins and morph targets (no GL): a ``Rig`` poses a model's nodes at a time.

The semantics are glTF 2.0's (section 3.11 of the specification), the one animated format
facet reads:

* A clip (glTF's "animation") is a set of channels, each driving one node's translation,
  rotation (a unit quaternion x, y, z, w), scale or morph weights through a sampler: key
  times (seconds, increasing) and values, interpolated STEP (the earlier key's value),
  LINEAR (lerp; slerp along the shorter arc for rotations) or CUBICSPLINE (Hermite, with an
  in-tangent, a value and an out-tangent per key, tangents scaled by the key interval;
  rotations normalised afterwards). Before the first key a channel holds the first value,
  after the last the last one (the specification's clamp; a sequence chooses its range).
* A node's local matrix is T R S of its (animated) properties, or its fixed ``matrix``;
  its world matrix is its parent's world matrix times its local one.
* Morph targets displace positions, normals and tangents: ``p = p0 + sum_i w_i d_i``; the
  weights are the node's (else the mesh's) defaults unless a channel drives them.
* A skin binds vertices to joints (nodes): joint matrix ``J_j = W(joint_j) IBM_j`` (world
  matrix times inverse bind matrix); a vertex moves by ``sum_k w_k J_{j_k}`` (up to 8
  influences: JOINTS_0/1, WEIGHTS_0/1), morphs first. Skinned vertices land in the file's
  world frame (the mesh node's own transform is not applied, as the specification says);
  normals move by the inverse transpose of the blended matrix, tangents by the matrix.

The first clip plays by default, as glTF viewers do; ``animation=NAME|INDEX`` plays another,
``animation="all"`` every clip at once (later clips win where two drive the same property, and
a warning says which clips collide). All of it is numpy over whole arrays (no
Python loop over vertices or keys; one loop over the nodes for their world matrices).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from .skinned import SkinnedPose  # a pose deformed on demand (the GPU's, else numpy)

INTERPOLATIONS = ("STEP", "LINEAR", "CUBICSPLINE")
PATHS = ("translation", "rotation", "scale", "weights")
NO_CLIPS = ("no clips",)  # Rig.clips_for: nothing plays (a model without the named one)
ALL_CLIPS = "all"  # Rig.clips_for: every clip at once (a clip's own name "all" wins)
SLERP_LINEAR = 0.9995  # cos(angle) above which slerp is a normalised lerp (sin ~ 0)


@dataclass(frozen=True)
class Sampler:
    """Key ``times`` (K,) float64, increasing; ``values`` (K, W) float64, or (K, 3, W) for
    CUBICSPLINE (in-tangent, value, out-tangent per key)."""

    times: np.ndarray
    values: np.ndarray
    interpolation: str = "LINEAR"

    def __call__(self, t: float, rotation: bool = False) -> np.ndarray:
        """The value at time ``t`` (W,) (a unit quaternion when ``rotation``)."""
        times, cubic = self.times, self.interpolation == "CUBICSPLINE"
        keys = self.values[:, 1] if cubic else self.values
        if len(times) == 1 or t <= times[0]:
            return keys[0]
        if t >= times[-1]:
            return keys[-1]
        k = int(np.searchsorted(times, t, side="right")) - 1
        span = times[k + 1] - times[k]
        u = (t - times[k]) / span
        if self.interpolation == "STEP":
            return keys[k]
        if cubic:  # the specification's Hermite spline, tangents scaled by the interval
            u2, u3 = u * u, u * u * u
            v = ((2 * u3 - 3 * u2 + 1) * keys[k] + span * (u3 - 2 * u2 + u) * self.values[k, 2]
                 + (-2 * u3 + 3 * u2) * keys[k + 1] + span * (u3 - u2) * self.values[k + 1, 0])
            return v / max(np.linalg.norm(v), 1e-300) if rotation else v
        if rotation:
            return slerp(keys[k], keys[k + 1], u)
        return (1.0 - u) * keys[k] + u * keys[k + 1]

    @property
    def end(self) -> float:
        return float(self.times[-1])


def slerp(q0: np.ndarray, q1: np.ndarray, u: float) -> np.ndarray:
    """Spherical linear interpolation of unit quaternions (x, y, z, w), along the shorter
    arc (q and -q are one rotation)."""
    q0 = q0 / np.linalg.norm(q0)
    q1 = q1 / np.linalg.norm(q1)
    d = float(np.dot(q0, q1))
    if d < 0.0:
        q1, d = -q1, -d
    if d > SLERP_LINEAR:
        q = (1.0 - u) * q0 + u * q1
        return q / np.linalg.norm(q)
    angle = np.arccos(d)
    return (np.sin((1.0 - u) * angle) * q0 + np.sin(u * angle) * q1) / np.sin(angle)


def trs_matrices(translation: np.ndarray, rotation: np.ndarray,
                 scale: np.ndarray) -> np.ndarray:
    """(N, 4, 4) matrices T R S of (N, 3) translations, (N, 4) quaternions (x, y, z, w;
    normalised here) and (N, 3) scales."""
    q = rotation / np.maximum(np.linalg.norm(rotation, axis=1, keepdims=True), 1e-300)
    x, y, z, w = q.T
    r = np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                  2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                  2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
                 axis=1).reshape(-1, 3, 3)
    m = np.zeros((len(q), 4, 4))
    m[:, :3, :3] = r * scale[:, None, :]
    m[:, :3, 3] = translation
    m[:, 3, 3] = 1.0
    return m


@dataclass(frozen=True)
class Channel:
    node: int
    path: str  # one of PATHS
    sampler: Sampler


@dataclass(frozen=True)
class Clip:
    name: str
    channels: tuple[Channel, ...]

    @property
    def duration(self) -> float:
        """Seconds from 0 to the last key of any channel."""
        return max((c.sampler.end for c in self.channels), default=0.0)


@dataclass(frozen=True)
class Skin:
    joints: np.ndarray  # (J,) node indices
    inverse_bind: np.ndarray  # (J, 4, 4)


@dataclass(frozen=True)
class Deformation:
    """A part's per-vertex skin and morph data, in the order of its mesh's vertices.

    joints : (N, K) int64 indices into the skin's joints, K = 4 or 8 (or None)
    weights : (N, K) float64, each row summing to 1 (or None)
    targets : {"positions" | "normals" | "tangents": (T, N, 3) float32} displacements
    """

    joints: np.ndarray | None = None
    weights: np.ndarray | None = None
    targets: dict = field(default_factory=dict)

    def remapped(self, source: np.ndarray) -> Deformation:
        """The same data for vertices ``source`` (N',) of the old order (loaders split
        vertices at creases)."""
        return Deformation(None if self.joints is None else self.joints[source],
                           None if self.weights is None else self.weights[source],
                           {k: v[:, source] for k, v in self.targets.items()})


@dataclass(frozen=True)
class Binding:
    """Part ``part`` (its index in the loader's parts) hangs on node ``node`` (placed by
    ``offset`` under it: an instance of EXT_mesh_gpu_instancing); ``skin`` (an index into
    Rig.skins) skins it; ``deform`` holds its vertex data."""

    part: int
    node: int
    skin: int | None
    deform: Deformation | None
    offset: np.ndarray | None = None


class Rig:
    """A model's node tree, clips, skins and the parts they move (see the module
    docstring). ``parents`` (N,) int (-1: a root); ``order``: every node after its parent;
    ``rest``: (translation (N, 3), rotation (N, 4), scale (N, 3)); ``fixed``: {node: 4x4}
    for nodes given by a matrix; ``weights``: {node: (T,) default morph weights};
    ``cameras``: {name: (node, Camera)} of cameras on nodes."""

    NO_CLIPS = NO_CLIPS  # (for callers that do not import this module)

    def __init__(self, parents, order, rest, fixed, weights, clips, skins, bindings,
                 cameras=None):
        self.parents = np.asarray(parents, dtype=np.int64)
        self.order = list(order)
        self.rest = tuple(np.asarray(a, dtype=np.float64) for a in rest)
        self.fixed, self.weights = dict(fixed), dict(weights)
        self.clips: list[Clip] = list(clips)
        self.skins: list[Skin] = list(skins)
        self.bindings: list[Binding] = list(bindings)
        self.cameras = dict(cameras or {})

    def with_corners(self, sources: list) -> Rig:
        """This rig for parts whose vertices became ``sources[part]`` (N',) of the old ones
        (flat shading: one vertex per face corner)."""
        out = copy.copy(self)
        out.bindings = [b if b.deform is None else
                        Binding(b.part, b.node, b.skin, b.deform.remapped(sources[b.part]),
                                b.offset)
                        for b in self.bindings]
        return out

    @property
    def clip_names(self) -> list[str]:
        return [c.name for c in self.clips]

    def has(self, which) -> bool:
        try:
            self.clips_for(which)
        except InputError:
            return False
        return True

    def clips_for(self, which) -> list[Clip]:
        """The clips that play: the first (None), all (``ALL_CLIPS``), one by name, or one
        by index (NO_CLIPS: none)."""
        if which is None:
            return self.clips[:1]
        if which is NO_CLIPS:
            return []
        if isinstance(which, str) and which in self.clip_names:
            return [self.clips[self.clip_names.index(which)]]
        if which == ALL_CLIPS:
            _warn_overlaps(self.clips)
            return self.clips
        index = which if isinstance(which, int) else \
            int(which) if isinstance(which, str) and which.isdigit() else None
        if index is not None and 0 <= index < len(self.clips):
            return [self.clips[index]]
        known = ", ".join(f"{i}: {n}" for i, n in enumerate(self.clip_names)) or "none"
        raise InputError(f"animation {which!r}: no such animation in this model "
                         f"(animations: {known}; or all)")

    def duration(self, which=None) -> float:
        return max((c.duration for c in self.clips_for(which)), default=0.0)

    def world(self, time: float, which=None) -> tuple[np.ndarray, dict]:
        """(N, 4, 4) world matrices of every node at ``time`` and {node: (T,) morph
        weights}, with the clips ``which`` (clips_for) playing."""
        t, r, s = (a.copy() for a in self.rest)
        weights = {k: v.copy() for k, v in self.weights.items()}
        for clip in self.clips_for(which):
            for c in clip.channels:
                if c.path == "weights":
                    weights[c.node] = c.sampler(time)
                else:
                    {"translation": t, "rotation": r, "scale": s}[c.path][c.node] = \
                        c.sampler(time, rotation=c.path == "rotation")
        local = trs_matrices(t, r, s)
        for node, matrix in self.fixed.items():
            local[node] = matrix
        world = np.empty_like(local)
        for node in self.order:  # parents first (facet.formats.gltf_check: a forest)
            p = self.parents[node]
            world[node] = local[node] if p < 0 else world[p] @ local[node]
        return world, weights

    def pose(self, time: float, which=None) -> tuple[dict, dict]:
        """({part: (4x4 part -> file, joint matrices (J, 4, 4) or None, morph weights (T,)
        or None)}, {camera name: 4x4 camera node -> file}) at ``time``. A skinned part's
        matrix is the identity: its joints carry it (module docstring)."""
        world, weights = self.world(time, which)
        parts = {}
        for b in self.bindings:
            joints = None
            if b.skin is not None:
                skin = self.skins[b.skin]
                joints = world[skin.joints] @ skin.inverse_bind
            placed = world[b.node] if b.offset is None else world[b.node] @ b.offset
            parts[b.part] = (np.eye(4) if joints is not None else placed, joints,
                             weights.get(b.node))
        return parts, {name: world[node] for name, (node, _) in self.cameras.items()}

    def posed_meshes(self, meshes: list, time: float, which=None) -> tuple[list, dict]:
        """([(mesh, 4x4 part -> file)] of the parts whose rest meshes are ``meshes`` (in
        part order), deformed where skinned or morphed, and the cameras' frames
        (``pose``) at ``time``."""
        parts, cams = self.pose(time, which)
        out = list(zip(meshes, [np.eye(4)] * len(meshes), strict=True))
        for b in self.bindings:
            matrix, joints, weights = parts[b.part]
            mesh = meshes[b.part]
            if b.deform is not None and (joints is not None or weights is not None):

                mesh = SkinnedPose(mesh, b.deform, joints, weights)
            out[b.part] = (mesh, matrix)
        return out, cams


_WARNED_OVERLAPS: set = set()


def _warn_overlaps(clips: list) -> None:
    """One warning line (once per set of clips) when clips played together drive the same
    node's property: the later clip's value is the one drawn."""
    owner: dict = {}
    clash: list = []
    for k, clip in enumerate(clips):
        for c in clip.channels:
            first = owner.setdefault((c.node, c.path), k)
            if first != k and (first, k) not in clash:
                clash.append((first, k))
    key = tuple(id(c) for c in clips)
    if not clash or key in _WARNED_OVERLAPS:
        return
    _WARNED_OVERLAPS.add(key)
    import warnings

    from ..errors import FacetWarning

    names = [c.name or str(k) for k, c in enumerate(clips)]
    pairs = ", ".join(f"{names[a]!r} and {names[b]!r}" for a, b in clash)
    warnings.warn(f"animation 'all': clips {pairs} drive the same nodes; the later clip's "
                  "values are drawn there", FacetWarning, stacklevel=4)


@dataclass
class Animated:
    """A rig placed in a scene: rig part ``i`` is scene object ``objects[i]``, the whole
    model placed by ``placement`` (4x4 file -> world); ``cameras``: {rig camera name:
    scene camera name}."""

    rig: Rig
    objects: list[int]
    placement: np.ndarray = field(default_factory=lambda: np.eye(4))
    cameras: dict = field(default_factory=dict)
    _memo: tuple = (None, None)  # (time, clip) -> (objects, cameras) of the last pose

    def posed(self, objects: list, by_id: dict, time: float,
              which=None) -> tuple[dict, dict]:
        """({object id: SceneObject at ``time``}, {scene camera name: 4x4 camera node ->
        world}), built from the scene's ``objects`` (their rest meshes); the last pose is
        kept, so rendering one time twice deforms (and uploads) once."""
        from dataclasses import replace

        key = (float(time), which)
        if self._memo[0] == key:
            return self._memo[1]
        rest = [objects[by_id[oid]] for oid in self.objects]
        placed, cams = self.rig.posed_meshes([o.mesh for o in rest], time, which)
        out = {o.id: replace(o, mesh=mesh, transform=self.placement @ matrix)
               for o, (mesh, matrix) in zip(rest, placed, strict=True)}
        cameras = {self.cameras[name]: self.placement @ m for name, m in cams.items()
                   if name in self.cameras}
        self._memo = (key, (out, cameras))
        return out, cameras


def pose_scene(scene, time: float, which=None):
    """``scene`` as it stands at ``time`` seconds with the clips ``which`` playing (each
    model's first clip by default; Rig.clips_for): a view whose animated objects and
    cameras are posed; ``scene`` itself when nothing in it is animated."""
    animated = getattr(scene, "animated", None)
    if not animated:
        if which is not None and not getattr(scene, "posed", False):
            import warnings

            from ..errors import FacetWarning

            warnings.warn(f"animation {which!r}: this scene has no animations; drawn as it "
                          "is", FacetWarning, stacklevel=3)
        return scene
    if which is not None and not any(a.rig.has(which) for a in animated):
        animated[0].rig.clips_for(which)  # the error naming the animations there are
    by_id = {o.id: k for k, o in enumerate(scene.objects)}
    objects, cameras = list(scene.objects), dict(scene.cameras)
    for a in animated:  # a model without the named animation stands still
        chosen = which if which is None or a.rig.has(which) else NO_CLIPS
        posed, views = a.posed(scene.objects, by_id, time, chosen)
        for oid, obj in posed.items():
            objects[by_id[oid]] = obj
        for name, frame in views.items():
            cameras[name] = cameras[name].with_view(camera_view(frame))
    view = scene.view(objects=objects)
    view.cameras = cameras
    view.animated = []  # posed: a second pose_scene leaves it
    view.posed = True
    return view


def camera_view(frame: np.ndarray) -> np.ndarray:
    """The view matrix of a camera on a node whose matrix is ``frame`` (4x4 node ->
    world): the frame without its scale, inverted (glTF cameras look down their -z)."""
    f = np.array(frame, dtype=np.float64)
    scale = np.linalg.norm(f[:3, :3], axis=0, keepdims=True)
    if not np.isfinite(f).all() or scale.min() < 1e-12:
        from ..errors import InputError

        raise InputError("a camera's node has a zero (or not finite) scale: the camera has "
                         "no direction; give its node a non-zero scale")
    f[:3, :3] /= scale
    if abs(np.linalg.det(f[:3, :3])) < 1e-9:  # its axes fold onto each other
        from ..errors import InputError

        raise InputError("a camera's node has a degenerate matrix (its axes are not "
                         "independent): the camera has no direction")
    return np.linalg.inv(f)
