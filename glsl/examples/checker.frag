#version 330 core
// A procedural checkerboard on the texture coordinates, lit by the built-in Phong shading.
// Try: facet view spot.obj --frag glsl/examples/checker.frag --uniform u_squares=16
#include "lib/lights.glsl"

in vec3 v_pos_world;
in vec3 v_normal_world;
in vec2 v_uv;

uniform vec3 u_eye_world;
uniform float u_squares = 8.0;

layout(location = 0) out vec4 f_color;

void main() {
    vec2 cell = floor(v_uv * u_squares);
    float check = mod(cell.x + cell.y, 2.0);
    vec3 albedo = mix(vec3(0.15), vec3(0.95), check);
    vec3 N = normalize(v_normal_world) * (gl_FrontFacing ? 1.0 : -1.0);
    vec3 V = normalize(u_eye_world - v_pos_world);
    f_color = vec4(shade_scene(v_pos_world, N, V, albedo, false), 1.0);
}
