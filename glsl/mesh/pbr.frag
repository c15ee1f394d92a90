#version 330 core
// glTF metallic-roughness shading (glsl/lib/pbr.glsl) per fragment, world space, linear
// light; the exact channels as glsl/mesh/phong.frag writes them. Texture slots (SLOT_*),
// each with its coordinate set, KHR_texture_transform matrix and mirrored axes (repeat and
// clamp are the sampler's), are enabled by TEX_<SLOT> defines. Image-based light comes from
// the environment's prefiltered maps (HAS_ENVIRONMENT), else from the ambient intensity
// as a uniform environment. Without COLOR_SRGB the result is sRGB-encoded here for 8-bit
// output (the other models' inputs and outputs are then display values; this one's inputs
// are always linear); float output (LINEAR_OUT) is linear light in either mode.

in vec3 v_pos_world;
in vec3 v_normal_world;
in float v_depth_view;
in vec2 v_uv;
#ifdef HAS_UV1
in vec2 v_uv1;
#endif
#ifdef HAS_TANGENTS
in vec4 v_tangent;  // world space, w: handedness
#endif
#ifdef HAS_VERTEX_COLORS
in vec4 v_color;  // linear
#endif

// The shading equation's Phong inputs are not used here.
#define AMBIENT_TERM vec3(0.0)
#define LIGHT_DIFFUSE(i) vec3(0.0)
#define LIGHT_SPECULAR(i) vec3(0.0)
#define SHININESS 1.0
#include "lib/lights.glsl"
#include "lib/pbr.glsl"
#include "lib/sampling.glsl"
#include "lib/color.glsl"

uniform vec3 u_eye_world;  // eye, or with VIEW_ORTHOGRAPHIC the direction to the viewer
uniform vec4 u_base_color;  // linear RGBA factor
uniform float u_metallic;
uniform float u_roughness;
uniform vec3 u_ior_f0;     // the dielectric's lobe: ((ior - 1) / (ior + 1))^2 x specular
uniform float u_specular;  // colour, and the specular factor (facet.scene.pbr.PbrMaterial)
uniform vec2 u_clearcoat;  // KHR_materials_clearcoat: factor, roughness; its normal map's
uniform float u_clearcoat_normal_scale;  // x and y scale
uniform vec4 u_sheen;            // KHR_materials_sheen: colour, roughness
uniform vec3 u_emissive;  // factor x strength
uniform float u_normal_scale;
uniform float u_occlusion_strength;
uniform float u_alpha_cutoff;  // ALPHA_MASK
uniform bool u_unlit;
#ifdef INSTANCED
flat in int v_object_id;  // the instance's (glsl/mesh/phong.vert)
#define OBJECT_ID v_object_id
#else
uniform int u_object_id;
#define OBJECT_ID u_object_id
#endif

#include "mesh/slots.glsl"

#ifdef CLIP_PLANE
uniform vec4 u_clip_plane;  // a mirror's reflection pass: world plane, n towards the viewer
#endif
uniform sampler2D u_ibl_lut;
#ifdef HAS_ENVIRONMENT
uniform sampler2D u_irradiance;   // octahedral, irradiance / pi
uniform sampler2D u_prefiltered;  // octahedral, mip k: roughness k / (levels - 1)
uniform float u_prefiltered_levels;
#endif

#ifdef TRANSMISSION
// KHR_materials_transmission and _volume as facet.render.raster.transmission describes.
uniform sampler2D u_behind;   // the scene without transmitting objects, mipmapped
uniform float u_behind_width;
uniform mat4 u_model;
uniform mat4 u_view_projection;
uniform vec3 u_transmission;  // factor, thickness (object space; 0: thin-walled), ior
uniform vec3 u_absorption;    // per unit length inside
#endif

#include "mesh/outputs.glsl"

