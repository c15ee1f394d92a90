#version 330 core
// Toon shading for meshes: the diffuse term of each light quantised into u_steps bands,
// plus a hard specular spot. Try: facet view bunny.obj --frag glsl/examples/toon.frag
#include "lib/lights.glsl"

in vec3 v_pos_world;
in vec3 v_normal_world;

uniform vec3 u_eye_world;
uniform vec3 u_color;
uniform float u_steps = 4.0;  // bands of light

layout(location = 0) out vec4 f_color;

void main() {
    vec3 N = normalize(v_normal_world) * (gl_FrontFacing ? 1.0 : -1.0);
    vec3 V = normalize(u_eye_world - v_pos_world);
    float light = 0.0;
    float spot = 0.0;
    for (int i = 0; i < LIGHTS_IN_USE; ++i) {
        vec3 L;
        float falloff = incident_light(i, v_pos_world, L);
        light += falloff * max(dot(N, L), 0.0);
        spot = max(spot, step(0.96, dot(reflect(-L, N), V)));
    }
    float banded = floor(clamp(0.8 * light, 0.0, 0.999) * u_steps) / (u_steps - 1.0);
    f_color = vec4(u_color * (0.25 + 0.75 * banded) + 0.4 * spot, 1.0);
}
