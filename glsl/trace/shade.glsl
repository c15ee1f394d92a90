// The Whitted tracer's local shading of a surface: the Phong models by the rasterizer's own
// equation (lib/lights.glsl's light_scene, with this hit's material products and shadow
// rays in place of the per-draw uniforms and shadow maps), and a metallic-roughness
// material by the rasterizer's BRDF over the shared layering (lib/layers.glsl), lit by the
// lights with shadow rays and by the ambient light as a uniform sky.
#include "trace/surface.glsl"

// The material of the surface being shaded, for lib/lights.glsl's macros.
vec3 g_ambient_term, g_kd_c, g_ks;
float g_shininess;
vec3 g_ng;  // its geometric normal, for the shadow rays' offset
float light_visibility(int i, vec3 p, vec3 N, vec3 L, float falloff);
float through_surfaces(vec3 o, vec3 d, float t_max, int passes, bool refracting);
#define RECORD_PER_HIT  // (lib/lights.glsl: no per-draw record, mesh/record.glsl)
#define AMBIENT_TERM g_ambient_term
#define LIGHT_DIFFUSE(i) (u_lights[i].color.rgb * g_kd_c)
#define LIGHT_SPECULAR(i) (u_lights[i].color.rgb * g_ks)
#define SHININESS g_shininess
#define SHADOW(i, p, N, L, falloff) light_visibility(i, p, N, L, falloff)
#include "lib/lights.glsl"

// Shadow rays: towards the light from the side of the surface the light is on, up to the
// light (directional lights: without end); none where the light adds nothing anyway
// (outside a spot's cone, or behind the shading normal, where N.L <= 0).
float light_visibility(int i, vec3 p, vec3 N, vec3 L, float falloff) {
#ifdef SHADOWS
    if (falloff <= 0.0 || dot(N, L) <= 0.0) return 1.0;
    float dist = LIGHT_KIND(i) == LIGHT_DIRECTIONAL ? INF
                                                    : length(u_lights[i].position.xyz - p);
    vec3 side = dot(g_ng, L) >= 0.0 ? g_ng : -g_ng;
#ifdef ALPHA_SHADOWS
    return through_surfaces(offset_ray(p, side), L, dist, 8, true);
#else
    return trace_shadow(offset_ray(p, side), L, dist);
#endif
#else
    return 1.0;
#endif
}

#ifdef PBR_SLOTS
#include "trace/material.glsl"
#include "lib/layers.glsl"

// Below this roughness the Whitted tracer traces the scene's reflection in a glTF material
// and in its clear coat (glsl/trace/trace.frag); g_traced_specular and g_traced_coat of the
// ambient light's specular parts are left to those rays.
const float TRACED_ROUGHNESS = 0.6;
float g_traced_specular = 0.0;
float g_traced_coat = 0.0;

// The light that gets from o along d within t_max through what is not opaque, nearest
// first, over at most ``passes`` surfaces (lets_through: BLEND coverage, MASK cut-outs,
// thin glass; ``refracting`` as lets_through takes it): the Whitted tracer's shadow rays
// (ALPHA_SHADOWS) and the path tracer's visibility (trace/light_sampling.glsl).
float through_surfaces(vec3 o, vec3 d, float t_max, int passes, bool refracting) {
    float through = 1.0;
    for (int k = 0; k < passes; ++k) {
        Hit h = trace_scene(o, d, t_max, false);
        if (h.inst < 0 || h.inst == g_shadow_skip) return through;
        Surface s = surface_at(h, o, d);
        through *= lets_through(s, d, refracting);
        if (through <= 0.0) return 0.0;
        o = offset_ray(s.p, -s.ng);
        t_max -= h.t;
    }
    return 0.0;
}

// A metallic-roughness surface: each light with its shadow ray, the ambient light as a
// uniform sky (its split sum by the lobes' albedos), dimmed by the occlusion texture as the
// rasterizer's image-based light is; emission. Encoded for display outside the sRGB mode,
// as glsl/mesh/pbr.frag writes it.
vec3 shade_pbr(Surface s, vec3 V) {
    Material mat = material_of(s);
    vec3 rgb = mat.base;
    if (!mat.unlit) {
        vec3 N = valid_normal(mat.n, s.ng, V);
        vec3 c_trans;  // passes on: glsl/trace/trace.frag's transmission ray
        PbrSurface m = layered_surface(mat, N, valid_normal(mat.cc_n, s.ng, V), V, c_trans);
        g_ng = s.ng;
        rgb = vec3(0.0);
        for (int i = 0; i < u_light_count.x; ++i) {
            vec3 L;
            float falloff = incident_light(i, s.p, L);
            vec3 through = pbr_light_through(m, c_trans, N, V, L, mat.roughness,
                                             max(mat.ior, 1.0));  // a light behind glass
            float seen = light_visibility(i, s.p, through == vec3(0.0) && dot(N, L) >= 0.0
                                                  ? N : -N, L, falloff);  // (behind: -N)
            rgb += falloff * seen * u_lights[i].color.rgb * (pbr_light(m, N, V, L) + through);
        }
        float fc = schlick_weight(m.n_dot_v);
        vec3 F = pbr_fresnel(m, fc), F_d = pbr_fresnel_d(m, fc);
        vec3 sky = pbr_ambient_sheen(m, F * ggx_albedo(m.n_dot_v, mat.roughness) * m.ms
                                         * (1.0 - g_traced_specular)
                                         + (1.0 - F_d) * (m.c_diff + m.c_dt), vec3(1.0));
        sky = sky * (1.0 - m.cc * m.cc_fresnel) + m.cc * m.cc_fresnel * (1.0 - g_traced_coat)
            * ggx_albedo(m.cc_n_dot_v, mat.clearcoat_roughness);
        rgb += sky * u_ambient.rgb * mat.occlusion;
    }
    rgb += mat.emission;
#if !defined(COLOR_SRGB) && !defined(LINEAR_OUT)
    rgb = linear_to_srgb(clamp(rgb, 0.0, 1.0));
#endif
    return rgb;
}
#endif

// The Phong models' local colour of a surface seen from V (not clamped).
vec3 local_colour(Surface s, vec3 V) {
    vec3 c = s.color;
    g_ambient_term = u_ambient.rgb * s.k.x * c;
    g_kd_c = s.k.y * c;
    g_ks = vec3(s.k.z);
    g_shininess = s.k.w;
    g_ng = s.ng;
#if defined(SHADE_UNLIT)
    return c * s.albedo;
#elif defined(SHADE_NORMALS)
    return (s.front ? s.n : -s.n) * 0.5 + 0.5;  // the outward normal, as rasterized
#elif defined(SHADE_FLAT)
    return light_scene(s.p, s.ng, V, s.albedo, false);
#elif defined(SHADE_BLINN)
    return light_scene(s.p, s.n, V, s.albedo, true);
#else  // SHADE_PHONG; SHADE_GOURAUD is a rasterizer's per-vertex shortcut: traced as Phong
    return light_scene(s.p, s.n, V, s.albedo, false);
#endif
}

// The local colour of a surface seen from direction V (towards the viewer), times the
// share ``keep`` it adds beside its reflection (1 - reflectivity). The Phong models clamp
// that share as a pixel is clamped, not the local colour before it is shared: a highlight
// brighter than 1 still shows through (1 - reflectivity), as the notes' equation has it.
vec3 shade_surface(Surface s, vec3 V, float keep) {
#ifdef PBR_SHADING
    if (own_pbr(s)) return keep * shade_pbr(s, V);
#endif
    return clamp(keep * local_colour(s, V), 0.0, 1.0);
}
