#version 330 core
// The path tracer: one path per fragment and supersample, added to the accumulation
// (facet.render.trace.path_engine), on the ray tracer's hierarchy (trace/scene.glsl).
// Unidirectional. At each hit the material (trace/material.glsl: glTF metallic-roughness
// with its texture slots) adds what it emits and the direct light of
//   - the scene's point, spot and directional lights (delta lights: a shadow ray each),
//   - the emitting triangles (one point, chosen by power, then uniformly by area),
//   - the environment, or the scene's ambient light as a constant one (one direction,
//     uniform on the sphere),
// then the path goes on in a direction drawn from the BSDF (lib/pbr.glsl, the rasterizer's:
// a mixture of cosine-weighted diffuse and GGX half-vector sampling). Light sampling and
// BSDF sampling both find emitters and the environment; each is weighted by the power
// heuristic (Veach's multiple importance sampling, beta = 2), or u_strategy keeps only
// one of them (for tests). Cut-outs (alpha MASK) and BLEND surfaces (with probability
// 1 - alpha) let the ray by; shadow rays pass cut-outs and take 1 - alpha of each BLEND
// surface. Russian roulette after the third bounce; u_max_depth bounces after the eye ray
// at most (the last only gathers what it hits). Colour is linear radiance.
#include "trace/shade.glsl"
#include "trace/material.glsl"
#include "lib/pbr.glsl"
#include "lib/sampling.glsl"

uniform mat4 u_inv_view_projection;  // window NDC -> world, this sample's camera and shift
uniform vec2 u_viewport;
uniform vec4 u_background;  // straight RGB (linear) and alpha, for eye rays that escape
uniform int u_max_depth;    // bounces after the eye ray
uniform int u_sample;       // this supersample's index: with the pixel, the random stream
uniform int u_seed;
uniform int u_strategy;     // STRATEGY_*
uniform sampler2D u_emitters;  // per emitting triangle: (instance, triangle, cumulative
uniform int u_emitter_count;   // share of the emitted power, -), facet.render.trace.emitters
#ifdef HAS_ENVIRONMENT
uniform samplerCube u_environment;
#endif
out vec4 f_color;  // premultiplied colour and coverage of this sample

const int STRATEGY_MIS = 0, STRATEGY_LIGHT = 1, STRATEGY_BSDF = 2;
const int ROULETTE_AFTER = 3;  // bounces before Russian roulette may end a path
const int MAX_PASSES = 64;     // surfaces a ray may pass by (cut-outs, BLEND) in all
const float UNIFORM_SPHERE_PDF = 1.0 / (4.0 * PI);

// PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020).
uint g_rng;
uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
float random01() {  // uniform in [0, 1)
    g_rng = pcg_hash(g_rng);
    return float(g_rng >> 8u) * (1.0 / 16777216.0);
}
vec2 random2() { return vec2(random01(), random01()); }

// The radiance of the sky in direction d: the environment, or without one the scene's
// ambient light as a constant sky (the rasterizer's pbr model lights by it the same way).
vec3 escaped(vec3 d) {
#ifdef HAS_ENVIRONMENT
    return texture(u_environment, d).rgb;
#else
    return u_ambient.rgb;
#endif
}

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The power heuristic's weight of a sample of density a against the other strategy's b.
float power_weight(float a, float b) {
    float a2 = a * a;
    return a2 > 0.0 ? a2 / (a2 + b * b) : 0.0;
}

// f cos for light arriving from L (lib/pbr.glsl's pbr_light is pi f cos).
vec3 bsdf_cos(PbrSurface m, vec3 N, vec3 V, vec3 L) {
    return pbr_light(m, N, V, L) * (1.0 / PI);
}

// The probability of drawing from the specular lobe: its share of the reflected energy,
// roughly (the Fresnel reflectance at this angle against the diffuse albedo).
float specular_share(PbrSurface m) {
    float fc = schlick_weight(m.n_dot_v);
    float spec = luminance(m.f0 + (m.f90 - m.f0) * fc);
    float diff = luminance(m.c_diff * (1.0 - m.f0_d - (m.f90_d - m.f0_d) * fc));
    if (spec <= 0.0) return 0.0;  // no lobe (KHR_materials_specular's factor 0)
    return diff <= 0.0 ? 1.0 : clamp(spec / (spec + diff), 0.1, 0.9);
}

// The mixture's density of direction L (solid angle).
float bsdf_pdf(PbrSurface m, float p_spec, vec3 N, vec3 V, vec3 L) {
    float n_dot_l = dot(N, L);
    if (n_dot_l <= 0.0) return 0.0;
    vec3 H = normalize(L + V);
    float n_dot_h = max(dot(N, H), 0.0), v_dot_h = max(dot(V, H), 1e-6);
    float spec = ggx_d(n_dot_h, m.alpha) * n_dot_h / (4.0 * v_dot_h);
    return p_spec * spec + (1.0 - p_spec) * n_dot_l / PI;
}

