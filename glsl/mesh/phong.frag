#version 330 core
// Per-fragment shading in world space, plus the exact (never blended) linear depth and
// object id. The shading model is chosen by a define (facet.render.shading.SHADING_MODELS):
// SHADE_PHONG, SHADE_BLINN, SHADE_GOURAUD, SHADE_FLAT, SHADE_UNLIT, SHADE_NORMALS;
// VIEW_ORTHOGRAPHIC is defined for parallel projections.

in vec3 v_pos_world;
in vec3 v_normal_world;
in float v_depth_view;
in vec2 v_uv;
#ifdef HAS_VERTEX_COLORS
in vec4 v_color;
#endif
#ifdef HAS_TEXTURE
// The material's texture. Uploaded as sRGB (decoded to linear when sampled) in the sRGB
// colour mode, as plain RGBA8 (bytes / 255) otherwise; mipmapped, trilinear.
uniform sampler2D u_texture;
uniform mat3 u_uv_transform;  // on (u, v, 1): a glTF texture transform, else identity
#endif
#ifdef ALPHA_MASK
// glTF alphaMode MASK (a PbrMaterial drawn by these models, and the exact channels):
// fragments whose alpha (factor x texture x vertex colour) is below the cutoff are cut out.
uniform float u_base_alpha;
uniform float u_alpha_cutoff;
#endif
#ifdef SHADE_GOURAUD
in vec3 v_color_front;
in vec3 v_color_back;
#endif

#include "lib/lights.glsl"

// Eye position in world space; with VIEW_ORTHOGRAPHIC, the unit direction towards the viewer.
uniform vec3 u_eye_world;
uniform vec3 u_color;      // material C, linear [0, 1] (unlit)
#ifdef HAS_ENVIRONMENT
// Reflection and refraction of the environment (facet.scene.environment): the colour is
// mixed towards the environment by u_reflectivity; with u_ior > 0 the environment colour is
// the refraction and reflection weighted by Schlick's Fresnel term.
uniform samplerCube u_environment;
uniform float u_reflectivity;
uniform float u_ior;
// Glossy reflection by accumulation: each supersample tilts the reflected ray by
// u_gloss * u_gloss_jitter (a point of a jittered pattern in [-0.5, 0.5)^2), so the average
// of the samples is the environment blurred over a lobe as wide as u_gloss.
uniform float u_gloss;
uniform vec2 u_gloss_jitter;
#endif
#ifdef HAS_MIRROR
// A planar mirror (facet.render.mirror): the scene mirrored in its plane, drawn at this
// target's size, fetched at this fragment's own pixel and mixed in by u_mirror_weight.
uniform sampler2D u_mirror;
uniform float u_mirror_weight;
#endif
#ifdef CLIP_PLANE
// The reflection pass of a mirror: world-space plane n.x + d = 0, n towards the viewer;
// what lies behind the mirror is not in its reflection.
uniform vec4 u_clip_plane;
#endif
#ifdef OIT
// Weighted blended order-independent transparency (McGuire and Bavoil 2013), written with
// one additive blend for both targets: location 0 sums w a C and w a, location 1 sums
// -log(1 - a), so that exp(-sum) is the product of the (1 - a) behind which the opaque
// scene shows. The weight favours what is nearer: w = max(0.01, 3000 (1 - z)^3).
uniform float u_opacity;
#endif
uniform int u_object_id;

layout(location = 0) out vec4 f_color;
#ifdef OIT
layout(location = 1) out float f_reveal;
const float OIT_MAX_OPACITY = 0.999;  // log(1 - a) stays finite
#endif
// Auxiliary outputs exist only when asked for (OUT_<NAME> = its location, see
// facet.gl.targets): writing outputs nobody reads still costs a software rasteriser time.
#ifdef OUT_DEPTH_IDS
// (the bits of the linear depth along the camera axis, object id + 1): one attachment
layout(location = OUT_DEPTH_IDS) out uvec2 f_depth_ids;
#endif
#ifdef OUT_NORMALS
layout(location = OUT_NORMALS) out vec4 f_normal;  // world space, facing the viewer
#endif
#ifdef OUT_POSITION
layout(location = OUT_POSITION) out vec4 f_position;  // world space
#endif
#ifdef OUT_UV
layout(location = OUT_UV) out vec2 f_uv;
#endif

