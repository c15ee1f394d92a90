"""A material in a rasterizer draw: its record (facet.render.material_record) as the
uniform array ``u_material`` of glsl/mesh/record.glsl (every mesh program's, the Phong
family's and the shadow pass's too: ``phong_record``), and for the metallic-roughness model
each texture slot's image at its sampler's unit (facet.gl.bindings) with the glTF sampler
settings of the slot. Mirrored axes clamp here and are folded in glsl/lib/material.glsl."""

from __future__ import annotations

from ...gl.bindings import SLOT_SAMPLERS, unit
from ...scene.pbr import PbrMaterial
from ..material_record import material_record
from ..materials import SRGB_SLOTS, phong_color


class SlotSamplers:
    """moderngl samplers for the texture slots' glTF settings, made once per setting.
    Mirrored axes clamp here and are folded in glsl/lib/material.glsl."""

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


def set_pbr_material(prog, m: PbrMaterial, cache, samplers: SlotSamplers,
                     records: dict | None = None) -> list[int]:
    """The pbr model's material: its record (facet.render.material_record) as the uniform
    array ``u_material`` and each slot's image at its sampler's unit; returns the units
    whose sampler objects were bound (the caller clears them after the draw). ``records``:
    a pass's {id(material): (material, record)}, each made once there."""
    bound = []
    for slot_name, slot in m.slots.items():
        at = unit(SLOT_SAMPLERS[slot_name])
        cache.texture(slot.texture, slot_name in SRGB_SLOTS, slot.mipmaps).use(location=at)
        samplers.get(slot).use(location=at)
        bound.append(at)
    made = None if records is None else records.get(id(m))
    if made is None or made[0] is not m:
        made = (m, record_of(m, m.color))
        if records is not None:
            records[id(m)] = made
    prog.set_array("u_material", made[1], strict=False)
    return bound


def phong_record(m, state):
    """(RECORD_TEXELS, 4) float32: ``m``'s record for the Phong family, its C in the space
    lighting happens in (facet.render.materials.phong_color)."""
    return record_of(m, phong_color(m, state))


def record_of(m, color=(0.0, 0.0, 0.0)):
    """(RECORD_TEXELS, 4) float32: ``m``'s record with C = ``color`` (the shadow pass
    reads no colour); each slot's image is at its sampler's own unit."""
    return material_record(m, color, lambda name, slot: 0.0)  # (>= 0: "has an image")
