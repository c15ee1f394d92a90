// A glTF material's texture slots (facet.render.materials, facet.scene.pbr.SLOTS order):
// each with its coordinate set (v_uv or v_uv1, which the including stage declares), its
// KHR_texture_transform matrix and mirrored axes (repeat and clamp are the sampler's).
const int SLOT_BASE = 0, SLOT_MR = 1, SLOT_NORMAL = 2, SLOT_OCCLUSION = 3, SLOT_EMISSIVE = 4,
          SLOT_SPECULAR = 5, SLOT_SPECULAR_COLOR = 6, SLOT_TRANSMISSION = 7,
          SLOT_THICKNESS = 8, SLOT_CLEARCOAT = 9, SLOT_CLEARCOAT_ROUGHNESS = 10,
          SLOT_CLEARCOAT_NORMAL = 11, SLOT_SHEEN_COLOR = 12, SLOT_SHEEN_ROUGHNESS = 13;
const int SLOT_COUNT = 14;
uniform mat3 u_slot_transform[SLOT_COUNT];
uniform float u_slot_set[SLOT_COUNT];   // 0: v_uv, 1: v_uv1
uniform vec2 u_slot_mirror[SLOT_COUNT];  // 1 on mirrored axes
uniform sampler2D u_tex_base, u_tex_mr, u_tex_normal, u_tex_occlusion, u_tex_emissive,
                  u_tex_specular, u_tex_specular_color, u_tex_transmission, u_tex_thickness,
                  u_tex_clearcoat, u_tex_clearcoat_roughness, u_tex_clearcoat_normal,
                  u_tex_sheen_color, u_tex_sheen_roughness;

vec4 sample_slot(sampler2D tex, int k) {
#ifdef HAS_UV1
    vec2 uv = u_slot_set[k] > 0.5 ? v_uv1 : v_uv;
#else
    vec2 uv = v_uv;
#endif
    uv = (u_slot_transform[k] * vec3(uv, 1.0)).xy;
    uv = mix(uv, 1.0 - abs(mod(uv, 2.0) - 1.0), u_slot_mirror[k]);
    return texture(tex, uv);
}
