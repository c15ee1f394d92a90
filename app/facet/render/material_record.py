"""The material record: one GPU layout of a material that every engine reads (numpy, no GL).

A material (a Phong ``Material``, or glTF's metallic-roughness ``PbrMaterial`` with its
extensions and every texture slot) is packed once into ``RECORD_TEXELS`` texels of four
floats. The rasterizer uploads them as one uniform array (``u_material``, per draw); the
tracers keep them in each instance's row of the ray scene (facet.render.rays.pack). Both
read them through one GLSL accessor, glsl/lib/material.glsl (``material_at``), which
multiplies the factors by their textures and applies the normal maps; the layering of the
surface (base, transmission share, sheen, coat) is glsl/lib/layers.glsl, written once.

Texels (``TEXELS``; GLSL reads them as REC_<NAME>, the alpha modes as ALPHA_MODE_<MODE>:
``record_defines``):

    color        (C rgb, k_a): the Phong model's colour, in the space lighting happens in
    phong        (k_d, k_s, shininess, opacity)
    effects      (reflectivity, Phong ior, gloss, the Phong image's layer or -1)
    base         (base colour rgb, metallic)          linear, as glTF's factors are
    emission     (emitted radiance rgb, roughness)    emissive x strength
    alpha        (base alpha, alpha mode, cutoff, normal scale)
    specular     ((ior - 1)^2 / (ior + 1)^2 x specular colour rgb, specular)
    transmission (transmission, thickness, ior, clear coat)
    absorption   (absorption per unit length rgb, clear coat roughness)
    sheen        (sheen colour rgb, sheen roughness)
    iridescence  (iridescence factor, film ior, film thickness min and max in nm)
    anisotropy   (anisotropy strength, cos and sin of its rotation, -)
    diffuse_t    (diffuse transmission colour rgb, diffuse transmission)
    dispersion   (the ior's half spread over R, G, B: (ior - 1) 0.025 dispersion, -, -, -)
    flags        (an emitter's light-sampling density (the path tracer's, per instance),
                  unlit, 1 for a metallic-roughness material, clear coat normal scale)
    occlusion    (occlusion strength, the share of light it stops for shadow maps
                  (facet.render.materials.shadow_opacity), -, -)

then ``SLOT_TEXELS`` per texture slot in facet.scene.pbr.SLOTS order (SLOT_<NAME>):
(the uv transform's first row, the image or -1 without one), (its second row, coordinate set
+ 2 (wrap s + 3 wrap t)), (the image's width and height, 1 for nearest filtering, -). What
"the image" is belongs to the engine: a layer of the tracers' texture array, a sampler of
the rasterizer's (1).
"""

from __future__ import annotations

import numpy as np

from ..scene.pbr import SLOTS, PbrMaterial
from .materials import as_pbr, shadow_opacity

TEXELS = {"color": 0, "phong": 1, "effects": 2, "base": 3, "emission": 4, "alpha": 5,
          "specular": 6, "transmission": 7, "absorption": 8, "sheen": 9, "flags": 10,
          "occlusion": 11, "iridescence": 12,
          "anisotropy": 13, "diffuse_t": 14, "dispersion": 15}
SLOT_ROW = len(TEXELS)
SLOT_TEXELS = 3
RECORD_TEXELS = SLOT_ROW + SLOT_TEXELS * len(SLOTS)
ALPHA_MODES = {"OPAQUE": 0, "MASK": 1, "BLEND": 2}
WRAPS = {"repeat": 0, "clamp": 1, "mirror": 2}


def record_defines() -> dict:
    """The layout's constants for the GLSL that reads it (glsl/lib/material.glsl)."""
    return {"RECORD_TEXELS": RECORD_TEXELS, "SLOT_ROW": SLOT_ROW, "SLOT_TEXELS": SLOT_TEXELS,
            "SLOT_COUNT": len(SLOTS),
            **{f"REC_{name.upper()}": k for name, k in TEXELS.items()},
            **{f"SLOT_{name.upper()}": k for k, name in enumerate(SLOTS)},
            **{f"ALPHA_MODE_{mode}": k for mode, k in ALPHA_MODES.items()}}


def material_record(material, color, image, phong_image: float = -1.0) -> np.ndarray:
    """(RECORD_TEXELS, 4) float32: ``material``'s record (module docstring).

    Parameters
    ----------
    material : Material or PbrMaterial
        A Phong material enters through its metallic-roughness mapping
        (facet.render.materials.as_pbr) as well as its own Phong terms.
    color : (3,) float
        C for the Phong model, in the space lighting happens in
        (facet.render.materials.phong_color).
    image : callable
        ``image(slot_name, slot) -> float``: what the engine reads the slot's image
        through (a layer, a sampler), or -1 where the engine reads it through none.
    phong_image : float
        The Phong model's image (its texture's layer), or -1.
    """
    m, pbr = material, as_pbr(material)
    out = np.zeros((RECORD_TEXELS, 4), np.float32)
    t = TEXELS
    out[t["color"]] = (*color, m.ka)
    out[t["phong"]] = (m.kd, m.ks, m.shininess, m.opacity)
    phong_ior = 0.0 if isinstance(m, PbrMaterial) else m.ior  # refraction: Phong's
    out[t["effects"]] = (m.reflectivity, phong_ior, m.gloss, phong_image)
    out[t["base"]] = (*pbr.base_color[:3], pbr.metallic)
    out[t["emission"]] = (*(pbr.emissive * pbr.emissive_strength), pbr.roughness)
    out[t["alpha"]] = (pbr.base_color[3], ALPHA_MODES[pbr.alpha_mode], pbr.alpha_cutoff,
                       pbr.normal_scale)
    out[t["specular"]] = (*(pbr.ior_f0 * pbr.specular_color), pbr.specular)
    out[t["transmission"]] = (pbr.transmission, pbr.thickness, pbr.ior, pbr.clearcoat)
    out[t["absorption"]] = (*pbr.absorption, pbr.clearcoat_roughness)
    out[t["sheen"]] = (*pbr.sheen_color, pbr.sheen_roughness)
    out[t["iridescence"]] = (pbr.iridescence, pbr.iridescence_ior,
                             pbr.iridescence_thickness_min, pbr.iridescence_thickness_max)
    out[t["anisotropy"]] = (pbr.anisotropy, np.cos(pbr.anisotropy_rotation),
                            np.sin(pbr.anisotropy_rotation), 0.0)
    out[t["diffuse_t"]] = (*pbr.diffuse_transmission_color, pbr.diffuse_transmission)
    out[t["dispersion"], 0] = (max(pbr.ior, 1.0) - 1.0) * 0.025 * pbr.dispersion
    out[t["flags"]] = (0.0, float(pbr.unlit), float(isinstance(m, PbrMaterial)),
                       pbr.clearcoat_normal_scale)
    out[t["occlusion"]] = (pbr.occlusion_strength, shadow_opacity(m), 0.0, 0.0)
    for k, name in enumerate(SLOTS):
        slot = getattr(pbr, f"{name}_texture")
        at = SLOT_ROW + SLOT_TEXELS * k
        out[at, 3] = out[at + 1, 3] = -1.0
        if slot is None:
            continue
        out[at, :3], out[at + 1, :3] = slot.transform[0], slot.transform[1]
        out[at, 3] = image(name, slot)
        out[at + 1, 3] = slot.texcoord + 2 * (WRAPS[slot.wrap[0]] + 3 * WRAPS[slot.wrap[1]])
        h, w = slot.texture.pixels.shape[:2]
        out[at + 2] = (w, h, float(slot.filter[1] == "nearest"), 0.0)
    return out