// The light that gets from o along d within t_max: 0 behind an opaque surface; cut-outs
// let it by, BLEND surfaces 1 - alpha of it (as the rasterizer's shadow maps count them).
float visibility(vec3 o, vec3 d, float t_max) {
#ifdef HAS_ALPHA
    float through = 1.0;
    for (int k = 0; k < MAX_PASSES; ++k) {
        Hit h = trace_scene(o, d, t_max, false);
        if (h.inst < 0) return through;
        Surface s = surface_at(h, o, d);
        int mode;
        float cutoff;
        float a = coverage(h.inst, s, mode, cutoff);
        if (mode == ALPHA_OPAQUE || (mode == ALPHA_MASK && a >= cutoff)) return 0.0;
        if (mode == ALPHA_BLEND) through *= 1.0 - a;
        if (through <= 0.0) return 0.0;
        o = offset_ray(s.p, -s.ng);
        t_max -= h.t;
    }
    return 0.0;
#else
    return trace_shadow(o, d, t_max);
#endif
}

// A point on the emitting triangles for the surface point p: chosen by power (binary
// search in the cumulative shares), then uniformly on the triangle. Returns the radiance
// it sends towards p (0 from the back of a one-sided emitter), the direction L and
// distance to it, and the density of L in solid angle.
vec3 sample_emitter(vec3 p, out vec3 L, out float dist, out float pdf) {
    float u = random01();
    int lo = 0, hi = u_emitter_count - 1;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (fetch(u_emitters, mid).z > u) hi = mid; else lo = mid + 1;
    }
    vec4 e = fetch(u_emitters, lo);
    int inst = int(e.x), tri = int(e.y);
    vec2 b = random2();
    if (b.x + b.y > 1.0) b = 1.0 - b;
    vec3 p_obj = fetch(u_tris, 3 * tri).xyz + b.x * fetch(u_tris, 3 * tri + 1).xyz
               + b.y * fetch(u_tris, 3 * tri + 2).xyz;
    vec3 to = apply_rows(inst * INSTANCE_TEXELS + 3, p_obj, 1.0) - p;
    dist = length(to);
    L = to / max(dist, 1e-20);
    Surface s = surface_at(Hit(dist, inst, tri, b, vec3(0.0), vec2(0.0)), p, L);
    Material m = material_at(inst, s);
    float cos_l = abs(dot(s.ng, L));
    pdf = cos_l > 0.0 ? m.emit_pdf * dist * dist / cos_l : 0.0;
    bool one_sided = (int(fetch(u_instances, inst * INSTANCE_TEXELS + 6).w)
                      & FLAG_ONE_SIDED) != 0;
    return s.front || !one_sided ? m.emission : vec3(0.0);
}

