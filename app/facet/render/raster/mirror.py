"""Planar mirrors: a flat object whose material has ``mirror=True`` shows the scene mirrored
in its plane (the rasterizer's planar reflection).

Per mirror and per colour pass, the scene without that mirror is drawn once more into a
texture the size of the target, through the camera reflected in the mirror's plane
(``view @ M`` with M = ``facet.geometry.planes.reflection``), with world-space fragments
behind the plane discarded (else what is under a mirrored floor would appear above it) and
front faces swapped (M swaps handedness). The mirror's own fragments then fetch that texture
at their own pixel (same size, flip and sub-pixel jitter) and mix it in by the material's
``reflectivity``. One bounce: a mirror seen in a mirror shows its plain material. The
reflection is drawn with the pass's objects, so the opaque pass reflects opaque objects.
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError
from ...geometry.planes import fit_plane


def mirror_plane(obj, eye) -> np.ndarray:
    """World-space plane (n, d) of a mirror object with n towards ``eye`` (the side it
    reflects); InputError when its mesh is not flat."""
    p = obj.mesh.positions @ obj.transform[:3, :3].T + obj.transform[:3, 3]
    plane = fit_plane(p)
    if plane is None:
        name = obj.name or f"object {obj.id}"
        raise InputError(f"{name}: a mirror must be flat (all its vertices in one plane); "
                         "use a plane or quad mesh, or drop 'mirror' from its material")
    return plane if plane[:3] @ eye + plane[3] >= 0 else -plane


class MirrorTargets:
    """Colour textures (one per mirror in a pass) and a shared depth buffer of one size."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.size = None
        self.depth = None
        self.targets: list[tuple[object, object]] = []  # (texture, framebuffer)

    def get(self, index: int, width: int, height: int):
        """The ``index``-th mirror's (texture, framebuffer) at ``width`` x ``height``."""
        if self.size != (width, height):
            self.release()
            self.size = (width, height)
            self.depth = self.ctx.depth_renderbuffer(self.size)
        while len(self.targets) <= index:
            tex = self.ctx.texture(self.size, 4, dtype="f2")  # float: sRGB mode is linear
            self.targets.append((tex, self.ctx.framebuffer([tex], self.depth)))
        return self.targets[index]

    def release(self) -> None:
        for tex, fbo in self.targets:
            fbo.release()
            tex.release()
        self.targets.clear()
        if self.depth is not None:
            self.depth.release()
        self.depth, self.size = None, None
