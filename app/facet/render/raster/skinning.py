"""The rasterizer's skinning (glsl/lib/skin.glsl): a skinned pose (facet.scene.skinned) is
drawn from its rest mesh's buffers, with the joints and weights uploaded once beside them,
and its joint matrices uploaded each pose as a small float texture: three texels, the rows
of each joint's 3x4 matrix. Its vertices are never computed on the CPU for this."""

from __future__ import annotations

import numpy as np

from ..state import UNITS


def skin_of(mesh) -> int:
    """The influences per vertex of a skinned pose the rasterizer skins (4 or 8), else 0."""
    skin = getattr(mesh, "skin", None)
    if skin is None or getattr(mesh, "joint_matrices", None) is None:
        return 0
    return 8 if skin.joints.shape[1] > 4 else 4


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
        self.texture.use(location=UNITS["joints"])
        prog.set("u_joints", UNITS["joints"])

    def release(self) -> None:
        if self.texture is not None:
            self.texture.release()
            self.texture = None


def skinned_buffers(cache, mesh, ctx):
    """The rest mesh's buffers of a skinned pose, with its joints and weights."""
    buffers = cache.buffers(mesh.rest)
    buffers.add_skin(ctx, mesh.skin)
    return buffers