#ifdef TRANSMISSION
// The light a transmitting surface lets through towards V: the picture behind it read
// where the refracted ray leaves the volume, and each light through a mirrored GGX lobe.
vec3 transmitted(PbrSurface s, vec3 c_trans, vec3 N, vec3 V, float roughness) {
    if (c_trans == vec3(0.0)) return vec3(0.0);
    float ior = u_transmission.z, thickness = u_transmission.y;
#ifdef TEX_THICKNESS
    thickness *= sample_slot(u_tex_thickness, SLOT_THICKNESS).g;
#endif
    vec3 scale = vec3(length(u_model[0].xyz), length(u_model[1].xyz), length(u_model[2].xyz));
    vec3 ray = normalize(refract(-V, N, 1.0 / ior)) * thickness * scale;
    vec4 clip = u_view_projection * vec4(v_pos_world + ray, 1.0);
    vec2 uv = clamp(clip.xy / clip.w * 0.5 + 0.5, 0.0, 1.0);
    float rough = roughness * clamp(2.0 * ior - 2.0, 0.0, 1.0);  // rougher with a bigger ior
    vec3 behind = textureLod(u_behind, uv, log2(u_behind_width) * rough).rgb;
#if !defined(COLOR_SRGB) && !defined(LINEAR_OUT)
    behind = srgb_to_linear(max(behind, 0.0));  // the picture holds display values then
#endif
    vec3 F_d = s.f0_d + (s.f90_d - s.f0_d) * schlick_weight(s.n_dot_v);
    vec3 through = behind;
    // Lights behind the surface, seen through it: GGX about the mirrored direction.
    float alpha = max(rough * rough, MIN_ALPHA);
    for (int i = 0; i < LIGHTS_IN_USE; ++i) {
        vec3 L;
        float falloff = incident_light(i, v_pos_world + ray, L);
        vec3 L_m = normalize(L - 2.0 * N * dot(N, L));  // on the viewer's side
        float n_dot_l = max(dot(N, L_m), 0.0);
        vec3 H = normalize(L_m + V);
        through += falloff * u_lights[i].color.rgb * PI * n_dot_l
                 * ggx_d(max(dot(N, H), 0.0), alpha) * smith_vis(n_dot_l, s.n_dot_v, alpha)
                 * step(dot(N, L), 0.0);
    }
    vec3 kept = (1.0 - F_d) * (1.0 - s.cc * s.cc_fresnel) * (1.0 - s.sheen_dim);
    return kept * c_trans * exp(-u_absorption * length(ray)) * through;
}
#endif

