"""The shading-model table: model name (facet.options.render.SHADING) -> the GLSL stages and
define that implement it. Render code picks its program by this table."""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError
from ..options.render import SHADING


@dataclass(frozen=True)
class ProgramSpec:
    vertex: str  # path under glsl/
    fragment: str
    define: str  # selects the model inside the shared stage files


SHADING_MODELS: dict[str, ProgramSpec] = {
    "phong": ProgramSpec("mesh/phong.vert", "mesh/phong.frag", "SHADE_PHONG"),
    "blinn": ProgramSpec("mesh/phong.vert", "mesh/phong.frag", "SHADE_BLINN"),
    "gouraud": ProgramSpec("mesh/phong.vert", "mesh/phong.frag", "SHADE_GOURAUD"),
    "flat": ProgramSpec("mesh/phong.vert", "mesh/phong.frag", "SHADE_FLAT"),
    "unlit": ProgramSpec("mesh/phong.vert", "mesh/phong.frag", "SHADE_UNLIT"),
    "normals": ProgramSpec("mesh/phong.vert", "mesh/phong.frag", "SHADE_NORMALS"),
    # glTF metallic-roughness (glsl/lib/pbr.glsl); Phong materials drawn by it become
    # dielectrics of their colour (facet.render.materials.as_pbr).
    "pbr": ProgramSpec("mesh/phong.vert", "mesh/pbr.frag", "SHADE_PBR"),
}

# "auto" is no model of its own: pbr for PbrMaterial, phong for the rest
# (facet.render.materials.model_for).
assert set(SHADING_MODELS) | {"auto"} == set(SHADING)


def check_shading(name: str) -> str:
    if name not in SHADING_MODELS and name != "auto":
        raise InputError(f"unknown shading model {name!r}; choose one of "
                         f"{', '.join(SHADING_MODELS)}")
    return name
