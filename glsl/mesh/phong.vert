#version 330 core
// Object -> world -> view -> clip. Lighting inputs go out in world space; depth along the
// camera axis (-z in view space) goes out for the linear depth buffer.
// SHADE_GOURAUD evaluates the shading equation here, per vertex, for both faces.

in vec3 in_position;  // object space
in vec3 in_normal;    // object space
in vec2 in_uv;        // texture coordinates ((0, 0) for meshes without them)
#ifdef HAS_UV1
in vec2 in_uv1;       // the second texture coordinate set
out vec2 v_uv1;
#endif
#ifdef INSTANCED
// One draw for many placements of one mesh (facet.render.raster.instancing): the
// matrices come per instance, composed in float64 as the uniforms are.
in mat4 in_model;           // object -> world
in mat4 in_mvp;             // object -> clip
in mat3 in_normal_matrix;   // (M^-1)^T
in int in_object_id;        // object id + 1
flat out int v_object_id;
#define MODEL in_model
#define MVP in_mvp
#define NORMAL_MATRIX in_normal_matrix
#else
uniform mat4 u_model;         // object -> world
uniform mat4 u_mvp;           // object -> clip: projection * view * model, composed in float64
uniform mat3 u_normal_matrix; // (M^-1)^T of u_model's upper 3x3
#define MODEL u_model
#define MVP u_mvp
#define NORMAL_MATRIX u_normal_matrix
#endif
#ifdef HAS_TANGENTS
in vec4 in_tangent;   // object space, w: handedness (bitangent = w cross(N, T))
out vec4 v_tangent;   // world space
#ifndef INSTANCED
uniform float u_handedness;  // -1 where the model matrix mirrors, else 1
#endif
#endif
#ifdef HAS_VERTEX_COLORS
in vec4 in_color;     // per-vertex colour, sRGB-encoded (facet.scene.mesh)
out vec4 v_color;     // linear with COLOR_SRGB and for SHADE_PBR, else as given
#include "lib/color.glsl"
#endif

uniform mat4 u_view;          // world -> view (OpenGL camera axes)

out vec3 v_pos_world;
out vec3 v_normal_world;
out float v_depth_view;
out vec2 v_uv;

#ifdef SKINNED
#include "lib/skin.glsl"
#endif
#ifdef MORPHED
#include "lib/morph.glsl"
#endif

#ifdef SHADE_GOURAUD
#include "lib/lights.glsl"
uniform vec3 u_eye_world;  // eye position; the direction to the viewer with VIEW_ORTHOGRAPHIC
out vec3 v_color_front;
out vec3 v_color_back;
#endif

void main() {
    vec4 position = vec4(in_position, 1.0);  // object space
    vec3 normal = in_normal;
#ifdef MORPHED
    position.xyz += morphed(0);
    normal += morphed(1);
#endif
#ifdef SKINNED
    mat4 skin = skin_matrix();  // rest pose -> this pose, object space
    position = skin * position;
    normal = transpose(inverse(mat3(skin))) * normal;
#endif
    vec4 pos_world = MODEL * position;
    gl_Position = MVP * position;
    v_pos_world = pos_world.xyz;
    v_normal_world = NORMAL_MATRIX * normal;
#ifdef INSTANCED
    v_object_id = in_object_id;
#endif
    v_uv = in_uv;
#ifdef HAS_UV1
    v_uv1 = in_uv1;
#endif
#ifdef HAS_TANGENTS
    // Tangents lie in the surface: they transform with the model matrix itself.
#ifdef INSTANCED
    float handedness = determinant(mat3(in_model)) < 0.0 ? -1.0 : 1.0;
#else
    float handedness = u_handedness;
#endif
    vec3 tangent = in_tangent.xyz;
#ifdef MORPHED
    tangent += morphed(2);
#endif
#ifdef SKINNED
    tangent = mat3(skin) * tangent;
#endif
    v_tangent = vec4(mat3(MODEL) * tangent, in_tangent.w * handedness);
#endif
#ifdef HAS_VERTEX_COLORS
#if defined(COLOR_SRGB) || defined(SHADE_PBR)
    v_color = vec4(srgb_to_linear(in_color.rgb), in_color.a);
#else
    v_color = in_color;
#endif
#endif
    v_depth_view = -dot(vec4(u_view[0][2], u_view[1][2], u_view[2][2], u_view[3][2]), pos_world);
#ifdef SHADE_GOURAUD
    vec3 N = normalize(v_normal_world);
#ifdef VIEW_ORTHOGRAPHIC
    vec3 V = u_eye_world;
#else
    vec3 V = normalize(u_eye_world - pos_world.xyz);
#endif
#ifdef HAS_VERTEX_COLORS
    vec3 albedo = v_color.rgb;
#else
    vec3 albedo = vec3(1.0);
#endif
    // Per-vertex lighting; a texture, if any, modulates the result per fragment.
    v_color_front = shade_scene(pos_world.xyz, N, V, albedo, false);
    v_color_back = shade_scene(pos_world.xyz, -N, V, albedo, false);
#endif
}
