#version 330 core
// The path tracer: one path per fragment and supersample, added to the accumulation
// (facet.render.trace.path_engine), on the ray tracer's hierarchy (trace/scene.glsl).
// Unidirectional: from the eye, each hit adds what it emits (when reached by the BSDF's
// own sampling) and the direct light of the scene's lights (point, spot, directional:
// delta lights, sampled with one shadow ray each: next-event estimation), then continues
// in a direction drawn from its BSDF, the glTF metallic-roughness model of lib/pbr.glsl
// (the rasterizer's; Phong materials through facet's mapping, facet.render.materials
// .as_pbr): a mixture of cosine-weighted diffuse and GGX half-vector sampling, weighted by
// f cos / pdf of the mixture. Rays that escape take the environment's radiance (none:
// black, and the background for eye rays). Russian roulette after the third bounce;
// u_max_depth bounces after the eye ray at most. Colour is linear radiance.
#include "trace/shade.glsl"
#include "lib/pbr.glsl"
#include "lib/sampling.glsl"

uniform mat4 u_inv_view_projection;  // window NDC -> world, this sample's camera and shift
uniform vec2 u_viewport;
uniform vec4 u_background;  // straight RGB (linear) and alpha, for eye rays that escape
uniform int u_max_depth;    // bounces after the eye ray
uniform int u_sample;       // this supersample's index: with the pixel, the random stream
uniform int u_seed;
#ifdef HAS_ENVIRONMENT
uniform samplerCube u_environment;
#endif
out vec4 f_color;  // premultiplied colour and coverage of this sample

const int ROULETTE_AFTER = 3;  // bounces before Russian roulette may end a path

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

vec3 escaped(vec3 d) {
#ifdef HAS_ENVIRONMENT
    return texture(u_environment, d).rgb;
#else
    return vec3(0.0);
#endif
}

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// f cos for light arriving from L (lib/pbr.glsl's pbr_light is pi f cos).
vec3 bsdf_cos(PbrSurface m, vec3 N, vec3 V, vec3 L) {
    return pbr_light(m, N, V, L) * (1.0 / PI);
}

// The probability of drawing from the specular lobe: its share of the reflected energy,
// roughly (the Fresnel reflectance at this angle against the diffuse albedo).
float specular_share(PbrSurface m) {
    float spec = luminance(m.f0 + (1.0 - m.f0) * schlick_weight(m.n_dot_v));
    float diff = luminance(m.c_diff) * (1.0 - DIELECTRIC_F0);
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
    for (int bounce = 0; bounce <= u_max_depth; ++bounce) {
        Hit h = trace_scene(o, d, t_max, false);
        if (h.inst < 0) {
            if (bounce == 0) {
#ifdef HAS_ENVIRONMENT
                radiance = escaped(d);
#else
                radiance = u_background.rgb * u_background.a;
                alpha = u_background.a;
#endif
            } else {
                radiance += throughput * escaped(d);
            }
            break;
        }
        Surface s = surface_at(h, o, d);
        int base = h.inst * INSTANCE_TEXELS;
        vec4 p0 = fetch(u_instances, base + 11), p1 = fetch(u_instances, base + 12);
        vec3 V = -d, N = s.n;
        PbrSurface m = pbr_surface(p0.rgb * s.albedo, p0.w, p1.w, dot(N, V));
        // Emission is one-sided: the outward face emits (two-sided materials both).
        if (s.front || (int(fetch(u_instances, base + 6).w) & FLAG_ONE_SIDED) == 0)
            radiance += throughput * p1.rgb;
        // Direct light from the scene's lights (delta lights: one shadow ray each).
        for (int i = 0; i < u_light_count.x; ++i) {
            vec3 L;
            float falloff = incident_light(i, s.p, L);
            if (falloff <= 0.0 || dot(N, L) <= 0.0 || dot(s.ng, L) <= 0.0) continue;
            float dist = LIGHT_KIND(i) == LIGHT_DIRECTIONAL
                       ? INF : length(u_lights[i].position.xyz - s.p);
            float visible = trace_shadow(offset_ray(s.p, s.ng), L, dist);
            radiance += throughput * visible * falloff * u_lights[i].color.rgb
                      * pbr_light(m, N, V, L);
        }
        if (bounce == u_max_depth) break;
        // The next direction, from the BSDF.
        float p_spec = specular_share(m);
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
        if (bounce >= ROULETTE_AFTER) {
            float survive = clamp(max(throughput.r, max(throughput.g, throughput.b)), 0.05,
                                  0.95);
            if (random01() >= survive) break;
            throughput /= survive;
        }
        o = offset_ray(s.p, s.ng);
        d = L;
        t_max = INF;
    }
    f_color = vec4(radiance, alpha);
}
