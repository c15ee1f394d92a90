"""glTF's KHR material extensions -> PbrMaterial keywords (no GL), checked: a value of the
wrong type is one line naming the material and the field; their textures become the
material's slots (TEXTURES).

    KHR_materials_ior           ior (>= 1, or 0)
    KHR_materials_specular      specularFactor, specularColorFactor
    KHR_materials_transmission  transmissionFactor
    KHR_materials_volume        thicknessFactor, attenuationDistance, attenuationColor
    KHR_materials_clearcoat     clearcoatFactor, clearcoatRoughnessFactor
    KHR_materials_sheen         sheenColorFactor, sheenRoughnessFactor
    KHR_materials_iridescence   iridescenceFactor, iridescenceIor, iridescenceThickness-
                                Minimum and -Maximum (nm)
    KHR_materials_anisotropy    anisotropyStrength, anisotropyRotation (radians)
    KHR_materials_diffuse_transmission   diffuseTransmissionFactor, -ColorFactor
    KHR_materials_dispersion    dispersion (20 / Abbe number)
    KHR_materials_pbrSpecularGlossiness   (archived; files made before 2022 still use it)
        converted as KHR_materials_specular describes: the diffuse colour is the base
        colour, the specular colour is the dielectric's F0 colour with ior 0 (F0 = that
        colour), metallic 0, roughness 1 - glossiness (the glossiness in the
        specular-glossiness texture's alpha becomes a roughness image)
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
    "KHR_materials_iridescence": (("iridescenceFactor", "iridescence", "unit"),
                                  ("iridescenceIor", "iridescence_ior", "film ior"),
                                  ("iridescenceThicknessMinimum", "iridescence_thickness_min",
                                   "length"),
                                  ("iridescenceThicknessMaximum", "iridescence_thickness_max",
                                   "length")),
    "KHR_materials_anisotropy": (("anisotropyStrength", "anisotropy", "unit"),
                                 ("anisotropyRotation", "anisotropy_rotation", "angle")),
    "KHR_materials_diffuse_transmission": (
        ("diffuseTransmissionFactor", "diffuse_transmission", "unit"),
        ("diffuseTransmissionColorFactor", "diffuse_transmission_color", "colour")),
    "KHR_materials_dispersion": (("dispersion", "dispersion", "length"),),
}
SPEC_GLOSS = "KHR_materials_pbrSpecularGlossiness"
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
    "KHR_materials_iridescence": (("iridescenceTexture", "iridescence"),
                                  ("iridescenceThicknessTexture", "iridescence_thickness")),
    "KHR_materials_anisotropy": (("anisotropyTexture", "anisotropy"),),
    "KHR_materials_diffuse_transmission": (
        ("diffuseTransmissionTexture", "diffuse_transmission"),
        ("diffuseTransmissionColorTexture", "diffuse_transmission_color")),
    SPEC_GLOSS: (("diffuseTexture", "base_color"),
                 ("specularGlossinessTexture", "specular_color")),
}


def extension_fields(ext: dict, name: str, fail, slot) -> dict:
    """PbrMaterial keywords from a material's ``extensions`` object. ``fail(message)``
    raises; ``slot(info)`` makes a TextureSlot of a textureInfo object (or None)."""
    out = {}
    for extension in {**FIELDS, **TEXTURES}:
        values = ext.get(extension)
        if not isinstance(values, dict):
            continue
        for key, keyword, kind in FIELDS.get(extension, ()):
            if key in values:
                out[keyword] = _value(values[key], kind, f"material {name!r} {key}", fail)
        for key, keyword in TEXTURES.get(extension, ()):
            info = values.get(key)  # checked by facet.formats.gltf_check with the core's
            if info is None:
                continue
            out[f"{keyword}_texture"] = slot(info)
            if keyword == "clearcoat_normal" and "scale" in info:
                out["clearcoat_normal_scale"] = abs(float(info["scale"]))
    if isinstance(ext.get(SPEC_GLOSS), dict):
        out.update(_spec_gloss(ext[SPEC_GLOSS], name, fail, out.get("specular_color_texture")))
    return out


def _spec_gloss(values: dict, name: str, fail, texture) -> dict:
    """PbrMaterial keywords of a specular-glossiness material (module docstring);
    ``texture``: the slot of its specularGlossinessTexture (or None)."""
    what = f"material {name!r} KHR_materials_pbrSpecularGlossiness"
    diffuse = values.get("diffuseFactor", [1.0, 1.0, 1.0, 1.0])
    if not (isinstance(diffuse, list) and len(diffuse) == 4):
        fail(f"{what} diffuseFactor must be 4 numbers, got {diffuse!r}")
    out = {"base_color": [float(np.clip(_number(x, f"{what} diffuseFactor", fail), 0, 1))
                          for x in diffuse],
           "specular_color": _value(values.get("specularFactor", [1.0, 1.0, 1.0]), "colour",
                                    f"{what} specularFactor", fail),
           "specular": 1.0, "ior": 0.0, "metallic": 0.0}
    gloss = _value(values.get("glossinessFactor", 1.0), "unit", f"{what} glossinessFactor",
                   fail)
    out["roughness"] = 1.0 - gloss
    if texture is not None:
        from dataclasses import replace

        from ..scene.texture import Texture

        alpha = texture.texture.pixels[..., 3].astype(np.float64) / 255.0
        rough = np.empty(texture.texture.pixels.shape, np.uint8)
        rough[..., 0] = 0
        rough[..., 1] = np.rint(255.0 * (1.0 - gloss * alpha))  # (metallic-roughness: G)
        rough[..., 2] = 0
        rough[..., 3] = 255
        out["roughness"] = 1.0
        out["metallic_roughness_texture"] = replace(
            texture, texture=Texture(rough, f"{texture.texture.name} (roughness)"))
    return out


def _value(v, kind: str, what: str, fail):
    if kind in ("colour", "tint"):
        if not (isinstance(v, list) and len(v) == 3):
            fail(f"{what} must be 3 numbers, got {v!r}")
        numbers = [_number(x, what, fail) for x in v]
        return [float(np.clip(x, 0, 1)) if kind == "colour" else max(x, 0.0) for x in numbers]
    x = _number(v, what, fail)
    if kind == "angle":
        return x
    if kind == "unit":
        return float(np.clip(x, 0, 1))
    if kind == "ior" and x != 0 and x < 1:
        fail(f"{what} must be >= 1 (or 0), got {x}")
    if kind == "film ior" and x < 1:
        fail(f"{what} must be >= 1, got {x}")
    if kind == "distance" and x <= 0:
        fail(f"{what} must be > 0, got {x}")
    return max(x, 0.0)


def _number(v, what: str, fail) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v):
        fail(f"{what} must be a finite number, got {v!r}")
    return float(v)
