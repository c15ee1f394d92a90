// The scene's lights as a uniform block, and the whole shading equation over them.
// World space throughout. Filled by facet.render.forward (std140, 4 vec4 per light).
#include "lib/lighting.glsl"

#ifndef MAX_LIGHTS
#define MAX_LIGHTS 16
#endif

struct LightData {
    vec4 position;   // xyz: world position (point, spot); w: kind (LIGHT_*)
    vec4 direction;  // xyz: unit direction the light travels (directional, spot); w: cos inner
    vec4 color;      // rgb: colour x intensity; w: cos outer
    vec4 falloff;    // xyz: attenuation (c, l, q)
};

layout(std140) uniform Lights {
    vec4 u_ambient;      // rgb: ambient intensity I_a
    ivec4 u_light_count; // x: number of lights in use
    LightData u_lights[MAX_LIGHTS];
};

// facet compiles one program per light set (LIGHT_COUNT and LIGHT_KIND_LIST defined): the
// loop has a constant trip count and known kinds, so the compiler unrolls it and drops the
// branches; without them the loop runs over u_light_count with kinds read at run time.
#if defined(LIGHT_COUNT) && LIGHT_COUNT > 0
const int LIGHT_KINDS[LIGHT_COUNT] = LIGHT_KIND_LIST;
#define LIGHT_KIND(i) LIGHT_KINDS[i]
#else
#define LIGHT_KIND(i) int(u_lights[i].position.w)
#endif
#ifdef LIGHT_COUNT
#define LIGHTS_IN_USE LIGHT_COUNT
#else
#define LIGHTS_IN_USE u_light_count.x
#endif

// Unit vector from p towards light i, and the light's intensity arriving at p.
vec3 incident_light(int i, vec3 p, out vec3 L) {
    LightData light = u_lights[i];
    int kind = LIGHT_KIND(i);
    if (kind == LIGHT_DIRECTIONAL) {
        L = -light.direction.xyz;
        return light.color.rgb;
    }
    vec3 to_light = light.position.xyz - p;
    float d = length(to_light);
    L = to_light / max(d, 1e-9);
    vec3 I = light.color.rgb * light_attenuation(light.falloff.xyz, d);
    if (kind == LIGHT_SPOT) I *= spot_cone(-L, light.direction.xyz, light.direction.w,
                                           light.color.w);
    return I;
}

// I = I_a k_a C + sum_i (diffuse + specular), clamped to [0, 1].
// k = (k_a, k_d, k_s, n). blinn selects the halfway-vector specular.
vec3 shade_scene(vec3 p, vec3 N, vec3 V, vec3 C, vec4 k, bool blinn) {
    vec3 I = u_ambient.rgb * k.x * C;
    for (int i = 0; i < LIGHTS_IN_USE; ++i) {
        vec3 L;
        vec3 Ii = incident_light(i, p, L);
        I += blinn ? blinn_light(N, L, V, C, k.y, k.z, k.w, Ii)
                   : phong_light(N, L, V, C, k.y, k.z, k.w, Ii);
    }
    return clamp(I, 0.0, 1.0);
}
