#version 330 core
// glTF metallic-roughness shading per fragment, world space, linear light; the exact
// channels as glsl/mesh/phong.frag writes them. The material is the object's record read
// through the shared accessor (glsl/mesh/slots.glsl, lib/material.glsl), its surface
// layered as every engine layers it (lib/layers.glsl). Image-based light comes from
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
#include "lib/sampling.glsl"
#include "lib/color.glsl"
#include "mesh/slots.glsl"
#include "lib/layers.glsl"

uniform vec3 u_eye_world;  // eye, or with VIEW_ORTHOGRAPHIC the direction to the viewer
#ifdef INSTANCED
flat in int v_object_id;  // the instance's (glsl/mesh/phong.vert)
#define OBJECT_ID v_object_id
#else
uniform int u_object_id;
#define OBJECT_ID u_object_id
#endif

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
#endif

#include "mesh/outputs.glsl"

#ifdef TRANSMISSION
// The light a transmitting surface lets through towards V: the picture behind it read
// where the refracted ray leaves the volume (m.thickness along it, 0 thin-walled), and
// each light through a mirrored GGX lobe.
vec3 transmitted(PbrSurface s, Material m, vec3 c_trans, vec3 N, vec3 V) {
    if (c_trans == vec3(0.0)) return vec3(0.0);
    float ior = max(m.ior, 1.0);
    vec3 scale = vec3(length(u_model[0].xyz), length(u_model[1].xyz), length(u_model[2].xyz));
    vec3 ray = normalize(refract(-V, N, 1.0 / ior)) * m.thickness * scale;
    vec4 clip = u_view_projection * vec4(v_pos_world + ray, 1.0);
    vec2 uv = clamp(clip.xy / clip.w * 0.5 + 0.5, 0.0, 1.0);
    float lod = log2(u_behind_width) * ior_roughness(m.roughness, ior);
    vec3 behind = textureLod(u_behind, uv, lod).rgb;
#ifndef NO_DISPERSION
    // KHR_materials_dispersion, as the Khronos Sample Viewer approximates it: red and
    // blue read where rays at their own indices leave the volume.
    if (m.dispersion_spread > 0.0) {
        for (int c = 0; c < 3; c += 2) {
            float ior_c = ior + m.dispersion_spread * float(c - 1);
            vec3 ray_c = normalize(refract(-V, N, 1.0 / ior_c)) * m.thickness * scale;
            vec4 clip_c = u_view_projection * vec4(v_pos_world + ray_c, 1.0);
            vec2 uv_c = clamp(clip_c.xy / clip_c.w * 0.5 + 0.5, 0.0, 1.0);
            behind[c] = textureLod(u_behind, uv_c, lod)[c];
        }
    }
#endif
#if !defined(COLOR_SRGB) && !defined(LINEAR_OUT)
    behind = srgb_to_linear(max(behind, 0.0));  // the picture holds display values then
#endif
    vec3 rgb = kept_through_layers(s) * c_trans * behind;
    // Lights behind the surface, seen through it (lib/layers.glsl: every engine's).
    for (int i = 0; i < LIGHTS_IN_USE; ++i) {
        vec3 L;
        float falloff = incident_light(i, v_pos_world + ray, L);
        rgb += falloff * u_lights[i].color.rgb
             * pbr_light_through(s, c_trans, N, V, L, m.roughness, ior);
    }
    return exp(-m.absorption * length(ray)) * rgb;
}
#endif

// The split sum's table at (N.V, roughness) (LUT_SIZE: facet.render.raster.ibl's; its
// texel centres are at 0 and 1).
vec3 lut_at(float n_dot_v, float roughness) {
    return texture(u_ibl_lut, (vec2(n_dot_v, roughness) * (LUT_SIZE - 1.0) + 0.5)
                              / LUT_SIZE).rgb;
}

// The environment prefiltered for ``roughness`` along R (the ambient light without one).
vec3 prefiltered(vec3 R, float roughness) {
#ifdef HAS_ENVIRONMENT
    return textureLod(u_prefiltered, octahedral_uv(R), roughness
                      * (u_prefiltered_levels - 1.0)).rgb;
#else
    return u_ambient.rgb;
#endif
}

