"""Scene files: metallic-roughness materials (facet.formats.scenefile reads the rest).

A material table (``[materials.NAME]`` or an object's inline ``material = {...}``) that
holds any of ``PBR`` keys is a glTF metallic-roughness ``PbrMaterial``; one with only
Phong keys stays a Phong ``Material``; the two kinds of key do not mix (one line says
which key belongs to which). Colours here are linear, as glTF's factors are:

    [materials.gold]
    base_color = [1.0, 0.77, 0.34]     # 3 or 4 (alpha) numbers in [0, 1]
    metallic = 1.0
    roughness = 0.3
    specular = 1.0                     # KHR_materials_specular: 0 leaves Lambert
    specular_color = [1, 1, 1]
    ior = 1.5                          # KHR_materials_ior
    emissive = [0, 0, 0]
    emissive_strength = 1.0
    transmission = 0.0                 # KHR_materials_transmission: glass is 1
    thickness = 0.0                    # 0: thin-walled; > 0: a volume (KHR_materials_volume)
    attenuation_color = [1, 1, 1]      # what is left after attenuation_distance inside
    attenuation_distance = 1e30
    clearcoat = 0.0                    # KHR_materials_clearcoat: a clear layer on top
    clearcoat_roughness = 0.0
    sheen_color = [0, 0, 0]            # KHR_materials_sheen: cloth's soft rim
    sheen_roughness = 0.0
    alpha_mode = "OPAQUE"              # or MASK (with alpha_cutoff) or BLEND
    double_sided = false
    base_color_texture = "albedo.png"  # or a table: image, texcoord, wrap, filter,
                                       # offset, rotation (degrees), scale: as
                                       # KHR_texture_transform
    # and every other slot of facet.scene.pbr.SLOTS as <slot>_texture (normal,
    # occlusion, emissive, specular, specular_color, transmission, thickness, clearcoat,
    # clearcoat_roughness, clearcoat_normal, sheen_color, sheen_roughness)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import FacetError
from ..scene.material import Material
from ..scene.pbr import ALPHA_MODES, FILTERS, SLOTS, WRAP_MODES, PbrMaterial, TextureSlot
from ..scene.pbr import texture_transform as _uv_transform
from .validate import AnyKey, show

PBR = ("base_color", "metallic", "roughness", "specular", "specular_color", "emissive",
       "emissive_strength", "alpha_mode", "alpha_cutoff", "double_sided", "normal_scale",
       "occlusion_strength", "unlit", "transmission", "thickness", "attenuation_color",
       "attenuation_distance", "clearcoat", "clearcoat_roughness", "sheen_color",
       "sheen_roughness", "clearcoat_normal_scale", "iridescence", "iridescence_ior",
       "iridescence_thickness_min", "iridescence_thickness_max", "anisotropy",
       "anisotropy_rotation", "diffuse_transmission", "diffuse_transmission_color",
       "dispersion",
       *(f"{s}_texture" for s in SLOTS))
SHARED = ("ior",)  # a Phong material's refraction, a metallic-roughness one's dielectric
SLOT_KEYS = ("image", "texcoord", "wrap", "filter", "offset", "rotation", "scale")
UNIT_KEYS = ("metallic", "roughness", "specular", "alpha_cutoff", "occlusion_strength",
             "transmission", "clearcoat", "clearcoat_roughness", "sheen_roughness",
             "iridescence", "anisotropy", "diffuse_transmission")


def is_pbr(t: dict) -> bool:
    """Whether the material table ``t`` describes a metallic-roughness material."""
    return any(key in t for key in PBR)


def read_pbr(r, t: dict, where: str, phong_keys, texture) -> PbrMaterial:
    """The PbrMaterial of table ``t``. ``phong_keys``: the Phong material's keys (refused
    here with a pointer); ``texture(value, where)``: an image loaded like a Phong texture."""
    for key in t:
        if key in phong_keys and key not in SHARED:
            r.fail(f"{where}.{key}", f"a Phong key in a metallic-roughness material (it has "
                   f"{next(k for k in t if k in PBR)}); use base_color, metallic, roughness, "
                   "... or only Phong keys")
    r.table(t, where, PBR + SHARED)
    kw = {}
    if "base_color" in t:
        kw["base_color"] = r.color(t["base_color"], f"{where}.base_color", channels=(3, 4))
    if "sheen_color" in t:
        kw["sheen_color"] = r.color(t["sheen_color"], f"{where}.sheen_color")
    if "attenuation_color" in t:
        kw["attenuation_color"] = r.color(t["attenuation_color"], f"{where}.attenuation_color")
    if "attenuation_distance" in t:
        kw["attenuation_distance"] = r.number(t["attenuation_distance"],
                                              f"{where}.attenuation_distance", above=0)
    for key in ("emissive", "specular_color"):
        if key in t:
            kw[key] = r.vector(t[key], f"{where}.{key}")
            if kw[key].min() < 0:
                r.fail(f"{where}.{key}", f"expected numbers >= 0, got {show(t[key])}")
    for key in UNIT_KEYS:
        if key in t:
            kw[key] = r.number(t[key], f"{where}.{key}", minimum=0)
            if kw[key] > 1:
                r.fail(f"{where}.{key}", f"expected a number in [0, 1], got {show(t[key])}")
    if "diffuse_transmission_color" in t:
        kw["diffuse_transmission_color"] = r.color(t["diffuse_transmission_color"],
                                                   f"{where}.diffuse_transmission_color")
    for key in ("emissive_strength", "normal_scale", "thickness", "clearcoat_normal_scale",
                "iridescence_thickness_min", "iridescence_thickness_max", "dispersion"):
        if key in t:
            kw[key] = r.number(t[key], f"{where}.{key}", minimum=0)
    if "iridescence_ior" in t:
        kw["iridescence_ior"] = r.number(t["iridescence_ior"], f"{where}.iridescence_ior",
                                         minimum=1)
    if "anisotropy_rotation" in t:
        kw["anisotropy_rotation"] = r.number(t["anisotropy_rotation"],
                                             f"{where}.anisotropy_rotation")
    if "ior" in t:
        kw["ior"] = r.number(t["ior"], f"{where}.ior", minimum=0)
        if 0 < kw["ior"] < 1:
            r.fail(f"{where}.ior", f"expected a number >= 1 (or 0), got {show(t['ior'])}")
    if "alpha_mode" in t:
        kw["alpha_mode"] = r.choice(t["alpha_mode"], f"{where}.alpha_mode", ALPHA_MODES)
    for key in ("double_sided", "unlit"):
        if key in t:
            if not isinstance(t[key], bool):
                r.fail(f"{where}.{key}", f"expected true or false, got {show(t[key])}")
            kw[key] = t[key]
    for slot in SLOTS:
        key = f"{slot}_texture"
        if key in t:
            kw[key] = _slot(r, t[key], f"{where}.{key}", texture)
    try:
        return PbrMaterial(**kw, name=where.rsplit(".", 1)[-1])
    except FacetError as exc:
        r.fail(where, str(exc))


def _slot(r, value, where: str, texture) -> TextureSlot:
    """A texture slot: an image path, or a table of SLOT_KEYS."""
    if not isinstance(value, dict):
        return TextureSlot(texture(value, where))
    r.table(value, where, SLOT_KEYS)
    if "image" not in value:
        r.fail(where, "a texture table needs image = \"path\"")
    kw = {}
    if "texcoord" in value:
        if value["texcoord"] not in (0, 1) or isinstance(value["texcoord"], bool):
            r.fail(f"{where}.texcoord", f"expected 0 or 1, got {show(value['texcoord'])}")
        kw["texcoord"] = int(value["texcoord"])
    for key, allowed in (("wrap", WRAP_MODES), ("filter", FILTERS)):
        if key in value:
            v = value[key]
            pair = [v, v] if isinstance(v, str) else v
            if not (isinstance(pair, list) and len(pair) == 2):
                r.fail(f"{where}.{key}", f"expected one or two of {', '.join(allowed)}, "
                       f"got {show(v)}")
            kw[key] = tuple(r.choice(p, f"{where}.{key}", allowed) for p in pair)
    offset = r.vector(value["offset"], f"{where}.offset", 2) if "offset" in value \
        else (0.0, 0.0)
    scale = r.vector(value["scale"], f"{where}.scale", 2) if "scale" in value else (1.0, 1.0)
    rotation = r.number(value["rotation"], f"{where}.rotation") if "rotation" in value \
        else 0.0
    kw["transform"] = _uv_transform(offset, np.radians(rotation), scale)
    return TextureSlot(texture(value["image"], f"{where}.image"), **kw)


MATERIAL = ("color", "ka", "kd", "ks", "shininess", "opacity", "reflectivity", "ior",
            "gloss", "mirror", "texture", "shader", "vertex_shader", "uniforms")


class MaterialTables:
    """The scene file reader's material tables, shaders and textures (its ``r``, ``base``,
    ``uniforms`` and ``texture_cache``: facet.formats.scenefile)."""

    def material(self, t, where: str) -> Material | PbrMaterial:
        r = self.r
        if isinstance(t, dict) and is_pbr(t):
            return read_pbr(r, t, where, MATERIAL, self.texture)
        r.table(t, where, MATERIAL + PBR)  # (PBR: for "did you mean" only)
        kw: dict[str, Any] = {"color": r.color(t["color"], f"{where}.color")} \
            if "color" in t else {}
        for key in ("ka", "kd", "ks", "shininess"):
            if key in t:
                kw[key] = r.number(t[key], f"{where}.{key}", minimum=0)
        for key, hi in (("reflectivity", 1.0), ("ior", 5.0), ("gloss", 1.0)):
            if key in t:
                kw[key] = r.number(t[key], f"{where}.{key}", minimum=0)
                if kw[key] > hi:
                    r.fail(f"{where}.{key}", f"expected a number in [0, {hi:g}], got {t[key]}")
        if "opacity" in t:
            kw["opacity"] = r.number(t["opacity"], f"{where}.opacity", minimum=0)
            if kw["opacity"] > 1:
                r.fail(f"{where}.opacity", f"expected a number in [0, 1], got {t['opacity']}")
        if "mirror" in t:
            if not isinstance(t["mirror"], bool):
                r.fail(f"{where}.mirror", f"expected true or false, got {show(t['mirror'])}")
            if t["mirror"] and not kw.get("reflectivity"):
                r.fail(f"{where}.mirror", "a mirror needs reflectivity > 0 (1: a perfect "
                       "mirror)")
            kw["mirror"] = t["mirror"]
        if "texture" in t:
            kw["texture"] = self.texture(t["texture"], f"{where}.texture")
        if "shader" in t:
            kw["shader"] = self.shader(t, where)
        elif "vertex_shader" in t or "uniforms" in t:
            r.fail(where, "vertex_shader and uniforms belong to a material with a 'shader'")
        return Material(**kw, name=where.rsplit(".", 1)[-1])

    def shader(self, t: dict, where: str):
        """A material's own GLSL: shader (fragment), vertex_shader, and uniforms (the
        file-wide [uniforms] table first, the material's own on top)."""
        from ..scene.shader import UserShader

        r = self.r
        uniforms = dict(self.uniforms)
        own = r.table(t.get("uniforms", {}), f"{where}.uniforms", AnyKey())
        for name, value in own.items():
            uniforms[name] = self.uniform_value(value, f"{where}.uniforms.{name}")
        frag = self.base / r.string(t["shader"], f"{where}.shader")
        vert = self.base / r.string(t["vertex_shader"], f"{where}.vertex_shader") \
            if "vertex_shader" in t else None
        try:
            return UserShader(frag, vert, uniforms)
        except FacetError as exc:
            r.fail(f"{where}.shader", str(exc))

    def uniform_value(self, value, where: str) -> list[float]:
        if isinstance(value, list):
            return [self.r.number(v, f"{where}[{i}]") for i, v in enumerate(value)]
        return [self.r.number(value, where)]

    def texture(self, value, where: str):
        """A texture: an image path (relative to the scene file) or "checker"."""
        from ..scene.texture import Texture

        name = self.r.string(value, where)
        if name == "checker":
            return Texture.checker()
        path = self.base / name
        if path not in self.texture_cache:
            try:
                self.texture_cache[path] = Texture.load(path)
            except FacetError as exc:
                self.r.fail(where, str(exc))
        return self.texture_cache[path]
