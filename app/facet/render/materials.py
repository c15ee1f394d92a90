"""Materials as the shading models see them: which model draws an object, the Phong and
the physically based uniforms of a material, and the glTF samplers of its texture slots.

Colour spaces (facet.image.colorspace): a Phong ``Material``'s colours are values "as
given" (sRGB-encoded in the sRGB mode); a ``PbrMaterial``'s are linear. Each model gets
what it expects: the Phong models a PbrMaterial's colour encoded for display (in the
default mode), the pbr model a Material's colour decoded to linear.
"""

from __future__ import annotations

import numpy as np

from ..gl.bindings import SLOT_SAMPLERS, unit
from ..scene.pbr import COLOR_SLOTS, PbrMaterial
from ..srgb import linear_to_srgb, srgb_to_linear

# glsl/mesh/slots.glsl's define of each slot: TEX_<SHORT> for its sampler u_tex_<short>.
SLOT_DEFINES = {s: f"TEX_{name[len('u_tex_'):].upper()}" for s, name in SLOT_SAMPLERS.items()}
SRGB_SLOTS = COLOR_SLOTS  # colour images; the others hold data


def slot_defines(m: PbrMaterial) -> tuple[str, ...]:
    """The TEX_* defines of ``m``'s slots; an occlusion map packed into the red channel of
    the metallic-roughness image (glTF's common "ORM" texture) is read from that one fetch
    (ORM_PACKED) instead of a second."""
    slots = m.slots
    mr, occ = slots.get("metallic_roughness"), slots.get("occlusion")
    if mr is not None and occ is not None and _same_lookup(mr, occ):
        return (*(SLOT_DEFINES[s] for s in slots if s != "occlusion"), "ORM_PACKED")
    return tuple(SLOT_DEFINES[s] for s in slots)


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


class SlotSamplers:
    """moderngl samplers for the texture slots' glTF settings, made once per setting.
    Mirrored axes clamp here and are mirrored in glsl/mesh/pbr.frag."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._samplers: dict[tuple, object] = {}

    def get(self, slot):
        key = (slot.wrap, slot.filter, slot.mipmaps)
        if key not in self._samplers:
            near = {"nearest": self.ctx.NEAREST, "linear": self.ctx.LINEAR}
            mip = {"nearest": self.ctx.NEAREST_MIPMAP_LINEAR,
                   "linear": self.ctx.LINEAR_MIPMAP_LINEAR}
            minify = (mip if slot.mipmaps else near)[slot.filter[0]]
            self._samplers[key] = self.ctx.sampler(
                repeat_x=slot.wrap[0] == "repeat", repeat_y=slot.wrap[1] == "repeat",
                filter=(minify, near[slot.filter[1]]))
        return self._samplers[key]

    def release(self) -> None:
        for s in self._samplers.values():
            s.release()
        self._samplers.clear()


def set_pbr_material(prog, m: PbrMaterial, cache, samplers: SlotSamplers) -> list[int]:
    """The pbr model's material: its record (facet.render.material_record) as the uniform
    array ``u_material`` and each slot's image at its sampler's unit; returns the units
    whose sampler objects were bound (the caller clears them after the draw)."""
    from .material_record import material_record

    bound = []
    for slot_name, slot in m.slots.items():
        at = unit(SLOT_SAMPLERS[slot_name])
        cache.texture(slot.texture, slot_name in SRGB_SLOTS, slot.mipmaps).use(location=at)
        samplers.get(slot).use(location=at)
        bound.append(at)
    prog.set_array("u_material", material_record(m, m.color, lambda name, slot: 0.0),
                   strict=False)
    return bound
