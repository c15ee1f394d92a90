"""Area lights as the path tracer sees them: emitting rectangles and spheres (no GL).

The rasterizer and the Whitted tracer draw an ``AreaLight`` as a point light at another
point of its rectangle in each supersample (facet.render.antialias). The path tracer makes
it what it stands for: a one-sided rectangle that emits on its ``normal`` side, sampled as
a light like every emitting surface (facet.render.path.emitters) and seen where a camera
ray or a reflection meets it. Its radiance keeps the light's strength: seen from far along
its normal, a rectangle of area A and radiance L is a point source of intensity L A, which
gives irradiance L A / d^2; facet's point light of intensity I gives pi I / d^2 (with
inverse-square attenuation), so L = pi I / A, in the light's colour. The rectangle falls off
with the inverse square of the distance whatever the light's ``attenuation`` says. A
``SphereLight`` (an AreaLight of a radius) is an emitting sphere the same way: of radiance
L = I / r^2, its far irradiance L pi r^2 / d^2 = pi I / d^2.
"""

from __future__ import annotations

import numpy as np

from ...scene.light import AreaLight, SphereLight
from ...scene.pbr import PbrMaterial
from ...scene.scene import SceneObject
from ...scene.shapes import Plane, Sphere


class AreaEmitters:
    """Per engine: the rectangles of a scene's area lights, made once per light."""

    def __init__(self):
        self._made: dict[tuple, SceneObject] = {}

    def objects(self, scene) -> list[SceneObject]:
        """The emitting rectangles of ``scene``'s area lights (ids after its objects)."""
        out = []
        for light in scene.lights:
            if not isinstance(light, AreaLight):
                continue
            key = (light.position.tobytes(), light.normal.tobytes(), light.size,
                   light.color.tobytes(), light.intensity, getattr(light, "radius", None))
            if key not in self._made:
                self._made[key] = _sphere(light) if isinstance(light, SphereLight) else \
                    _rectangle(light)
            obj = self._made[key]
            obj.id = len(scene.objects) + len(out)
            out.append(obj)
        return out

    def with_rectangles(self, scene):
        """``scene`` with its area lights' rectangles added to its objects."""
        extra = self.objects(scene)
        return scene.view(objects=scene.objects + extra) if extra else scene


def _rectangle(light: AreaLight) -> SceneObject:
    """The light's rectangle as an analytic plane (facet.scene.shapes: y = 0 facing +y,
    ``size`` along x and z) turned to face its normal: a scene of shapes stays one (its
    tracers' programs leave mesh traversal out: facet.render.rays.scene scene_defines)."""
    a, b = light.axes()  # a x b = normal; the plane's x, y, z: a, normal, a x normal = -b
    placed = np.eye(4)
    placed[:3, :3] = np.column_stack([a, light.normal, -b])
    placed[:3, 3] = light.position
    shape = Plane(light.size)
    area = light.size[0] * light.size[1]
    material = PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0, specular=0.0,
                           emissive=light.color, emissive_strength=np.pi * light.intensity / area,
                           name="area light")
    return SceneObject(0, shape.mesh(), material, placed, "area light", shape=shape)


def _sphere(light: SphereLight) -> SceneObject:
    """A sphere light as an emitting sphere of radiance I / r^2 (module docstring's
    reasoning: a sphere of radiance L is a point source of intensity L pi r^2 from afar)."""
    placed = np.eye(4)
    placed[:3, 3] = light.position
    shape = Sphere(light.radius)
    material = PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0, specular=0.0,
                           emissive=light.color,
                           emissive_strength=light.intensity / light.radius ** 2,
                           name="sphere light")
    return SceneObject(0, shape.mesh(), material, placed, "sphere light", shape=shape)


def strip_area_points(scene, scene_k, lights) -> tuple:
    """``lights`` (a sample's, where each of ``scene``'s area lights became a point light
    of ``scene_k``) without those points."""
    if len(scene.lights) != len(lights):
        return tuple(lights)
    return tuple(x for x, orig in zip(lights, scene.lights, strict=True)
                 if not isinstance(orig, AreaLight))
