#version 330 core
// Rim light: the built-in Phong shading plus a Fresnel (Schlick) glow where the surface
// turns away from the viewer. Try: facet view spot.obj --frag glsl/examples/rim.frag
#include "lib/lights.glsl"

in vec3 v_pos_world;
in vec3 v_normal_world;

uniform vec3 u_eye_world;
uniform vec3 u_rim_color = vec3(0.4, 0.7, 1.0);
uniform float u_rim_power = 3.0;

layout(location = 0) out vec4 f_color;

void main() {
    vec3 N = normalize(v_normal_world) * (gl_FrontFacing ? 1.0 : -1.0);
    vec3 V = normalize(u_eye_world - v_pos_world);
    vec3 base = shade_scene(v_pos_world, N, V, vec3(1.0), false);
    float fresnel = pow(1.0 - max(dot(N, V), 0.0), u_rim_power);  // Schlick with F0 = 0
    f_color = vec4(clamp(base + u_rim_color * fresnel, 0.0, 1.0), 1.0);
}