// Image-based light on surface s: the environment's irradiance and prefiltered radiance
// (else the ambient light as a uniform one) by the split sum, the sheen and the coat's own
// lobe over it, dimmed by the occlusion texture.
vec3 image_light(PbrSurface s, Material m, vec3 N, vec3 V) {
#ifdef HAS_ENVIRONMENT
    vec3 diffuse = texture(u_irradiance, octahedral_uv(N)).rgb;
#else
    vec3 diffuse = u_ambient.rgb;
#endif
    vec3 lut = lut_at(s.n_dot_v, m.roughness);
    vec3 ambient = pbr_ambient_sheen(s, pbr_ambient(s, diffuse, prefiltered(
        reflect(-V, pbr_bent_normal(s, N, V, m.roughness)), m.roughness), lut), diffuse);
#ifndef NO_DIFFUSE_TRANSMISSION
#ifdef HAS_ENVIRONMENT
    ambient += pbr_ambient_through(s, texture(u_irradiance, octahedral_uv(-N)).rgb, lut);
#else
    ambient += pbr_ambient_through(s, u_ambient.rgb, lut);
#endif
#endif
    if (m.clearcoat > 0.0)  // the coat's own lobe, at its roughness, on its normal
        ambient = pbr_ambient_coat(s, ambient, prefiltered(reflect(-V, m.cc_n),
                                   m.clearcoat_roughness),
                                   lut_at(s.cc_n_dot_v, m.clearcoat_roughness));
    return ambient * m.occlusion;
}

void main() {
#ifdef CLIP_PLANE
    if (dot(u_clip_plane, vec4(v_pos_world, 1.0)) < 0.0) discard;
#endif
#ifdef VIEW_ORTHOGRAPHIC
    vec3 V = u_eye_world;
#else
    vec3 V = normalize(u_eye_world - v_pos_world);
#endif
    // Seen from behind (double-sided materials), the whole frame turns round.
    float side = gl_FrontFacing ? 1.0 : -1.0;
    MaterialPoint p;
    p.uv = v_uv;
#ifdef HAS_UV1
    p.uv1 = v_uv1;
#else
    p.uv1 = v_uv;
#endif
#ifdef HAS_VERTEX_COLORS
    p.color = v_color;
#else
    p.color = vec4(1.0);
#endif
    p.n = normalize(v_normal_world) * side;
#if defined(HAS_TANGENTS) && (defined(TEX_NORMAL) || defined(TEX_CLEARCOAT_NORMAL) || \
                              !defined(NO_ANISOTROPY))
    p.tangent = v_tangent;
#else
    p.tangent = vec4(0.0);
#endif
    p.side = side;
    Material m = material_at(0, p);
#if defined(ALPHA_MASK)
    if (m.alpha < m.cutoff) discard;
#endif
    write_exact();
    write_normal(m.n);
    vec3 rgb = m.base;
    if (!m.unlit) {
        vec3 N = m.n;
#ifndef TRANSMISSION
        m.transmission = 0.0;  // drawn without the picture behind: its diffuse part stays
#endif
        vec3 c_trans;  // what passes instead of diffusing
        PbrSurface s = layered_surface(m, N, m.cc_n, V, c_trans);
        rgb = vec3(0.0);
        for (int i = 0; i < LIGHTS_IN_USE; ++i) {
            vec3 L;
            float falloff = incident_light(i, v_pos_world, L);
            falloff *= SHADOW(i, v_pos_world, N, L, falloff);
            rgb += falloff * u_lights[i].color.rgb * pbr_light(s, N, V, L);
        }
        rgb += image_light(s, m, N, V);
#ifdef TRANSMISSION
        rgb += transmitted(s, m, c_trans, N, V);
#endif
    }
    rgb += m.emission;
#if !defined(COLOR_SRGB) && !defined(LINEAR_OUT)
    rgb = linear_to_srgb_fast(clamp(rgb, 0.0, 1.0));
#endif
    write_color(rgb, m.alpha);
}
