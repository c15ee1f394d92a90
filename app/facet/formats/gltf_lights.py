"""glTF's KHR_lights_punctual -> facet lights (no GL).

The document's ``extensions.KHR_lights_punctual.lights`` are placed by the nodes that name
them: at the node's origin, shining down its -z. glTF's units are photometric and its
lights fall off with the inverse square of the distance; facet's light of intensity I gives
irradiance pi I (facet.scene.pbr), so:

- directional, intensity in lux (irradiance E):   DirectionalLight, I = E / pi;
- point, intensity in candela (E = cd / d^2):     PointLight, I = cd / pi, attenuation
                                                  (0, 0, 1): 1 / d^2;
- spot, the same with innerConeAngle and outerConeAngle (radians, half-angles; facet's
  cone ends below 90 degrees).

``range`` (a fade to zero at that distance, which glTF leaves to the renderer) is not
modelled: one warning line says so.
"""

from __future__ import annotations

import numpy as np

from ..scene.light import DirectionalLight, PointLight, SpotLight

KINDS = ("directional", "point", "spot")


def document_lights(gltf, fail) -> list:
    """The raw light definitions (dicts) of the document, checked; ``fail(message)`` raises."""
    ext = (gltf.extensions or {}).get("KHR_lights_punctual")
    if ext is None:
        return []
    lights = ext.get("lights") if isinstance(ext, dict) else None
    if not isinstance(lights, list) or not all(isinstance(x, dict) for x in lights):
        fail("KHR_lights_punctual.lights must be a list of objects")
    for i, light in enumerate(lights):
        where = f"KHR_lights_punctual.lights[{i}]"
        if light.get("type") not in KINDS:
            fail(f"{where}.type must be one of {', '.join(KINDS)}, got {light.get('type')!r}")
        colour = light.get("color", [1.0, 1.0, 1.0])
        if not (isinstance(colour, list) and len(colour) == 3 and all(_number(c) and c >= 0
                                                                     for c in colour)):
            fail(f"{where}.color must be 3 numbers >= 0, got {colour!r}")
        intensity = light.get("intensity", 1.0)
        if not (_number(intensity) and intensity >= 0):
            fail(f"{where}.intensity must be a number >= 0, got {intensity!r}")
        spot = light.get("spot", {})
        if light["type"] == "spot":
            if not isinstance(spot, dict):
                fail(f"{where}.spot must be an object")
            inner, outer = spot.get("innerConeAngle", 0.0), spot.get("outerConeAngle",
                                                                     np.pi / 4)
            if not (_number(inner) and _number(outer) and 0 <= inner < outer <= np.pi / 2):
                fail(f"{where}.spot needs 0 <= innerConeAngle < outerConeAngle <= pi/2, got "
                     f"{inner!r}, {outer!r}")
    return lights


def node_light(node, lights: list, fail):
    """The index of the light a node names, or None."""
    ext = (node.extensions or {}).get("KHR_lights_punctual")
    if ext is None:
        return None
    index = ext.get("light") if isinstance(ext, dict) else None
    if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < len(lights):
        fail(f"a node's KHR_lights_punctual.light must index the document's "
             f"{len(lights)} lights, got {index!r}")
    return index


def facet_light(light: dict, world: np.ndarray):
    """The facet light of a glTF light placed by the node matrix ``world``."""
    colour = np.clip(np.asarray(light.get("color", [1.0, 1.0, 1.0]), dtype=np.float64), 0, 1)
    scale = float(light.get("intensity", 1.0)) / np.pi
    position = world[:3, 3]
    axis = -world[:3, 2]
    direction = axis / np.linalg.norm(axis) if np.linalg.norm(axis) > 0 else \
        np.array([0.0, 0.0, -1.0])
    kind = light["type"]
    if kind == "directional":
        return DirectionalLight(direction=direction, color=colour, intensity=scale)
    if kind == "point":
        return PointLight(position=position, color=colour, intensity=scale,
                          attenuation=(0.0, 0.0, 1.0))
    spot = light.get("spot", {})
    inner = np.degrees(spot.get("innerConeAngle", 0.0))
    outer = min(np.degrees(spot.get("outerConeAngle", np.pi / 4)), 89.9)
    return SpotLight(position=position, direction=direction, color=colour, intensity=scale,
                     attenuation=(0.0, 0.0, 1.0), inner_angle=min(inner, outer),
                     outer_angle=outer)


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v)
