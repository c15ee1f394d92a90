// The rasterizer's side of the material record (facet.render.material_record): the record
// of the object being drawn (mesh/record.glsl), and a sampler per texture slot (the slot's
// repeat and clamp are its sampler's, facet.render.materials.SlotSamplers), each enabled by
// its TEX_<SLOT> define; then the shared accessor, lib/material.glsl.
#include "mesh/record.glsl"
uniform sampler2D u_tex_base, u_tex_mr, u_tex_normal, u_tex_occlusion, u_tex_emissive,
                  u_tex_specular, u_tex_specular_color, u_tex_transmission, u_tex_thickness,
                  u_tex_clearcoat, u_tex_clearcoat_roughness, u_tex_clearcoat_normal,
                  u_tex_sheen_color, u_tex_sheen_roughness, u_tex_iridescence,
                  u_tex_iridescence_thickness, u_tex_anisotropy,
                  u_tex_diffuse_transmission, u_tex_diffuse_transmission_color;

vec4 slot_image(int rec, int k, vec2 uv) {
#define SLOT_IMAGE(NAME, SAMPLER) if (k == NAME) return texture(SAMPLER, uv);
#ifdef TEX_BASE
    SLOT_IMAGE(SLOT_BASE_COLOR, u_tex_base)
#endif
#ifdef TEX_MR
    SLOT_IMAGE(SLOT_METALLIC_ROUGHNESS, u_tex_mr)
#endif
#ifdef TEX_NORMAL
    SLOT_IMAGE(SLOT_NORMAL, u_tex_normal)
#endif
#ifdef TEX_OCCLUSION
    SLOT_IMAGE(SLOT_OCCLUSION, u_tex_occlusion)
#endif
#ifdef TEX_EMISSIVE
    SLOT_IMAGE(SLOT_EMISSIVE, u_tex_emissive)
#endif
#ifdef TEX_SPECULAR
    SLOT_IMAGE(SLOT_SPECULAR, u_tex_specular)
#endif
#ifdef TEX_SPECULAR_COLOR
    SLOT_IMAGE(SLOT_SPECULAR_COLOR, u_tex_specular_color)
#endif
#ifdef TEX_TRANSMISSION
    SLOT_IMAGE(SLOT_TRANSMISSION, u_tex_transmission)
#endif
#ifdef TEX_THICKNESS
    SLOT_IMAGE(SLOT_THICKNESS, u_tex_thickness)
#endif
#ifdef TEX_CLEARCOAT
    SLOT_IMAGE(SLOT_CLEARCOAT, u_tex_clearcoat)
#endif
#ifdef TEX_CLEARCOAT_ROUGHNESS
    SLOT_IMAGE(SLOT_CLEARCOAT_ROUGHNESS, u_tex_clearcoat_roughness)
#endif
#ifdef TEX_CLEARCOAT_NORMAL
    SLOT_IMAGE(SLOT_CLEARCOAT_NORMAL, u_tex_clearcoat_normal)
#endif
#ifdef TEX_SHEEN_COLOR
    SLOT_IMAGE(SLOT_SHEEN_COLOR, u_tex_sheen_color)
#endif
#ifdef TEX_SHEEN_ROUGHNESS
    SLOT_IMAGE(SLOT_SHEEN_ROUGHNESS, u_tex_sheen_roughness)
#endif
#ifdef TEX_IRIDESCENCE
    SLOT_IMAGE(SLOT_IRIDESCENCE, u_tex_iridescence)
#endif
#ifdef TEX_IRIDESCENCE_THICKNESS
    SLOT_IMAGE(SLOT_IRIDESCENCE_THICKNESS, u_tex_iridescence_thickness)
#endif
#ifdef TEX_ANISOTROPY
    SLOT_IMAGE(SLOT_ANISOTROPY, u_tex_anisotropy)
#endif
#ifdef TEX_DIFFUSE_TRANSMISSION
    SLOT_IMAGE(SLOT_DIFFUSE_TRANSMISSION, u_tex_diffuse_transmission)
#endif
#ifdef TEX_DIFFUSE_TRANSMISSION_COLOR
    SLOT_IMAGE(SLOT_DIFFUSE_TRANSMISSION_COLOR, u_tex_diffuse_transmission_color)
#endif
#undef SLOT_IMAGE
    return vec4(1.0);
}

#include "lib/material.glsl"
