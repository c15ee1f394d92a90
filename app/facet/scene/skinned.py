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

LAZY = ("positions", "normals", "_tangents", "_bounds")


def _readonly(a):
    if a is None:
        return None
    a = np.ascontiguousarray(a, dtype=np.float32)
    a.setflags(write=False)
    return a


class SkinnedPose:
    """``rest`` (a facet.scene.mesh.Mesh) deformed through ``skin`` (a Deformation: joints
    and weights and/or morph targets) by ``joint_matrices`` (J, 4, 4) (None: not skinned)
    and morph ``weights`` (T,) (None: not morphed). It reads as a Mesh: what a pose does
    not change (faces, uvs, colours, material, closedness) is the rest mesh's."""

    def __init__(self, rest, skin, joint_matrices, weights=None):
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

    def __getattr__(self, name: str):
        if name.startswith("__") or name in LAZY or name in ("rest", "_posed"):
            raise AttributeError(name)
        return getattr(self.rest, name)  # faces, uvs, colors, material, closed, kind, ...

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) the posed vertices' bounds (they are computed for it)."""
        p = self.positions
        return np.stack([p.min(axis=0), p.max(axis=0)]).astype(np.float64)

    @property
    def tangents(self):
        """(N, 4) the posed tangent frames (the rest mesh's moved, else computed from the
        posed vertices and the uvs), or None without uvs."""
        if self._tangents is None and self.rest.uvs is not None:
            from .normals import tangents

            self._tangents = tangents(self.positions, self.normals, self.rest.uvs,
                                      self.rest.faces)
        return self._tangents

    @property
    def vertex_count(self) -> int:
        return self.rest.vertex_count

    def __repr__(self) -> str:
        return f"SkinnedPose({self.rest!r})"

    def _pose(self) -> tuple:
        if self._posed is None:
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


def joint_boxes(rest, skin) -> tuple[np.ndarray, np.ndarray]:
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


def deform(mesh, deform, weights: np.ndarray | None,
           joint_matrices: np.ndarray | None):
    """(positions (N, 3), normals (N, 3), tangents (N, 4) or None) of ``mesh`` morphed by
    ``weights`` (T,) and skinned by ``joint_matrices`` (J, 4, 4) (each may be None)."""
    p = mesh.positions.astype(np.float64)
    n = mesh.normals.astype(np.float64)
    tangents = mesh._tangents
    tan = None if tangents is None else tangents[:, :3].astype(np.float64)
    if weights is not None and deform.targets:
        w = np.asarray(weights, dtype=np.float64)
        count = next(iter(deform.targets.values())).shape[0]
        w = np.pad(w[:count], (0, max(count - len(w), 0)))
        if "positions" in deform.targets:
            p = p + np.einsum("t,tnk->nk", w, deform.targets["positions"])
        if "normals" in deform.targets:
            n = n + np.einsum("t,tnk->nk", w, deform.targets["normals"])
        if tan is not None and "tangents" in deform.targets:
            tan = tan + np.einsum("t,tnk->nk", w, deform.targets["tangents"])
    if joint_matrices is not None and deform.joints is not None:
        # The blended matrix per vertex, sum_k w_k J_{j_k} (its top 3 rows, (N, 3, 4)),
        # float32 and one influence at a time: a loop over at most 8 influences, each a
        # gather and a multiply-add over every vertex.
        rows = joint_matrices[:, :3, :].astype(np.float32)
        weights = deform.weights.astype(np.float32)
        m = np.zeros((len(p), 3, 4), np.float32)
        for k in range(deform.joints.shape[1]):
            m += weights[:, k, None, None] * rows[deform.joints[:, k]]
        p = np.einsum("nij,nj->ni", m[:, :, :3], p.astype(np.float32)) + m[:, :, 3]
        a = m[:, :, :3]
        c0, c1, c2 = a[:, :, 0], a[:, :, 1], a[:, :, 2]
        # Inverse transpose up to the determinant: the cofactor matrix, its columns the
        # cross products of the other two; the determinant's sign keeps mirrors right.
        cof = np.stack([np.cross(c1, c2), np.cross(c2, c0), np.cross(c0, c1)], axis=2)
        det = np.einsum("ni,ni->n", c0, cof[:, :, 0])
        n = np.einsum("nij,nj->ni", cof, n) * np.where(det < 0, -1.0, 1.0)[:, None]
        if tan is not None:
            tan = np.einsum("nij,nj->ni", a, tan)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.where(length > 0, n / np.where(length > 0, length, 1.0), mesh.normals)
    if tan is not None:
        tl = np.linalg.norm(tan, axis=1, keepdims=True)
        tan = np.where(tl > 0, tan / np.where(tl > 0, tl, 1.0), tangents[:, :3])
        tan = np.hstack([tan, tangents[:, 3:4]])
    return p, n, tan
