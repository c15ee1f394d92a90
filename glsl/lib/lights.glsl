// The scene's lights as a uniform block, and the whole shading equation over them.
// World space throughout. Filled by facet.render.state.pack_lights (std140, 4 vec4 per
// light); MAX_LIGHTS is facet.scene.scene.MAX_LIGHTS, defined by facet when it compiles.
// The shading equation takes the material's products with each light:
//   AMBIENT_TERM = I_a k_a C, LIGHT_DIFFUSE(i) = I_i k_d C, LIGHT_SPECULAR(i) = I_i k_s,
// from the material record (the rasterizer's: mesh/record.glsl; the tracers define them
// from the record of the surface they hit).
#include "lib/lighting.glsl"

#ifndef MAX_LIGHTS
#error MAX_LIGHTS is defined by facet (facet.scene.scene.MAX_LIGHTS)
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

// The material's products with the lights. The rasterizer (and a user's mesh shader) reads
// the drawn object's record; the ray tracer, whose material changes from hit to hit,
// defines these four macros before including this file (glsl/trace/shade.glsl).
// (record.glsl is included here whatever the macros: facet includes each file once per
// stage, ahead of the preprocessor, so an include inside an #if block would hide it from a
// later one outside; the tracers' stages define RECORD_PER_HIT and get none of it.)
#include "mesh/record.glsl"
#ifndef LIGHT_DIFFUSE
#ifdef GREY_TERMS
// Every term is grey (facet checks per draw): one channel is read and spread, so the
// compiler computes one colour channel where it would compute three; the same picture.
// (the products associated as below, so both give the same bits)
#define AMBIENT_TERM vec3(u_ambient.x * (phong_ka() * phong_c().x))
#define LIGHT_DIFFUSE(i) vec3(u_lights[i].color.x * (phong_kd() * phong_c().x))
#define LIGHT_SPECULAR(i) vec3(u_lights[i].color.x * phong_ks())
#else
#define AMBIENT_TERM (u_ambient.rgb * (phong_ka() * phong_c()))
#define LIGHT_DIFFUSE(i) (u_lights[i].color.rgb * (phong_kd() * phong_c()))
#define LIGHT_SPECULAR(i) (u_lights[i].color.rgb * phong_ks())
#endif
#define SHININESS phong_shininess()
#endif

// Unit vector from p towards light i, and the fraction of the light's intensity that
// arrives at p (1 for directional lights; attenuation and cone for point and spot lights).
float incident_light(int i, vec3 p, out vec3 L) {
    LightData light = u_lights[i];
    int kind = LIGHT_KIND(i);
    if (kind == LIGHT_DIRECTIONAL) {
        L = -light.direction.xyz;
        return 1.0;
    }
    vec3 to_light = light.position.xyz - p;
    float d = length(to_light);
    L = to_light / max(d, 1e-9);
    float falloff = light_attenuation(light.falloff.xyz, d);
    if (kind == LIGHT_SPOT) falloff *= spot_cone(-L, light.direction.xyz, light.direction.w,
                                                 light.color.w);
    return falloff;
}

// The fraction of light i that reaches p: shadow maps in the rasterizer, shadow rays in the
// ray tracer (which defines SHADOW itself), 1 without shadows. ``falloff`` is what arrives
// unshadowed (0: nothing to shadow, so the tracer casts no ray).
#ifndef SHADOW
#if defined(SHADOWS) && defined(LIGHT_COUNT) && LIGHT_COUNT > 0
#include "lib/shadows.glsl"
#define SHADOW(i, p, N, L, falloff) shadow_factor(i, p, N, L, \
                                                  length(u_lights[i].position.xyz - p))
#else
#define SHADOW(i, p, N, L, falloff) 1.0
#endif
#endif

// I = I_a k_a C + sum_i (diffuse + specular), not clamped: what a surface adds before it is
// mixed with its reflection (the notes clamp the pixel, not the local colour). ``albedo``
// multiplies C where it varies over the surface (texture x vertex colour; vec3(1) for
// plain materials). blinn selects the halfway-vector specular.
vec3 light_scene(vec3 p, vec3 N, vec3 V, vec3 albedo, bool blinn) {
    vec3 I = AMBIENT_TERM * albedo;
    for (int i = 0; i < LIGHTS_IN_USE; ++i) {
        vec3 L;
        float falloff = incident_light(i, p, L);
        falloff *= SHADOW(i, p, N, L, falloff);
        vec3 diffuse = LIGHT_DIFFUSE(i) * albedo;
        I += falloff * (blinn
            ? blinn_light(N, L, V, diffuse, LIGHT_SPECULAR(i), SHININESS)
            : phong_light(N, L, V, diffuse, LIGHT_SPECULAR(i), SHININESS));
    }
    return I;
}

// The same, clamped to [0, 1]: the colour of a surface that reflects nothing.
vec3 shade_scene(vec3 p, vec3 N, vec3 V, vec3 albedo, bool blinn) {
    return clamp(light_scene(p, N, V, albedo, blinn), 0.0, 1.0);
}
