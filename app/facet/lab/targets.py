"""What the passes of a Shadertoy-style program draw into (facet.lab.shadertoy): a
ping-pong pair of float targets per buffer (``[0]`` is drawn this frame, ``[1]`` holds the
last finished frame; they swap after each draw), one target for the image pass, and for
Cube A a pair of cube maps with one face-sized target and a pixel buffer to copy through.
Buffers are RGBA32F and clamp; nothing GL is made per frame.
"""

from __future__ import annotations

import numpy as np


class PassTargets:
    """The targets of ``keys`` (pass keys, in running order) at ``size``; Cube A's faces
    are ``cube_size`` texels."""

    def __init__(self, ctx, keys, size: tuple[int, int], cube_size: int):
        from ..gl.targets import allocating, check_size

        self.ctx, self.size, self.cube_size = ctx, tuple(size), int(cube_size)
        self.targets: dict = {}
        check_size(ctx, *self.size)
        with allocating(self.size, "pass buffers"):
            self._make(keys)

    def _make(self, keys) -> None:
        ctx = self.ctx
        for key in keys:
            if key == "cube":
                s = (self.cube_size, self.cube_size)
                face = ctx.texture(s, 4, dtype="f4")
                cubes = [ctx.texture_cube(s, 4, dtype="f4") for _ in range(2)]
                self.targets["cube"] = {"face": (face, ctx.framebuffer([face])),
                                        "cubes": cubes,
                                        "pixels": ctx.buffer(reserve=s[0] * s[1] * 16)}
                continue
            pair = []
            for _ in range(2 if key != "image" else 1):
                tex = ctx.texture(self.size, 4, dtype="f4")
                tex.repeat_x = tex.repeat_y = False  # Shadertoy's buffers clamp
                fbo = ctx.framebuffer([tex])
                fbo.clear(0.0, 0.0, 0.0, 0.0)
                pair.append((tex, fbo))
            self.targets[key] = pair

    def __getitem__(self, key):
        return self.targets[key]

    def latest(self, key):
        """Getter of the texture a reader of buffer ``key`` samples (its last finished
        frame: this frame's when it ran earlier in the frame)."""
        if key == "cube":
            pair = self.targets["cube"]["cubes"]
            return lambda: pair[1]
        pair = self.targets[key]
        return lambda: pair[1][0]

    @property
    def image_framebuffer(self):
        """Where the image pass draws (bottom-up, like any GL framebuffer)."""
        return self.targets["image"][0][1]

    def clear(self) -> None:
        """Every buffer and cube map back to zero (frame 0)."""
        for key, t in self.targets.items():
            if key != "cube":
                for _, fbo in t:
                    fbo.clear(0.0, 0.0, 0.0, 0.0)
                continue
            zero = np.zeros((self.cube_size, self.cube_size, 4), np.float32).tobytes()
            for cube in t["cubes"]:
                for face in range(6):
                    cube.write(face, zero)

    def read(self) -> np.ndarray:
        """The image, float32 (H, W, 4), row 0 at the top."""
        w, h = self.size
        out = np.empty((h, w, 4), np.float32)
        self.image_framebuffer.read_into(out, components=4, dtype="f4")
        return np.ascontiguousarray(out[::-1])  # fragCoord's origin is the bottom-left

    def read_cube(self) -> np.ndarray:
        """The latest cube map, (6, S, S, 4) float32 in OpenGL's face order, rows as
        written (t = 0 first)."""
        s = self.cube_size
        cube = self.targets["cube"]["cubes"][1]
        return np.stack([np.frombuffer(cube.read(face), np.float32).reshape(s, s, 4)
                         for face in range(6)])

    def release(self) -> None:
        for key, t in self.targets.items():
            if key == "cube":
                for obj in (t["face"][1], t["face"][0], t["pixels"], *t["cubes"]):
                    obj.release()
                continue
            for tex, fbo in t:
                fbo.release()
                tex.release()
        self.targets = {}
