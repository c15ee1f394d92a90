"""Per-frame state: what every draw of one frame shares, made once per frame and passed down
explicitly (nothing is parked on the renderer between calls).

``FrameState`` holds the camera and image size, how the target is oriented, the colour mode,
the lights as the shaders read them (packed once per frame into the std140 block of
glsl/lib/lights.glsl), the shadow maps drawn for this frame, the environment, and the
per-sample jitter of supersampling. Texture units are facet.gl.bindings'.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..geometry.camera import Camera
from ..gl.targets import FLIP_Y
from ..image.colorspace import srgb_to_linear
from ..scene.light import DirectionalLight, PointLight, SpotLight
from ..scene.scene import MAX_LIGHTS

LIGHT_KIND = {DirectionalLight: 0, PointLight: 1, SpotLight: 2}  # LIGHT_* in lighting.glsl


def pack_lights(lights, ambient, to_linear=np.asarray) -> bytes:
    """The std140 ``Lights`` block of glsl/lib/lights.glsl: ambient, count, 4 vec4 per light."""
    block = np.zeros(2 * 4 + MAX_LIGHTS * 16, dtype=np.float32)
    block[0:3] = to_linear(ambient)
    block[4:8] = np.array([len(lights), 0, 0, 0], dtype=np.int32).view(np.float32)
    for i, light in enumerate(lights):
        pos, direction, color, falloff = block[8 + 16 * i: 24 + 16 * i].reshape(4, 4)
        pos[3] = LIGHT_KIND[type(light)]
        color[:3] = to_linear(light.color) * light.intensity
        if hasattr(light, "position"):
            pos[:3] = light.position
            falloff[:3] = light.attenuation
        if hasattr(light, "direction"):
            direction[:3] = light.direction
        if isinstance(light, SpotLight):
            direction[3] = np.cos(np.radians(light.inner_angle))
            color[3] = np.cos(np.radians(light.outer_angle))
    return block.tobytes()


@dataclass(frozen=True)
class FrameState:
    """One frame's shared state (see the module docstring). ``lights`` are point-like (area
    lights already replaced by a point of theirs); ``shadows`` is what
    ``facet.render.raster.shadow.ShadowMaps.draw`` returned, or None."""

    camera: Camera
    width: int
    height: int
    flip_y: bool  # offscreen targets are drawn upside down (facet.gl.targets)
    shading: str
    srgb: bool  # inputs are sRGB-encoded and get linearised (facet.image.colorspace)
    lights: tuple
    ambient: np.ndarray
    environment: object = None
    shadows: object = None
    time: float = 0.0  # users' shaders' u_time
    jitter: np.ndarray | None = None  # clip-space sub-pixel shift (facet.render.antialias)
    gloss_jitter: tuple[float, float] = (0.0, 0.0)
    clip_plane: tuple | None = None  # world (n, d) of the mirror whose reflection is drawn
    cull: str = "auto"  # back-face culling: auto, on, off (facet.render.raster.culling)
    # Float colour out of an offscreen render: linear light, never sRGB-encoded (the
    # metallic-roughness model then writes its linear result in the default mode too).
    linear_out: bool = False
    lights_block: bytes = field(default=b"", compare=False)

    def __post_init__(self):
        if not self.lights_block:
            object.__setattr__(self, "lights_block",
                               pack_lights(self.lights, self.ambient, self.to_linear))

    def to_linear(self, color) -> np.ndarray:
        """An input colour in the space lighting happens in."""
        return srgb_to_linear(color) if self.srgb else np.asarray(color, dtype=np.float64)

    @property
    def light_kinds(self) -> tuple[int, ...]:
        return tuple(LIGHT_KIND[type(x)] for x in self.lights)

    def view_projection(self) -> np.ndarray:
        """Clip <- world for this frame's target: jittered, flipped for offscreen readback."""
        projection = self.camera.projection(self.width, self.height)
        if self.jitter is not None:
            projection = self.jitter @ projection
        return (FLIP_Y @ projection if self.flip_y else projection) @ self.camera.view

    def with_(self, **changes) -> FrameState:
        """A copy with some fields changed (a sample's camera, a mirror's reflection...);
        the light block is repacked only when the lights change."""
        if "lights" not in changes:
            changes["lights_block"] = self.lights_block
        else:
            changes["lights_block"] = b""
        return replace(self, **changes)
