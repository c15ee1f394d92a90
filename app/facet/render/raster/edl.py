"""Eye-dome lighting for unlit point clouds (glsl/lib/edl.glsl): the cloud's linear depth,
drawn first into a float texture of the target's size; from it a full-screen pass computes
the shade of each pixel (glsl/post/edl_shade.frag: eight depth reads a pixel, not a
fragment), which the cloud's colour draw multiplies by. One target per renderer, remade
when the size changes."""

from __future__ import annotations

EDL_STRENGTH = 1.0  # Potree's defaults
EDL_RADIUS = 1.4  # pixels


class EdlTarget:
    def __init__(self, ctx):
        self.ctx = ctx
        self.size = None
        self.texture = self.depth = self.fbo = None
        self.shade = self.shade_fbo = None
        self.shade_pass = None  # made on first use

    def draw_shade(self, width: int, height: int, draw):
        """The eye-dome shade of what ``draw()`` draws (a texture: 1 where nothing), from
        its linear depth. The framebuffer bound before is bound again (its depth test as it
        was)."""
        if self.size != (width, height):
            self.release()
            self.size = (width, height)
            self.texture = self.ctx.texture(self.size, 1, dtype="f4")
            self.texture.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
            self.depth = self.ctx.depth_renderbuffer(self.size)
            self.fbo = self.ctx.framebuffer([self.texture], self.depth)
            self.shade = self.ctx.texture(self.size, 1, dtype="f2")
            self.shade.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
            self.shade_fbo = self.ctx.framebuffer([self.shade])
        if self.shade_pass is None:
            from ...gl.fullscreen import FullScreenPass

            self.shade_pass = FullScreenPass(self.ctx, "post/edl_shade.frag")
        bound = self.ctx.fbo
        self.fbo.use()
        self.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        try:
            draw()
            self.shade_fbo.use()
            depth_test = self.ctx.DEPTH_TEST
            self.ctx.disable(depth_test)
            self.shade_pass.draw({"u_edl_depth": self.texture},
                                 u_edl_strength=EDL_STRENGTH, u_edl_radius=EDL_RADIUS)
            self.ctx.enable(depth_test)
        finally:
            bound.use()
        return self.shade

    def release(self) -> None:
        for obj in (self.fbo, self.texture, self.depth, self.shade_fbo, self.shade):
            if obj is not None:
                obj.release()
        self.texture = self.depth = self.fbo = self.shade = self.shade_fbo = None
        self.size = None
        if self.shade_pass is not None:
            self.shade_pass.release()
            self.shade_pass = None
