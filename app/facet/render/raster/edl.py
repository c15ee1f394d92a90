"""Eye-dome lighting for unlit point clouds (glsl/lib/edl.glsl): the cloud's linear depth,
drawn first into a float texture of the target's size, which its colour draw then reads
around each fragment. One target per renderer, remade when the size changes."""

from __future__ import annotations

EDL_STRENGTH = 1.0  # Potree's defaults
EDL_RADIUS = 1.4  # pixels


class EdlTarget:
    def __init__(self, ctx):
        self.ctx = ctx
        self.size = None
        self.texture = self.depth = self.fbo = None

    def draw_depth(self, width: int, height: int, draw):
        """The linear depth ``draw()`` leaves (0 where it draws nothing), as a texture; the
        framebuffer bound before is bound again."""
        if self.size != (width, height):
            self.release()
            self.size = (width, height)
            self.texture = self.ctx.texture(self.size, 1, dtype="f4")
            self.texture.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
            self.depth = self.ctx.depth_renderbuffer(self.size)
            self.fbo = self.ctx.framebuffer([self.texture], self.depth)
        bound = self.ctx.fbo
        self.fbo.use()
        self.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        try:
            draw()
        finally:
            bound.use()
        return self.texture

    def release(self) -> None:
        for obj in (self.fbo, self.texture, self.depth):
            if obj is not None:
                obj.release()
        self.texture = self.depth = self.fbo = None
        self.size = None
