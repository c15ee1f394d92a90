"""Materials as the shading models see them: which model draws an object, the Phong and
the physically based uniforms of a material, and the glTF samplers of its texture slots.

Colour spaces (facet.image.colorspace): a Phong ``Material``'s colours are values "as
given" (sRGB-encoded in the sRGB mode); a ``PbrMaterial``'s are linear. Each model gets
what it expects: the Phong models a PbrMaterial's colour encoded for display (in the
default mode), the pbr model a Material's colour decoded to linear.
"""

from __future__ import annotations

import numpy as np

from ..gl.bindings import SLOT_SAMPLERS
from ..scene.pbr import COLOR_SLOTS, PbrMaterial
from ..srgb import linear_to_srgb, srgb_to_linear

# glsl/mesh/slots.glsl's define of each slot: TEX_<SHORT> for its sampler u_tex_<short>.
SLOT_DEFINES = {s: f"TEX_{name[len('u_tex_'):].upper()}" for s, name in SLOT_SAMPLERS.items()}
SRGB_SLOTS = COLOR_SLOTS  # colour images; the others hold data


def slot_defines(m: PbrMaterial) -> tuple[str, ...]:
    """The TEX_* defines of ``m``'s slots; an occlusion map packed into the red channel of
    the metallic-roughness image (glTF's common "ORM" texture) is read from that one fetch
    (ORM_PACKED) instead of a second; NO_IRIDESCENCE, NO_ANISOTROPY,
    NO_DIFFUSE_TRANSMISSION and NO_DISPERSION without a thin film, an anisotropic lobe,
    diffuse transmission or dispersion (their code left out of the material's variant)."""
    slots = m.slots
    film = (() if m.iridescence > 0 else ("NO_IRIDESCENCE",)) + \
        (() if m.anisotropy > 0 else ("NO_ANISOTROPY",)) + \
        (() if m.diffuse_transmission > 0 else ("NO_DIFFUSE_TRANSMISSION",)) + \
        (() if m.dispersion > 0 else ("NO_DISPERSION",))
    mr, occ = slots.get("metallic_roughness"), slots.get("occlusion")
    if mr is not None and occ is not None and _same_lookup(mr, occ):
        return (*(SLOT_DEFINES[s] for s in slots if s != "occlusion"), "ORM_PACKED", *film)
    return (*(SLOT_DEFINES[s] for s in slots), *film)


def _same_lookup(a, b) -> bool:
    return (a.texture is b.texture and a.texcoord == b.texcoord and a.wrap == b.wrap and
            a.filter == b.filter and a.mipmaps == b.mipmaps and
            np.array_equal(a.transform, b.transform))


def model_for(shading: str, material) -> str:
    """The shading model that draws ``material`` under the ``shading`` option: "auto" is
    pbr for glTF's metallic-roughness materials and phong for the rest."""
    if shading == "auto":
        return "pbr" if isinstance(material, PbrMaterial) else "phong"
    return shading


def phong_color(material, state) -> np.ndarray:
    """C for the Phong models, in the space lighting happens in."""
    if isinstance(material, PbrMaterial):
        return material.color if state.srgb else linear_to_srgb(material.color)
    return state.to_linear(material.color)


def as_pbr(material) -> PbrMaterial:
    """A Phong ``Material`` drawn by the pbr model: a dielectric of the same colour whose
    GGX lobe matches the Phong exponent (roughness = (2 / (n + 2))^(1/4))."""
    if isinstance(material, PbrMaterial):
        return material
    cached = getattr(material, "_as_pbr", None)
    if cached is not None and cached[0] == _phong_key(material):
        return cached[1]
    from ..scene.pbr import TextureSlot

    rough = float((2.0 / (material.shininess + 2.0)) ** 0.25)
    pbr = PbrMaterial(
        base_color=np.append(srgb_to_linear(material.color), material.opacity), metallic=0.0,
        roughness=rough, alpha_mode="BLEND" if material.opacity < 1 else "OPAQUE",
        double_sided=True, name=material.name,
        base_color_texture=None if material.texture is None else
        TextureSlot(material.texture))
    object.__setattr__(material, "_as_pbr", (_phong_key(material), pbr))
    return pbr


def shadow_opacity(material) -> float:
    """How much of a light ``material`` stops, for shadow maps: its opacity, less what a
    transmitting glTF material lets through at normal incidence (transmission x (1 -
    metallic) x base colour x (1 - F0), the mean over RGB); the tracers' shadow rays take
    the same share at their own angle (glsl/trace/material.glsl, lets_through)."""
    if not isinstance(material, PbrMaterial) or material.transmission <= 0:
        return material.opacity
    passed = material.transmission * (1.0 - material.metallic) * float(np.mean(
        material.base_color[:3] * (1.0 - material.dielectric_f0)))
    return material.opacity * (1.0 - passed)


def _phong_key(m) -> tuple:
    return (tuple(m.color), m.shininess, m.opacity, id(m.texture))
