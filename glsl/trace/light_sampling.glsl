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
// One loop over these candidates with one shadow ray, one BSDF evaluation and one density
// in its body: llvmpipe runs every line of a shader's branches whether or not a lane takes
// them (only loops end early), so each call site of visibility() was a whole traversal
// run on every bounce; four of them were most of a path's time.
vec3 direct_light(Surface s, Material mat, Bsdf b, vec3 N, vec3 V, bool emitters, bool sky,
                  bool bsdf_hits) {
    vec3 light = vec3(0.0);
    // The candidates there are: each delta light, then one emitter point, then one sky
    // direction (a loop's turn costs its whole body, taken or not).
#ifdef NO_DELTA_LIGHTS
    int delta = 0;
#else
    int delta = u_light_count.x;
#endif
#ifdef NO_EMITTERS
    int emitter = -1;
#else
    int emitter = emitters && u_emitter_count > 0 ? delta : -1;
#endif
    int count = delta + (emitter >= 0 ? 1 : 0) + (sky ? 1 : 0);
    // do-while: llvmpipe runs a for loop's body once more for its failing test at the top.
    int j = -1;
    if (count > 0) do {
        ++j;
        vec3 L, weight;       // the light's radiance over its density, before the BSDF
        float dist = INF;     // to the light
        float pdf_light = 0.0;  // > 0: weighed against BSDF sampling
        float scale = 1.0;    // delta lights: their irradiance times PI
        bool through = false;  // through a thin rough wall, from behind it
        int skip = -1;         // an instance the shadow ray passes (sample_emitter)
#ifndef NO_DELTA_LIGHTS
        if (j < delta) {
            // A delta light: one shadow ray each.
            float falloff = incident_light(j, s.p, L);
            if (falloff <= 0.0) continue;
            if (LIGHT_KIND(j) != LIGHT_DIRECTIONAL) dist = length(u_lights[j].position.xyz - s.p);
            weight = falloff * u_lights[j].color.rgb;
            scale = PI;
            // A thin rough wall passes a light behind it through its transmission lobe (a
            // delta light: no path from the eye finds it otherwise).
            through = (b.thin && !b.polished || b.m.c_dt != vec3(0.0)) && dot(s.ng, L) < 0.0;
            if (!through && (dot(N, L) <= 0.0 || dot(s.ng, L) <= 0.0)) continue;
        } else
#endif
#ifndef NO_EMITTERS
        if (j == emitter) {
            // One point on the emitting triangles.
            vec3 Le = sample_emitter(s.p, L, dist, pdf_light, skip);
            if (pdf_light <= 0.0 || Le == vec3(0.0) || dot(N, L) <= 0.0 || dot(s.ng, L) <= 0.0)
                continue;
            weight = Le / pdf_light;
            dist *= 1.0 - 1e-4;
        } else
#endif
        {
            // One direction of the environment.
            L = sample_sky(s.ng, pdf_light);
            if (pdf_light <= 0.0 || dot(N, L) <= 0.0 || dot(s.ng, L) <= 0.0) continue;
            weight = sky_light(L) / pdf_light;
        }
        // (behind, bsdf_eval is the diffuse transmission lobe's alone)
        vec3 f = scale * bsdf_eval(b, N, V, L);
        if (through && b.thin && !b.polished)
            f += pbr_light_through(b.m, b.c_trans, N, V, L, mat.roughness, max(mat.ior, 1.0));
        float w = pdf_light > 0.0 && bsdf_hits ?
                  power_weight(pdf_light, bsdf_pdf(b, N, V, L)) : 1.0;
        if (f == vec3(0.0) || w == 0.0) continue;
        g_shadow_skip = skip;
        light += weight * f * w * visibility(offset_ray(s.p, through ? -s.ng : s.ng), L, dist);
        g_shadow_skip = -1;
    } while (j + 1 < count);
    return light;
}