void main() {
#ifdef CLIP_PLANE
    if (dot(u_clip_plane, vec4(v_pos_world, 1.0)) < 0.0) discard;
#endif
#ifdef VIEW_ORTHOGRAPHIC
    vec3 V = u_eye_world;
#else
    vec3 V = normalize(u_eye_world - v_pos_world);
#endif
    vec4 base = u_base_color;
#ifdef TEX_BASE
    base *= sample_slot(u_tex_base, SLOT_BASE);  // an sRGB texture: decoded when sampled
#endif
#ifdef HAS_VERTEX_COLORS
    base *= v_color;
#endif
#if defined(ALPHA_MASK)
    if (base.a < u_alpha_cutoff) discard;
#endif
    write_exact();
    // Seen from behind (double-sided materials), the whole frame turns round.
    float side = gl_FrontFacing ? 1.0 : -1.0;
    vec3 Ng = normalize(v_normal_world) * side;
    vec3 N = Ng, N_coat = Ng;
#if defined(HAS_TANGENTS) && (defined(TEX_NORMAL) || defined(TEX_CLEARCOAT_NORMAL))
    vec3 T = normalize(v_tangent.xyz - Ng * dot(Ng, v_tangent.xyz)) * side;
    mat3 TBN = mat3(T, cross(Ng, T) * v_tangent.w, Ng);
#ifdef TEX_NORMAL
    vec3 t = sample_slot(u_tex_normal, SLOT_NORMAL).xyz * 2.0 - 1.0;
    N = normalize(TBN * vec3(t.xy * u_normal_scale, t.z));
#endif
#ifdef TEX_CLEARCOAT_NORMAL
    vec3 tc = sample_slot(u_tex_clearcoat_normal, SLOT_CLEARCOAT_NORMAL).xyz * 2.0 - 1.0;
    N_coat = normalize(TBN * vec3(tc.xy * u_clearcoat_normal_scale, tc.z));
#endif
#endif
    write_normal(N);
    float metallic = u_metallic, roughness = u_roughness;
#ifdef TEX_MR
    vec4 mr = sample_slot(u_tex_mr, SLOT_MR);
    roughness *= mr.g;
    metallic *= mr.b;
#endif
    // The extensions' factors times their textures (facet.scene.pbr.PbrMaterial).
    float specular = u_specular, clearcoat = u_clearcoat.x, clearcoat_roughness = u_clearcoat.y;
    vec3 ior_f0 = u_ior_f0;
    vec4 sheen = u_sheen;
#ifdef TEX_SPECULAR
    specular *= sample_slot(u_tex_specular, SLOT_SPECULAR).a;
#endif
#ifdef TEX_SPECULAR_COLOR
    ior_f0 *= sample_slot(u_tex_specular_color, SLOT_SPECULAR_COLOR).rgb;
#endif
#ifdef TEX_CLEARCOAT
    clearcoat *= sample_slot(u_tex_clearcoat, SLOT_CLEARCOAT).r;
#endif
#ifdef TEX_CLEARCOAT_ROUGHNESS
    clearcoat_roughness *= sample_slot(u_tex_clearcoat_roughness, SLOT_CLEARCOAT_ROUGHNESS).g;
#endif
#ifdef TEX_SHEEN_COLOR
    sheen.rgb *= sample_slot(u_tex_sheen_color, SLOT_SHEEN_COLOR).rgb;
#endif
#ifdef TEX_SHEEN_ROUGHNESS
    sheen.a *= sample_slot(u_tex_sheen_roughness, SLOT_SHEEN_ROUGHNESS).a;
#endif
    vec3 rgb;
    if (u_unlit) {
        rgb = base.rgb;
    } else {
        float n_dot_v = clamp(dot(N, V), 0.0, 1.0);
        PbrSurface s = pbr_surface_full(base.rgb, metallic, roughness, n_dot_v,
                                        min(ior_f0, 1.0) * specular, specular);
        pbr_sheen(s, sheen.rgb, sheen.a);
        pbr_coat(s, clearcoat, clearcoat_roughness, N_coat, V);
#ifdef TRANSMISSION
        float transmission = u_transmission.x;
#ifdef TEX_TRANSMISSION
        transmission *= sample_slot(u_tex_transmission, SLOT_TRANSMISSION).r;
#endif
        vec3 c_trans = s.c_diff * transmission;  // what passes instead of diffusing
        s.c_diff *= 1.0 - transmission;
#endif
        rgb = vec3(0.0);
        for (int i = 0; i < LIGHTS_IN_USE; ++i) {
            vec3 L;
            float falloff = incident_light(i, v_pos_world, L);
            falloff *= SHADOW(i, v_pos_world, N, L, falloff);
            rgb += falloff * u_lights[i].color.rgb * pbr_light(s, N, V, L);
        }
        // The table's texel centres are at 0 and 1 (LUT_SIZE: facet.render.raster.ibl's).
        vec2 at = (vec2(n_dot_v, roughness) * (LUT_SIZE - 1.0) + 0.5) / LUT_SIZE;
        vec3 lut = texture(u_ibl_lut, at).rgb;
#ifdef HAS_ENVIRONMENT
        vec3 diffuse = texture(u_irradiance, octahedral_uv(N)).rgb;
        vec3 specular = textureLod(u_prefiltered, octahedral_uv(reflect(-V, N)),
                                   roughness * (u_prefiltered_levels - 1.0)).rgb;
#else
        vec3 diffuse = u_ambient.rgb, specular = u_ambient.rgb;
#endif
        vec3 ambient = pbr_ambient_sheen(s, pbr_ambient(s, diffuse, specular, lut), diffuse);
        if (clearcoat > 0.0) {  // the coat's own lobe, at its roughness, on its normal
            vec2 at_cc = (vec2(s.cc_n_dot_v, clearcoat_roughness) * (LUT_SIZE - 1.0) + 0.5)
                       / LUT_SIZE;
#ifdef HAS_ENVIRONMENT
            vec3 specular_cc = textureLod(u_prefiltered, octahedral_uv(reflect(-V, N_coat)),
                                          clearcoat_roughness
                                          * (u_prefiltered_levels - 1.0)).rgb;
#else
            vec3 specular_cc = u_ambient.rgb;
#endif
            ambient = pbr_ambient_coat(s, ambient, specular_cc, texture(u_ibl_lut, at_cc).rgb);
        }
#if defined(ORM_PACKED)
        ambient *= 1.0 + u_occlusion_strength * (mr.r - 1.0);  // the same image's red
#elif defined(TEX_OCCLUSION)
        ambient *= 1.0 + u_occlusion_strength * (sample_slot(u_tex_occlusion,
                                                             SLOT_OCCLUSION).r - 1.0);
#endif
        rgb += ambient;
#ifdef TRANSMISSION
        rgb += transmitted(s, c_trans, N, V, roughness);
#endif
    }
    vec3 emissive = u_emissive;
#ifdef TEX_EMISSIVE
    emissive *= sample_slot(u_tex_emissive, SLOT_EMISSIVE).rgb;
#endif
    rgb += emissive;
#if !defined(COLOR_SRGB) && !defined(LINEAR_OUT)
    rgb = linear_to_srgb_fast(clamp(rgb, 0.0, 1.0));
#endif
    write_color(rgb, base.a);
}