void main() {
    g_rng = pcg_hash(uint(gl_FragCoord.x) + pcg_hash(uint(gl_FragCoord.y) +
                     pcg_hash(uint(u_sample) + pcg_hash(uint(u_seed)))));
    vec2 ndc = gl_FragCoord.xy / u_viewport * 2.0 - 1.0;
    vec4 near = u_inv_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far = u_inv_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 o = near.xyz / near.w;
    vec3 span = far.xyz / far.w - o;
    vec3 d = normalize(span);
    float t_max = length(span);  // the eye ray stops at the far plane, as rasterized
    vec3 radiance = vec3(0.0), throughput = vec3(1.0);
    float alpha = 1.0;
    float prev_pdf = 0.0;  // the BSDF's density of d (0 for the eye ray: no MIS)
    bool light_nee = u_strategy != STRATEGY_BSDF, bsdf_hits = u_strategy != STRATEGY_LIGHT;
#ifdef HAS_ENVIRONMENT
    bool sample_environment = light_nee;
#else
    bool sample_environment = light_nee && any(greaterThan(u_ambient.rgb, vec3(0.0)));
#endif
    int bounce = 0;
    for (int step = 0; step < u_max_depth + 2 + MAX_PASSES; ++step) {
        Hit h = trace_scene(o, d, t_max, false);
        if (h.inst < 0) {
            if (bounce == 0) {
#ifdef HAS_ENVIRONMENT
                radiance = escaped(d);
#else
                radiance = u_background.rgb * u_background.a;
                alpha = u_background.a;
#endif
            } else if (!sample_environment) {
                radiance += throughput * escaped(d);
            } else if (bsdf_hits) {
                radiance += throughput * escaped(d) * power_weight(prev_pdf, UNIFORM_SPHERE_PDF);
            }
            break;
        }
        Surface s = surface_at(h, o, d);
#ifdef HAS_ALPHA
        if (passes(h.inst, s, random01())) {  // not there for this ray: on, unchanged
            o = offset_ray(s.p, -s.ng);
            t_max -= h.t;
            continue;
        }
#endif
        Material mat = material_at(h.inst, s);
        // What it emits towards the eye, or towards the last surface that sampled its BSDF.
        bool one_sided = (int(fetch(u_instances, h.inst * INSTANCE_TEXELS + 6).w)
                          & FLAG_ONE_SIDED) != 0;
        if ((s.front || !one_sided) && mat.emission != vec3(0.0)) {
            float w = 1.0;
            if (bounce > 0 && mat.emit_pdf > 0.0 && u_emitter_count > 0) {
                float pdf_light = mat.emit_pdf * h.t * h.t / max(abs(dot(s.ng, d)), 1e-12);
                w = !light_nee ? 1.0 : bsdf_hits ? power_weight(prev_pdf, pdf_light) : 0.0;
            }
            radiance += throughput * mat.emission * w;
        }
        if (mat.unlit) {  // KHR_materials_unlit: its colour, and nothing reflected
            radiance += throughput * mat.base;
            break;
        }
        if (bounce > u_max_depth) break;  // this bounce only gathered what it hit
        vec3 V = -d, N = valid_normal(mat.n, s.ng, V);
        PbrSurface m = pbr_surface_full(mat.base, mat.metallic, mat.roughness, dot(N, V),
                                        mat.f0_d, mat.f90_d);
        float p_spec = specular_share(m);
        vec3 from = offset_ray(s.p, s.ng);
        // Direct light from the scene's lights (delta lights: one shadow ray each).
        for (int i = 0; i < u_light_count.x; ++i) {
            vec3 L;
            float falloff = incident_light(i, s.p, L);
            if (falloff <= 0.0 || dot(N, L) <= 0.0 || dot(s.ng, L) <= 0.0) continue;
            float dist = LIGHT_KIND(i) == LIGHT_DIRECTIONAL
                       ? INF : length(u_lights[i].position.xyz - s.p);
            radiance += throughput * visibility(from, L, dist) * falloff
                      * u_lights[i].color.rgb * pbr_light(m, N, V, L);
        }
        // One point on the emitting triangles.
        if (light_nee && u_emitter_count > 0) {
            vec3 L;
            float dist, pdf_light;
            vec3 Le = sample_emitter(s.p, L, dist, pdf_light);
            if (pdf_light > 0.0 && Le != vec3(0.0) && dot(N, L) > 0.0 && dot(s.ng, L) > 0.0) {
                float w = bsdf_hits ? power_weight(pdf_light, bsdf_pdf(m, p_spec, N, V, L))
                                    : 1.0;
                radiance += throughput * Le * bsdf_cos(m, N, V, L) * (w / pdf_light)
                          * visibility(from, L, dist * (1.0 - 1e-4));
            }
        }
        // One direction of the environment.
        if (sample_environment) {
            vec2 xi = random2();
            float z = 1.0 - 2.0 * xi.x, r = sqrt(max(1.0 - z * z, 0.0));
            vec3 L = vec3(r * cos(TWO_PI * xi.y), r * sin(TWO_PI * xi.y), z);
            if (dot(N, L) > 0.0 && dot(s.ng, L) > 0.0) {
                float w = bsdf_hits
                        ? power_weight(UNIFORM_SPHERE_PDF, bsdf_pdf(m, p_spec, N, V, L)) : 1.0;
                radiance += throughput * escaped(L) * bsdf_cos(m, N, V, L)
                          * (w / UNIFORM_SPHERE_PDF) * visibility(from, L, INF);
            }
        }
        // The next direction, from the BSDF.
        vec3 L;
        if (random01() < p_spec) {
            vec3 H = around(ggx_sample(random2(), m.alpha), N);
            L = reflect(-V, H);
        } else {
            L = around(cosine_sample(random2()), N);
        }
        float pdf = bsdf_pdf(m, p_spec, N, V, L);
        if (pdf <= 0.0 || dot(s.ng, L) <= 0.0) break;  // below the surface: absorbed
        throughput *= bsdf_cos(m, N, V, L) / pdf;
        prev_pdf = pdf;
        ++bounce;
        if (bounce > ROULETTE_AFTER) {
            float survive = clamp(max(throughput.r, max(throughput.g, throughput.b)), 0.05,
                                  0.95);
            if (random01() >= survive) break;
            throughput /= survive;
        }
        o = from;
        d = L;
        t_max = INF;
    }
    f_color = vec4(radiance, alpha);
}
