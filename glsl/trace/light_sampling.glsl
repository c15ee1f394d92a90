// Light sampling of the path tracer (direct_light): shadow rays through cut-outs and
// BLEND surfaces, the scene's lights, a point on the emitters, a direction of the sky,
// each weighed against BSDF sampling by the power heuristic (multiple importance
// sampling, Veach 1997).
#include "trace/shade.glsl"
#include "trace/bsdf.glsl"
#include "trace/sky.glsl"
#include "trace/emitters.glsl"

const int MAX_PASSES = 64;     // surfaces a ray may pass by (cut-outs, BLEND) in all

// The light that gets from o along d within t_max: 0 behind an opaque surface; cut-outs
// let it by, BLEND surfaces 1 - alpha of it (as the rasterizer's shadow maps count them).
float visibility(vec3 o, vec3 d, float t_max) {
#ifdef HAS_ALPHA
    return through_surfaces(o, d, t_max, MAX_PASSES, false);
#else
    return trace_shadow(o, d, t_max);
#endif
}

// The power heuristic's weight of a sample of density a against the other strategy's b.
float power_weight(float a, float b) {
    float a2 = a * a;
    return a2 > 0.0 ? a2 / (a2 + b * b) : 0.0;
}

// The light that the surface point s (its material mat, BSDF b, shading normal N) sends
// back along V straight from the lights: the scene's point, spot and directional lights
// (a shadow ray each), one point on the emitters and one direction of the sky when asked,
// each weighed against BSDF sampling's finding them when bsdf_hits.
vec3 direct_light(Surface s, Material mat, Bsdf b, vec3 N, vec3 V, bool emitters, bool sky,
                  bool bsdf_hits) {
    vec3 light = vec3(0.0), from = offset_ray(s.p, s.ng);
    // Direct light from the scene's lights (delta lights: one shadow ray each).
    for (int i = 0; i < u_light_count.x; ++i) {
        vec3 L;
        float falloff = incident_light(i, s.p, L);
        float dist = LIGHT_KIND(i) == LIGHT_DIRECTIONAL
                   ? INF : length(u_lights[i].position.xyz - s.p);
        if (falloff <= 0.0) continue;
        if (dot(N, L) > 0.0 && dot(s.ng, L) > 0.0) {
            light += visibility(from, L, dist) * falloff
                 * u_lights[i].color.rgb * (PI * bsdf_eval(b, N, V, L));
        } else if (b.thin && !b.polished && dot(s.ng, L) < 0.0) {
            // A thin rough wall passes a light behind it through its transmission lobe
            // (a delta light: no path from the eye finds it otherwise).
            light += visibility(offset_ray(s.p, -s.ng), L, dist) * falloff
                 * u_lights[i].color.rgb * pbr_light_through(
                          b.m, b.c_trans, N, V, L, mat.roughness, max(mat.ior, 1.0));
        }
    }
    // One point on the emitting triangles.
    if (emitters && u_emitter_count > 0) {
        vec3 L;
        float dist, pdf_light;
        vec3 Le = sample_emitter(s.p, L, dist, pdf_light);
        if (pdf_light > 0.0 && Le != vec3(0.0) && dot(N, L) > 0.0 && dot(s.ng, L) > 0.0) {
            float w = bsdf_hits ? power_weight(pdf_light, bsdf_pdf(b, N, V, L)) : 1.0;
            light += Le * bsdf_eval(b, N, V, L) * (w / pdf_light)
                 * visibility(from, L, dist * (1.0 - 1e-4));
        }
    }
    // One direction of the environment.
    if (sky) {
        float pdf_sky;
        vec3 L = sample_sky(pdf_sky);
        if (pdf_sky > 0.0 && dot(N, L) > 0.0 && dot(s.ng, L) > 0.0) {
            float w = bsdf_hits ? power_weight(pdf_sky, bsdf_pdf(b, N, V, L)) : 1.0;
            light += sky_light(L) * bsdf_eval(b, N, V, L)
                 * (w / pdf_sky) * visibility(from, L, INF);
        }
    }
    return light;
}
