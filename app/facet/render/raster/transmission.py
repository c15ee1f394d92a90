"""The rasterizer's transmission (KHR_materials_transmission and _volume), as the Khronos
glTF Sample Viewer approximates it: a picture of the scene without its transmitting objects
is drawn first (into a float texture the size of the target, mipmapped); a transmitting
fragment then refracts the view ray by Snell's law at its shading normal, follows it for
the material's thickness (scaled by the object's transform) to an exit point, projects
that point into the picture and reads it there, blurred by a mip level that grows with
the roughness (log2(width) x roughness x clamp(2 ior - 2, 0, 1)), attenuated by
Beer-Lambert over the distance travelled and tinted by the base colour
(glsl/mesh/pbr.frag, TRANSMISSION). Lights behind the surface shine through a GGX lobe
mirrored to the viewer's side. What it cannot see: objects behind other transmitting ones
(one layer), what leaves the picture (clamped at its edge), refraction at the far side of
the volume, and shadows (transmitting objects cast opaque ones here; the path tracer does
all of it exactly).
"""

from __future__ import annotations


def transmits(material) -> bool:
    """Whether a metallic-roughness ``material`` lets light through."""
    return getattr(material, "transmission", 0.0) > 0


class TransmissionTarget:
    """The picture behind transmitting objects: a float colour texture with mip levels and
    a depth buffer, remade when the size changes."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.size = None
        self.texture = self.depth = self.fbo = None

    def get(self, width: int, height: int):
        """(texture, framebuffer) at ``width`` x ``height``."""
        if self.size != (width, height):
            self.release()
            self.size = (width, height)
            self.texture = self.ctx.texture(self.size, 4, dtype="f2")
            self.texture.filter = (self.ctx.LINEAR_MIPMAP_LINEAR, self.ctx.LINEAR)
            self.texture.repeat_x = self.texture.repeat_y = False
            self.depth = self.ctx.depth_renderbuffer(self.size)
            self.fbo = self.ctx.framebuffer([self.texture], self.depth)
        return self.texture, self.fbo

    def release(self) -> None:
        for thing in (self.fbo, self.texture, self.depth):
            if thing is not None:
                thing.release()
        self.texture = self.depth = self.fbo = None
        self.size = None
