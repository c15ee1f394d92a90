"""What a mesh program is specialised on (``Variant``: each field a define of glsl/mesh),
and whether a Phong draw's material-light products are grey (``light_products``,
``grey_terms``: the GREY_TERMS variant)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ...gl.targets import aux_locations
from ...scene.scene import MAX_LIGHTS
from ..material_record import record_defines
from ..materials import phong_color
from ..shading import SHADING_MODELS, check_shading
from ..state import FrameState
from .ibl import LUT_SIZE
from .skinning import POSE_DEFINES


@dataclass(frozen=True)
class Variant:
    """Everything a program is specialised on (each becomes a define in glsl/mesh)."""

    shading: str
    light_kinds: tuple[int, ...] = ()  # LIGHT_* of each light, in order
    aux: tuple[str, ...] = ()  # auxiliary outputs (facet.gl.targets)
    orthographic: bool = False  # the view direction is a constant
    texture: bool = False
    vertex_colors: bool = False
    srgb: bool = False  # vertex colours are sRGB-encoded
    linear_out: bool = False  # float output: the pbr model writes linear light
    shadow_slots: tuple[int, ...] | None = None  # per light: its first shadow tile, or -1
    shadow_tiles: int = 0  # tiles in the shadow atlas
    shadow_pcf: int = 1  # PCF kernel radius in texels
    oit: bool = False  # the transparent pass (into the OIT sums, raster.transparency)
    environment: bool = False  # reflects / refracts the scene's environment
    mirror: bool = False  # mixes in its planar reflection (facet.render.raster.mirror)
    clip_plane: bool = False  # discards what is behind a mirror (its reflection pass)
    slots: tuple[str, ...] = ()  # the pbr model's TEX_* defines (materials.slot_defines)
    uv1: bool = False  # the mesh has a second texture coordinate set
    tangents: bool = False  # normal mapping: the mesh's tangent frames
    alpha_mask: bool = False  # glTF alphaMode MASK: discard below the cutoff
    exact_only: bool = False  # a pass for the exact channels alone: no colour computed
    grey: bool = False  # every material-light term is grey (see grey_terms)
    transmission: bool = False  # refracts the picture behind it (raster.transmission)
    instanced: bool = False  # matrices per instance (facet.render.raster.instancing)
    sprite: str = ""  # "points" or "lines": quads per point or segment (mesh/sprite.vert)
    edl: bool = False  # eye-dome lighting of an unlit cloud (facet.render.raster.edl)
    edl_depth: bool = False  # the cloud's depth pass for it
    skin: int = 0  # skinned in the vertex shader: 4 or 8 influences (raster.skinning)
    morph: bool = False  # morphed in the vertex shader (raster.skinning)

    @classmethod
    def of(cls, state: FrameState, aux=(), oit: bool = False) -> Variant:
        """The frame's base variant (each object's is made from it)."""
        s = state.shadows
        return base_variant(state.shading, state.light_kinds, tuple(aux),
                             state.camera.is_orthographic, state.srgb,
                             s.slots if s else None, s.tiles if s else 0, s.pcf if s else 1,
                             oit, state.clip_plane is not None, state.linear_out)

    def defines(self) -> dict:
        spec = SHADING_MODELS[check_shading(self.shading)]
        d = {spec.define: None, "MAX_LIGHTS": MAX_LIGHTS, "LIGHT_COUNT": len(self.light_kinds)}
        if self.light_kinds:
            kinds = ", ".join(map(str, self.light_kinds))
            d["LIGHT_KIND_LIST"] = f"int[{len(self.light_kinds)}]({kinds})"
        for name, location in aux_locations(self.aux).items():
            d[f"OUT_{name.upper()}"] = location
        if self.shadow_slots is not None and self.light_kinds:
            d["SHADOWS"] = None
            slots = ", ".join(map(str, self.shadow_slots))
            d["LIGHT_SHADOW_LIST"] = f"int[{len(self.shadow_slots)}]({slots})"
            d["SHADOW_TILES"] = max(self.shadow_tiles, 1)
            d["SHADOW_PCF"] = self.shadow_pcf
        d.update({s: None for s in self.slots})
        d.update(record_defines())  # the material record's layout (glsl/mesh/record.glsl)
        if self.shading == "pbr":
            d["LUT_SIZE"] = float(LUT_SIZE)  # the split-sum table's (facet.render.raster.ibl)
        flags = {"VIEW_ORTHOGRAPHIC": self.orthographic, "HAS_TEXTURE": self.texture,
                 "HAS_UV1": self.uv1, "HAS_TANGENTS": self.tangents,
                 "ALPHA_MASK": self.alpha_mask, "EXACT_ONLY": self.exact_only,
                 "HAS_VERTEX_COLORS": self.vertex_colors, "COLOR_SRGB": self.srgb,
                 "OIT": self.oit, "HAS_ENVIRONMENT": self.environment,
                 "HAS_MIRROR": self.mirror, "CLIP_PLANE": self.clip_plane,
                 "GREY_TERMS": self.grey, "LINEAR_OUT": self.linear_out,
                 "TRANSMISSION": self.transmission, "INSTANCED": self.instanced,
                 "SPRITE_POINTS": self.sprite == "points",
                 "SPRITE_LINES": self.sprite == "lines", "EDL": self.edl,
                 "EDL_DEPTH": self.edl_depth, "SKINNED": self.skin > 0,
                 "SKIN_8": self.skin > 4, "MORPHED": self.morph}
        d.update({k: None for k, on in flags.items() if on})
        if self.skin or self.morph:
            d.update(POSE_DEFINES)
        return d


LIT = ("phong", "blinn", "flat", "gouraud")  # the models that evaluate shade_scene


def light_products(m, state: FrameState, ambient, intensities) -> tuple:
    """C and the material's products with each light, as glsl/lib/lights.glsl forms them
    from the material record (I_a k_a C, I_i k_d C, I_i k_s): what ``grey_terms`` asks."""
    color = np.asarray(phong_color(m, state), dtype=np.float64)
    return color, ambient * m.ka * color, intensities * (m.kd * color), intensities * m.ks


def grey_terms(terms) -> bool:
    """Whether every product of ``light_products`` is grey (equal channels), as an
    untextured grey material under white lights gives: then the program reads one channel
    of each (GREY_TERMS), and the compiler computes one colour channel where it would
    compute three. The picture is the same; a software rasteriser shades ~5% faster."""
    _, *products = terms
    return all(r == r[:1] * 3 for t in products for r in np.reshape(t, (-1, 3)).tolist())


@lru_cache(maxsize=64)  # asked for on every draw; a handful of distinct ones in a run
def base_variant(shading, light_kinds, aux, orthographic, srgb, slots, tiles, pcf, oit,
                  clip_plane, linear_out=False) -> Variant:
    # "auto" picks a model per material (facet.render.materials.model_for); the base
    # variant, which users' shaders see, is phong's.
    return Variant("phong" if shading == "auto" else shading, light_kinds,
                   tuple(aux_locations(aux)), orthographic, srgb=srgb, shadow_slots=slots,
                   shadow_tiles=tiles, shadow_pcf=pcf, oit=oit, clip_plane=clip_plane,
                   linear_out=linear_out)