void main() {
#ifdef CLIP_PLANE
    if (dot(u_clip_plane, vec4(v_pos_world, 1.0)) < 0.0) discard;
#endif
#ifdef HAS_TEXTURE
    vec4 tex = texture(u_texture, (u_uv_transform * vec3(v_uv, 1.0)).xy);
#endif
#ifdef ALPHA_MASK
    float alpha = u_base_alpha;
#ifdef HAS_TEXTURE
    alpha *= tex.a;
#endif
#ifdef HAS_VERTEX_COLORS
    alpha *= v_color.a;
#endif
    if (alpha < u_alpha_cutoff) discard;
#endif
#ifdef OUT_DEPTH_IDS
    f_depth_ids = uvec2(floatBitsToUint(v_depth_view), uint(u_object_id));
#endif
#ifdef OUT_POSITION
    f_position = vec4(v_pos_world, 1.0);
#endif
#ifdef OUT_UV
    f_uv = v_uv;
#endif
#ifdef VIEW_ORTHOGRAPHIC
    vec3 V = u_eye_world;  // parallel projection: the same direction to the viewer everywhere
#else
    vec3 V = normalize(u_eye_world - v_pos_world);
#endif
#if defined(SHADE_FLAT)
    // The face's geometric normal from screen-space derivatives, turned towards the viewer
    // (its sign depends on the window's y direction, which facet flips for readback).
    vec3 N = normalize(cross(dFdx(v_pos_world), dFdy(v_pos_world)));
    N = dot(N, V) < 0.0 ? -N : N;
#else
    // Two-sided lighting: back faces (open meshes, holes) are lit from their visible side.
    vec3 N = normalize(v_normal_world) * (gl_FrontFacing ? 1.0 : -1.0);
#endif
#ifdef OUT_NORMALS
    f_normal = vec4(N, 0.0);
#endif
#ifdef EXACT_ONLY
    // The exact-channel pass (facet.render.renderer, step 3): no colour is kept, so none
    // is computed (and the varyings only colour needs are dropped by the linker).
    f_color = vec4(0.0);
    return;
#endif
    // What multiplies the material colour C at this point (1 for plain materials).
    vec3 albedo = vec3(1.0);
#ifdef HAS_TEXTURE
    albedo *= tex.rgb;
#endif
#if defined(HAS_VERTEX_COLORS) && !defined(SHADE_GOURAUD)
    albedo *= v_color.rgb;
#endif
#if defined(SHADE_GOURAUD)
    vec3 rgb = (gl_FrontFacing ? v_color_front : v_color_back) * albedo;
#elif defined(SHADE_UNLIT)
    vec3 rgb = u_color * albedo;
#elif defined(SHADE_NORMALS)
    vec3 rgb = normalize(v_normal_world) * 0.5 + 0.5;  // world-space normal as colour
#elif defined(SHADE_BLINN)
    vec3 rgb = shade_scene(v_pos_world, N, V, albedo, true);
#else  // SHADE_PHONG, SHADE_FLAT
    vec3 rgb = shade_scene(v_pos_world, N, V, albedo, false);
#endif
#ifdef HAS_ENVIRONMENT
    vec3 R = reflect(-V, N);
    vec3 t1 = normalize(cross(R, abs(R.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
    vec3 t2 = cross(R, t1);
    R = normalize(R + 2.0 * u_gloss * (t1 * u_gloss_jitter.x + t2 * u_gloss_jitter.y));
    vec3 reflected = texture(u_environment, R).rgb;
    vec3 env = reflected;
    if (u_ior > 0.0) {
        float f0 = pow((u_ior - 1.0) / (u_ior + 1.0), 2.0);
        float fresnel = f0 + (1.0 - f0) * pow(1.0 - max(dot(N, V), 0.0), 5.0);
        vec3 refracted = texture(u_environment, refract(-V, N, 1.0 / u_ior)).rgb;
        env = mix(refracted, reflected, fresnel);
    }
    rgb = mix(rgb, env, u_reflectivity);
#endif
#ifdef HAS_MIRROR
    rgb = mix(rgb, texelFetch(u_mirror, ivec2(gl_FragCoord.xy), 0).rgb, u_mirror_weight);
#endif
#ifdef OIT
    float a = clamp(u_opacity, 0.0, OIT_MAX_OPACITY);
    float w = max(0.01, 3000.0 * pow(1.0 - gl_FragCoord.z, 3.0));
    f_color = vec4(rgb * a, a) * w;
    f_reveal = -log(1.0 - a);
#else
    f_color = vec4(rgb, 1.0);
#endif
}
