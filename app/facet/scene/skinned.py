"""A skinned pose of a rest mesh whose vertices are computed only when something asks for
them (no GL): the rasterizer skins in its vertex shader from the rest mesh's buffers and
the joint matrices (glsl/lib/skin.glsl), so playing an animation uploads a few matrices a
frame; the tracers and ``Mesh.load`` read ``positions`` and get the numpy skin
(facet.scene.animation.deform), computed once per pose.

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
    """``rest`` skinned by ``joint_matrices`` (J, 4, 4) through ``skin`` (a Deformation
    with joints and weights, no morph targets)."""

    def __init__(self, rest: Mesh, skin, joint_matrices: np.ndarray):
        self.__dict__.update({k: v for k, v in rest.__dict__.items() if k not in LAZY})
        self.rest = getattr(rest, "rest", None) or rest
        self.skin = skin
        self.joint_matrices = np.asarray(joint_matrices, dtype=np.float64)
        self._posed = None
        self._box = None

    def _pose(self) -> tuple:
        if self._posed is None:
            from .animation import deform

            p, n, t = deform(self.rest, self.skin, None, self.joint_matrices)
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
            boxes, used = joint_boxes(self.rest, self.skin)
            m = self.joint_matrices[:len(used)][used]
            lo, hi = boxes[used, 0], boxes[used, 1]
            corners = np.stack([np.where(np.array(c, bool), hi, lo) for c in
                                np.ndindex(2, 2, 2)], axis=1)  # (J, 8, 3)
            placed = np.einsum("jab,jkb->jka", m[:, :3, :3], corners) + m[:, None, :3, 3]
            self._box = np.stack([placed.reshape(-1, 3).min(axis=0),
                                  placed.reshape(-1, 3).max(axis=0)])
            self._box.setflags(write=False)
        return self._box


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
