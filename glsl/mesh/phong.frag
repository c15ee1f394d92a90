#version 330 core
// Per-fragment shading in world space, plus the exact (never blended) linear depth and
// object id. The shading model is chosen by a define (facet.render.shading.SHADING_MODELS):
// SHADE_PHONG, SHADE_BLINN, SHADE_GOURAUD, SHADE_FLAT, SHADE_UNLIT, SHADE_NORMALS;
// VIEW_ORTHOGRAPHIC is defined for parallel projections.

in vec3 v_pos_world;
in vec3 v_normal_world;
in float v_depth_view;
#ifdef SHADE_GOURAUD
in vec3 v_color_front;
in vec3 v_color_back;
#endif

#include "lib/lights.glsl"

// Eye position in world space; with VIEW_ORTHOGRAPHIC, the unit direction towards the viewer.
uniform vec3 u_eye_world;
uniform vec3 u_color;      // material C, linear [0, 1] (unlit)
uniform int u_object_id;

layout(location = 0) out vec4 f_color;
// COLOR_ONLY drops the depth and id outputs: writing outputs that have no attachment still
// costs a software rasteriser time, so colour-only passes use a program without them.
#ifndef COLOR_ONLY
layout(location = 1) out float f_depth;  // linear depth along the camera axis, scene units
layout(location = 2) out int f_object_id;
#endif

void main() {
#ifndef COLOR_ONLY
    f_depth = v_depth_view;
    f_object_id = u_object_id;
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
#if defined(SHADE_GOURAUD)
    vec3 rgb = gl_FrontFacing ? v_color_front : v_color_back;
#elif defined(SHADE_UNLIT)
    vec3 rgb = u_color;
#elif defined(SHADE_NORMALS)
    vec3 rgb = normalize(v_normal_world) * 0.5 + 0.5;  // world-space normal as colour
#elif defined(SHADE_BLINN)
    vec3 rgb = shade_scene(v_pos_world, N, V, true);
#else  // SHADE_PHONG, SHADE_FLAT
    vec3 rgb = shade_scene(v_pos_world, N, V, false);
#endif
    f_color = vec4(rgb, 1.0);
}
