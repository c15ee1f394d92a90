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
#ifdef SPRITE_LINES
in vec2 v_corner;  // across a line's quad (glsl/mesh/sprite.vert)
#endif
#ifdef EDL
uniform sampler2D u_edl_shade;  // eye-dome lighting per pixel (glsl/post/edl_shade.frag)
#endif
#ifdef HAS_TEXTURE
// The material's texture. Uploaded as sRGB (decoded to linear when sampled) in the sRGB
// colour mode, as plain RGBA8 (bytes / 255) otherwise; mipmapped, trilinear.
// Its uv through the base-colour slot's glTF texture transform (the identity for a Phong
// material's image: mesh/record.glsl).
uniform sampler2D u_texture;
#endif
// glTF alphaMode MASK (a PbrMaterial drawn by these models, and the exact channels, with
// ALPHA_MASK): fragments whose alpha (factor x texture x vertex colour) is below the
// cutoff are cut out.
#ifdef SHADE_GOURAUD
in vec3 v_color_front;
in vec3 v_color_back;
#endif

// The material: the drawn object's record (mesh/record.glsl), through which the lights'
// products are read too.
#include "lib/lights.glsl"

// Eye position in world space; with VIEW_ORTHOGRAPHIC, the unit direction towards the viewer.
uniform vec3 u_eye_world;
#ifdef HAS_ENVIRONMENT
// Reflection and refraction of the environment (facet.scene.environment): the colour is
// mixed towards the environment by the reflectivity; with an ior > 0 the environment
// colour is the refraction and reflection weighted by Schlick's Fresnel term; glossy by
// accumulation (lib/gloss.glsl; u_gloss_jitter is the frame's sample).
#include "lib/gloss.glsl"
uniform samplerCube u_environment;
uniform vec2 u_gloss_jitter;
#endif
#ifdef HAS_MIRROR
// A planar mirror (facet.render.raster.mirror): the scene mirrored in its plane, drawn at this
// target's size, fetched at this fragment's own pixel and mixed in by the reflectivity.
uniform sampler2D u_mirror;
#endif
#ifdef CLIP_PLANE
// The reflection pass of a mirror: world-space plane n.x + d = 0, n towards the viewer;
// what lies behind the mirror is not in its reflection.
uniform vec4 u_clip_plane;
#endif
#ifdef INSTANCED
flat in int v_object_id;  // the instance's (glsl/mesh/phong.vert)
#define OBJECT_ID v_object_id
#else
uniform int u_object_id;
#define OBJECT_ID u_object_id
#endif
#include "mesh/outputs.glsl"

void main() {
#ifdef SPRITE_POINTS
    vec2 corner = gl_PointCoord * 2.0 - 1.0;
    if (dot(corner, corner) > 1.0) discard;  // round discs
#endif
#ifdef EDL_DEPTH
    f_color = vec4(v_depth_view, 0.0, 0.0, 1.0);  // the cloud's depth for EDL
    return;
#endif
#ifdef CLIP_PLANE
    if (dot(u_clip_plane, vec4(v_pos_world, 1.0)) < 0.0) discard;
#endif
#ifdef HAS_TEXTURE
    vec4 tex = texture(u_texture, base_color_uv(v_uv));
#endif
#ifdef ALPHA_MASK
    float alpha = base_alpha();
#ifdef HAS_TEXTURE
    alpha *= tex.a;
#endif
#ifdef HAS_VERTEX_COLORS
    alpha *= v_color.a;
#endif
    if (alpha < alpha_cutoff()) discard;
#endif
    write_exact();
#ifdef VIEW_ORTHOGRAPHIC
    vec3 V = u_eye_world;  // parallel projection: the same direction to the viewer everywhere
#else
    vec3 V = normalize(u_eye_world - v_pos_world);
#endif
#if defined(SPRITE_POINTS) || defined(SPRITE_LINES)
    // A point's normal turned towards the viewer; unlit points and lines face the viewer.
    vec3 N = dot(v_normal_world, v_normal_world) > 0.0 ? normalize(v_normal_world) : V;
    N = dot(N, V) < 0.0 ? -N : N;
#elif defined(SHADE_FLAT)
    // The face's geometric normal from screen-space derivatives, turned towards the viewer
    // (its sign depends on the window's y direction, which facet flips for readback).
    vec3 N = normalize(cross(dFdx(v_pos_world), dFdy(v_pos_world)));
    N = dot(N, V) < 0.0 ? -N : N;
#else
    // Two-sided lighting: back faces (open meshes, holes) are lit from their visible side.
    vec3 N = normalize(v_normal_world) * (gl_FrontFacing ? 1.0 : -1.0);
#endif
    write_normal(N);
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
    vec3 rgb = phong_c() * albedo;
#elif defined(SHADE_NORMALS)
    vec3 rgb = normalize(v_normal_world) * 0.5 + 0.5;  // world-space normal as colour
#elif defined(SHADE_BLINN)
    vec3 rgb = light_scene(v_pos_world, N, V, albedo, true);
#else  // SHADE_PHONG, SHADE_FLAT
    vec3 rgb = light_scene(v_pos_world, N, V, albedo, false);
#endif
#ifdef EDL
    rgb *= texelFetch(u_edl_shade, ivec2(gl_FragCoord.xy), 0).r;
#endif
#ifdef HAS_ENVIRONMENT
    vec3 R = gloss_tilt(reflect(-V, N), phong_gloss(), u_gloss_jitter);
    vec3 reflected = texture(u_environment, R).rgb;
    vec3 env = reflected;
    float ior = phong_ior(), reflectivity = phong_reflectivity();
    if (ior > 0.0) {
        float f0 = pow((ior - 1.0) / (ior + 1.0), 2.0);
        float fresnel = f0 + (1.0 - f0) * pow(1.0 - max(dot(N, V), 0.0), 5.0);
        vec3 refracted = texture(u_environment, refract(-V, N, 1.0 / ior)).rgb;
        env = mix(refracted, reflected, fresnel);
    }
    // The local colour's share is clamped as a pixel is, not the local colour before
    // it is shared: a highlight brighter than 1 still shows through (1 - reflectivity).
    rgb = clamp((1.0 - reflectivity) * rgb, 0.0, 1.0) + reflectivity * env;
#elif defined(HAS_MIRROR)
    float reflectivity = phong_reflectivity();
    rgb = clamp((1.0 - reflectivity) * rgb, 0.0, 1.0)
        + reflectivity * texelFetch(u_mirror, ivec2(gl_FragCoord.xy), 0).rgb;
#else
    rgb = clamp(rgb, 0.0, 1.0);
#endif
#ifdef OIT
    write_color(rgb, phong_opacity());
#else
    write_color(rgb, 1.0);
#endif
}
