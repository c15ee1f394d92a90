"""The scene-to-GPU contract's bindings, named once: every texture unit, image unit and
uniform block that facet's GLSL declares.

A sampler uniform has one unit for every program that declares it, and no two names share a
unit, so no program can read one texture through another's unit (a skinned mesh's joints
once took the metallic-roughness texture's). ``compile_program`` (facet.gl.shaders) calls
``bind`` on every program it links: each active sampler is set to its unit here and each
uniform block to its binding; a sampler of facet's own GLSL that is missing here is an error
at link time. Draw code binds a texture with ``texture.use(location=unit(name))`` and sets
no unit of its own. Users' programs (mesh shaders, the shader lab) may declare samplers of
their own: those are left for their host to bind. The ray scene's arrays may instead be
read as images (``IMAGES``): their units are compiled in (``image_defines``), an image of
facet's own GLSL missing there is an error at link time, and draw code binds one with
``texture.bind_to_image(IMAGES[name], ...)``.

The 42 units fit GL 3.3's minimum of 48 combined units (llvmpipe has 192); what one stage
of one program declares at once (the metallic-roughness fragment stage: its 14 slots and 5
more) stays within the 32 per stage of llvmpipe and desktop GPUs.
"""

from __future__ import annotations

from ..errors import ShaderError
from ..scene.pbr import SLOTS

# The raster's scene passes (glsl/mesh, glsl/shadow, glsl/lib).
_SCENE = ("u_texture", "u_shadow_atlas", "u_environment", "u_mirror", "u_edl_shade",
          "u_joints", "u_targets", "u_behind", "u_ibl_lut", "u_irradiance", "u_prefiltered")
# A glTF material's texture slots (glsl/mesh/slots.glsl): u_tex_<short name>.
_SHORT = {"base_color": "base", "metallic_roughness": "mr"}
SLOT_SAMPLERS = {slot: f"u_tex_{_SHORT.get(slot, slot)}" for slot in SLOTS}
# Full-screen passes (glsl/post, glsl/ibl): their inputs.
_POST = ("u_source", "u_sample", "u_accum", "u_reveal", "u_edl_depth", "u_splat_aux")
# The ray scene (glsl/trace): geometry, instances, texture layers, emitters, the sky.
_RAYS = ("u_tris", "u_tri_index", "u_vertices", "u_nodes", "u_instances", "u_tlas",
         "u_textures", "u_emitters", "u_sky_cdf", "u_sky_pdf", "u_sky_radiance",
         "u_active")

SAMPLERS: dict[str, int] = {name: unit for unit, name in enumerate(
    (*_SCENE, *SLOT_SAMPLERS.values(), *_POST, *_RAYS))}
BLOCKS: dict[str, int] = {"Lights": 0, "Instances": 1, "Tlas": 2}  # glsl/lib/lights.glsl
# Image units: the ray scene's arrays where the context reads them as images
# (glsl/trace/data.glsl SCENE_IMAGES, bound with layout(binding = IMAGE_*): image_defines).
# At most MAX_IMAGES: GL 4.2's least number of image uniforms a fragment shader may hold
# (and of image units), so every context that lists image load and store links them.
MAX_IMAGES = 8
IMAGES: dict[str, int] = {name: unit for unit, name in enumerate(
    ("u_tris", "u_tri_index", "u_vertices", "u_nodes", "u_instances", "u_tlas"))}

# GL type enums of sampler uniforms (2D, cube, 2D array, 2D shadow, their int forms).
SAMPLER_TYPES = frozenset({0x8B5E, 0x8B60, 0x8DC1, 0x8B62, 0x8DCA, 0x8DCC, 0x8DCF, 0x8DD2,
                           0x8DD4, 0x8DD7})


# GL type enums of image uniforms (2D: float, int, unsigned).
IMAGE_TYPES = frozenset({0x904D, 0x9058, 0x9063})


def unit(name: str) -> int:
    """The texture unit of sampler uniform ``name``.

    Parameters
    ----------
    name : str
        A sampler uniform of facet's GLSL (``u_environment``, ``u_tex_mr``, ...).

    Returns
    -------
    int
        Its unit, the same in every program.
    """
    return SAMPLERS[name]


def image_defines() -> dict[str, int]:
    """The IMAGE_* defines of the image units in ``IMAGES`` (u_tris: IMAGE_TRIS)."""
    return {f"IMAGE_{name[2:].upper()}": unit for name, unit in IMAGES.items()}


def samplers(program) -> dict[str, int]:
    """The active sampler uniforms of a linked moderngl program and the units they hold."""
    import moderngl

    out = {}
    for name in program:
        member = program[name]
        if isinstance(member, moderngl.Uniform) and member.gl_type in SAMPLER_TYPES:
            out[name] = member.value
    return out


def images(program) -> set[str]:
    """The active image uniforms of a linked moderngl program (their units are compiled in:
    ``image_defines``)."""
    import moderngl

    return {name for name in program if isinstance(program[name], moderngl.Uniform)
            and program[name].gl_type in IMAGE_TYPES}


def bind(program, own: bool, label: str = "program") -> None:
    """Set every active sampler of ``program`` (a moderngl program) to its unit and every
    uniform block to its binding. ``own``: the program is built from facet's GLSL only, so
    a sampler missing from ``SAMPLERS`` is an error (a new texture must be named here)."""
    import moderngl

    for name in program:
        member = program[name]
        if isinstance(member, moderngl.UniformBlock) and name in BLOCKS:
            member.binding = BLOCKS[name]
        elif isinstance(member, moderngl.Uniform) and member.gl_type in SAMPLER_TYPES:
            if name in SAMPLERS:
                member.value = SAMPLERS[name]
            elif own:
                raise ShaderError(f"{label}: sampler '{name}' has no unit in "
                                  "facet.gl.bindings.SAMPLERS (name it there)")
        elif isinstance(member, moderngl.Uniform) and member.gl_type in IMAGE_TYPES and \
                own and name not in IMAGES:
            raise ShaderError(f"{label}: image '{name}' has no unit in "
                              "facet.gl.bindings.IMAGES (name it there)")
