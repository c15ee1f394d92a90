"""glTF's KHR material extensions -> PbrMaterial keywords (no GL), checked: a value of the
wrong type is one line naming the material and the field; a texture of an extension is
left out with one warning line (its factors are used).

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
# Textures left out (the volume's thicknessTexture scales the thickness a rasterizer's
# refraction assumes; the path tracer measures the volume itself: nothing to say).
TEXTURES = {
    "KHR_materials_specular": ("specularTexture", "specularColorTexture"),
    "KHR_materials_transmission": ("transmissionTexture",),
    "KHR_materials_clearcoat": ("clearcoatTexture", "clearcoatRoughnessTexture",
                                "clearcoatNormalTexture"),
    "KHR_materials_sheen": ("sheenColorTexture", "sheenRoughnessTexture"),
}


def extension_fields(ext: dict, name: str, fail, warn) -> dict:
    """PbrMaterial keywords from a material's ``extensions`` object. ``fail(message)``
    raises; ``warn(message)`` says one line."""
    out = {}
    for extension, fields in FIELDS.items():
        values = ext.get(extension)
        if not isinstance(values, dict):
            continue
        for key, keyword, kind in fields:
            if key in values:
                out[keyword] = _value(values[key], kind, f"material {name!r} {key}", fail)
        for key in TEXTURES.get(extension, ()):
            if key in values:
                warn(f"ignores {extension}'s {key} (material {name!r}: its factors are used)")
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
