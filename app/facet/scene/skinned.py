"""A skinned and/or morphed pose of a rest mesh whose vertices are computed only when
something asks for them (no GL): the rasterizer morphs and skins in its vertex shader from
the rest mesh's buffers, its morph targets (uploaded once) and the pose's morph weights and
joint matrices (glsl/lib/skin.glsl, glsl/lib/morph.glsl), so playing an animation uploads a
few numbers a frame; the tracers and ``Mesh.load`` read ``positions`` and get the numpy
deformation (facet.scene.animation.deform), computed once per pose.

``bounds`` are the vertices' (framing a posed model is as tight as before); ``loose_bounds``
come without them, for what runs every frame (culling): a skinned vertex is a convex
combination of its joints' placements of it, so it lies in the union of each joint's matrix
applied to the box of the rest vertices that joint moves (a little looser).
"""

from __future__ import annotations

import numpy as np

from .mesh import Mesh

LAZY = ("positions", "normals", "_tangents", "_bounds")


def _readonly(a):
    if a is None:
        return None
    a = np.ascontiguousarray(a, dtype=np.float32)
    a.setflags(write=False)
    return a


class SkinnedPose(Mesh):
    """``rest`` deformed through ``skin`` (a Deformation: joints and weights and/or morph
    targets) by ``joint_matrices`` (J, 4, 4) (None: not skinned) and morph ``weights`` (T,)
    (None: not morphed)."""

    def __init__(self, rest: Mesh, skin, joint_matrices, weights=None):
        self.__dict__.update({k: v for k, v in rest.__dict__.items() if k not in LAZY})
        self.rest = getattr(rest, "rest", None) or rest
        self.skin = skin
        self.joint_matrices = None if joint_matrices is None or skin.joints is None else \
            np.asarray(joint_matrices, dtype=np.float64)
        self.morph_weights = None
        if weights is not None and skin.targets:
            count = next(iter(skin.targets.values())).shape[0]
            w = np.asarray(weights, dtype=np.float64)[:count]
            self.morph_weights = np.pad(w, (0, count - len(w)))
        self._posed = None
        self._box = None

    def _pose(self) -> tuple:
        if self._posed is None:
            from .animation import deform

            p, n, t = deform(self.rest, self.skin, self.morph_weights, self.joint_matrices)
            self._posed = [_readonly(p), _readonly(n), _readonly(t)]
        return self._posed

    @property
    def positions(self) -> np.ndarray:
        return self._pose()[0]

    @property
    def normals(self) -> np.ndarray:
        return self._pose()[1]

    @property
    def _tangents(self):
        return self._pose()[2]

    @_tangents.setter
    def _tangents(self, value) -> None:  # (Mesh.tangents computes them from the uvs)
        self._pose()[2] = _readonly(value)

    @property
    def loose_bounds(self) -> np.ndarray:
        """(2, 3) conservative bounds (module docstring), without skinning a vertex."""
        if self._box is None:
            grow = morph_reach(self.skin, self.morph_weights)  # (3,) how far morphs move
            if self.joint_matrices is None:
                b = self.rest.bounds
                self._box = np.stack([b[0] - grow, b[1] + grow])
                self._box.setflags(write=False)
                return self._box
            boxes, used = joint_boxes(self.rest, self.skin)
            m = self.joint_matrices[:len(used)][used]
            lo, hi = boxes[used, 0] - grow, boxes[used, 1] + grow
            corners = np.stack([np.where(np.array(c, bool), hi, lo) for c in
                                np.ndindex(2, 2, 2)], axis=1)  # (J, 8, 3)
            placed = np.einsum("jab,jkb->jka", m[:, :3, :3], corners) + m[:, None, :3, 3]
            self._box = np.stack([placed.reshape(-1, 3).min(axis=0),
                                  placed.reshape(-1, 3).max(axis=0)])
            self._box.setflags(write=False)
        return self._box


def morph_reach(skin, weights) -> np.ndarray:
    """(3,) the most any vertex's morph targets move it along each axis at ``weights``."""
    if weights is None or "positions" not in skin.targets:
        return np.zeros(3)
    cache = skin.__dict__.get("_reach")
    if cache is None:  # (T, 3) each target's largest displacement along each axis
        cache = np.abs(skin.targets["positions"]).max(axis=1).astype(np.float64)
        object.__setattr__(skin, "_reach", cache)
    return np.abs(weights) @ cache


def joint_boxes(rest: Mesh, skin) -> tuple[np.ndarray, np.ndarray]:
    """((J, 2, 3) the box of the rest vertices each joint moves, (J,) whether it moves
    any), computed once per rest mesh and skin."""
    cache = rest.__dict__.setdefault("_joint_boxes", {})
    key = id(skin)
    if key not in cache:
        joints, weights = skin.joints, skin.weights
        count = int(joints.max()) + 1 if joints.size else 0
        p = rest.positions.astype(np.float64)
        lo = np.full((count, 3), np.inf)
        hi = np.full((count, 3), -np.inf)
        for k in range(joints.shape[1]):  # (at most 8 influences)
            moved = weights[:, k] > 0
            j = joints[moved, k]
            np.minimum.at(lo, j, p[moved])
            np.maximum.at(hi, j, p[moved])
        used = np.isfinite(lo).all(axis=1)
        cache[key] = (np.stack([lo, hi], axis=1), used)
    return cache[key]
