"""glTF's KHR material extensions -> PbrMaterial keywords (no GL), checked: a value of the
wrong type is one line naming the material and the field; their textures become the
material's slots (TEXTURES).

    KHR_materials_ior           ior (>= 1, or 0)
    KHR_materials_specular      specularFactor, specularColorFactor
    KHR_materials_transmission  transmissionFactor
    KHR_materials_volume        thicknessFactor, attenuationDistance, attenuationColor
    KHR_materials_clearcoat     clearcoatFactor, clearcoatRoughnessFactor
    KHR_materials_sheen         sheenColorFactor, sheenRoughnessFactor
"""

from __future__ import annotations

import numpy as np

# extension -> (glTF field, PbrMaterial keyword, kind); kinds: "unit" in [0, 1] (clipped),
# "ior", "length" >= 0, "distance" > 0, "colour" 3 in [0, 1] (clipped), "tint" 3 >= 0.
FIELDS = {
    "KHR_materials_ior": (("ior", "ior", "ior"),),
    "KHR_materials_specular": (("specularFactor", "specular", "unit"),
                               ("specularColorFactor", "specular_color", "tint")),
    "KHR_materials_transmission": (("transmissionFactor", "transmission", "unit"),),
    "KHR_materials_volume": (("thicknessFactor", "thickness", "length"),
                             ("attenuationDistance", "attenuation_distance", "distance"),
                             ("attenuationColor", "attenuation_color", "colour")),
    "KHR_materials_clearcoat": (("clearcoatFactor", "clearcoat", "unit"),
                                ("clearcoatRoughnessFactor", "clearcoat_roughness", "unit")),
    "KHR_materials_sheen": (("sheenColorFactor", "sheen_color", "colour"),
                            ("sheenRoughnessFactor", "sheen_roughness", "unit")),
}
# extension -> (glTF textureInfo field, PbrMaterial slot)
TEXTURES = {
    "KHR_materials_specular": (("specularTexture", "specular"),
                               ("specularColorTexture", "specular_color")),
    "KHR_materials_transmission": (("transmissionTexture", "transmission"),),
    "KHR_materials_volume": (("thicknessTexture", "thickness"),),
    "KHR_materials_clearcoat": (("clearcoatTexture", "clearcoat"),
                                ("clearcoatRoughnessTexture", "clearcoat_roughness"),
                                ("clearcoatNormalTexture", "clearcoat_normal")),
    "KHR_materials_sheen": (("sheenColorTexture", "sheen_color"),
                            ("sheenRoughnessTexture", "sheen_roughness")),
}


def extension_fields(ext: dict, name: str, fail, slot) -> dict:
    """PbrMaterial keywords from a material's ``extensions`` object. ``fail(message)``
    raises; ``slot(info)`` makes a TextureSlot of a textureInfo object (or None)."""
    out = {}
    for extension, fields in FIELDS.items():
        values = ext.get(extension)
        if not isinstance(values, dict):
            continue
        for key, keyword, kind in fields:
            if key in values:
                out[keyword] = _value(values[key], kind, f"material {name!r} {key}", fail)
        for key, keyword in TEXTURES.get(extension, ()):
            info = values.get(key)  # checked by facet.formats.gltf_check with the core's
            if info is None:
                continue
            out[f"{keyword}_texture"] = slot(info)
            if keyword == "clearcoat_normal" and "scale" in info:
                out["clearcoat_normal_scale"] = abs(float(info["scale"]))
    return out


def _value(v, kind: str, what: str, fail):
    if kind in ("colour", "tint"):
        if not (isinstance(v, list) and len(v) == 3):
            fail(f"{what} must be 3 numbers, got {v!r}")
        numbers = [_number(x, what, fail) for x in v]
        return [float(np.clip(x, 0, 1)) if kind == "colour" else max(x, 0.0) for x in numbers]
    x = _number(v, what, fail)
    if kind == "unit":
        return float(np.clip(x, 0, 1))
    if kind == "ior" and x != 0 and x < 1:
        fail(f"{what} must be >= 1 (or 0), got {x}")
    if kind == "distance" and x <= 0:
        fail(f"{what} must be > 0, got {x}")
    return max(x, 0.0)


def _number(v, what: str, fail) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v):
        fail(f"{what} must be a finite number, got {v!r}")
    return float(v)
