"""The rasterizer's skinning and morphing (glsl/lib/skin.glsl, glsl/lib/morph.glsl): a
deformed pose (facet.scene.skinned) is drawn from its rest mesh's buffers, with its joints
and weights (vertex attributes) and its morph targets (a float texture) uploaded once beside
them; each pose sends its joint matrices (a small float texture: three texels, the rows of
each joint's 3x4 matrix) and its morph weights. Its vertices are never computed on the CPU
for this (more than MAX_MORPH targets: numpy, facet.scene.animation)."""

from __future__ import annotations

import numpy as np

from ...gl.bindings import unit

MAX_MORPH = 64  # morph targets the vertex shader blends (more: numpy)
MORPH_WIDTH = 4096  # texels per row of the targets' texture
POSE_DEFINES = {"MAX_MORPH": MAX_MORPH, "MORPH_WIDTH": MORPH_WIDTH}


def gpu_pose(mesh) -> tuple[int, bool]:
    """(influences the vertex shader blends: 0, 4 or 8; whether it morphs) of a deformed
    pose; (0, False) for anything else (drawn from its own vertices)."""
    skin = getattr(mesh, "skin", None)
    if skin is None or not hasattr(mesh, "morph_weights"):
        return 0, False
    if mesh.morph_weights is not None and len(mesh.morph_weights) > MAX_MORPH:
        return 0, False
    joints = 0 if mesh.joint_matrices is None else (8 if skin.joints.shape[1] > 4 else 4)
    return joints, mesh.morph_weights is not None


class JointRows:
    """One RGBA32F texture of (3, J) texels, grown as poses need."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.texture = None

    def bind(self, matrices: np.ndarray, prog) -> None:
        """Upload ``matrices`` (J, 4, 4) and point ``prog``'s u_joints at them."""
        rows = np.ascontiguousarray(matrices[:, :3, :], dtype=np.float32)  # (J, 3, 4)
        count = len(rows)
        if self.texture is None or self.texture.height < count:
            if self.texture is not None:
                self.texture.release()
            self.texture = self.ctx.texture((3, max(count, 64)), 4, dtype="f4")
            self.texture.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
        self.texture.write(rows.tobytes(), viewport=(0, 0, 3, count))
        self.texture.use(location=unit("u_joints"))

    def release(self) -> None:
        if self.texture is not None:
            self.texture.release()
            self.texture = None


def pose_buffers(cache, mesh, ctx):
    """The rest mesh's buffers of a deformed pose, with its joints and weights and its
    morph targets."""
    buffers = cache.buffers(mesh.rest)
    joints, morphed = gpu_pose(mesh)
    if joints:
        buffers.add_skin(ctx, mesh.skin)
    if morphed:
        buffers.add_morph(ctx, mesh.skin, MORPH_WIDTH)
    return buffers


def bind_pose(prog, mesh, buffers, joint_rows: JointRows) -> None:
    """The pose's joint matrices and morph weights for ``prog``."""
    joints, morphed = gpu_pose(mesh)
    if joints:
        joint_rows.bind(mesh.joint_matrices, prog)
    if morphed:
        buffers.morph.use(location=unit("u_targets"))
        w = np.zeros(MAX_MORPH, np.float32)
        w[:len(mesh.morph_weights)] = mesh.morph_weights
        prog.set_array("u_morph_weights", w)
        prog.set("u_morph_count", len(mesh.morph_weights))
        prog.set("u_morph_vertices", len(mesh.rest.positions))
