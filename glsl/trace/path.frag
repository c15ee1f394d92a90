#version 330 core
// The path tracer: one path per fragment and supersample, added to the accumulation
// (facet.render.trace.path_engine), on the ray tracer's hierarchy (trace/scene.glsl).
// Unidirectional. At each hit the material (trace/material.glsl: glTF metallic-roughness
// with its texture slots) adds what it emits and the direct light of
//   - the scene's point, spot and directional lights (delta lights: a shadow ray each),
//   - the emitting triangles (one point, chosen by power, then uniformly by area),
//   - the environment, or the scene's ambient light as a constant one (one direction: by
//     the environment image's luminance, or uniform on the sphere),
// then the path goes on in a direction drawn from the BSDF (lib/pbr.glsl, the rasterizer's:
// a mixture of cosine-weighted diffuse and GGX half-vector sampling). Light sampling and
// BSDF sampling both find emitters and the environment; each is weighted by the power
// heuristic (Veach's multiple importance sampling, beta = 2), or u_strategy keeps only
// one of them (for tests). Cut-outs (alpha MASK) and BLEND surfaces (with probability
// 1 - alpha) let the ray by; shadow rays pass cut-outs and take 1 - alpha of each BLEND
// surface. Russian roulette after the fifth bounce (paths carrying less than 1 survive
// with that probability); u_max_depth bounces after the eye ray
// at most (the last only gathers what it hits). Colour is linear radiance.
#include "trace/shade.glsl"
#include "trace/material.glsl"
#include "trace/bsdf.glsl"

uniform mat4 u_inv_view_projection;  // window NDC -> world, this sample's camera and shift
uniform vec2 u_viewport;
uniform vec4 u_background;  // straight RGB (linear) and alpha, for eye rays that escape
uniform int u_max_depth;    // bounces after the eye ray
uniform int u_sample;       // this supersample's index: with the pixel, the random stream
uniform int u_seed;
uniform bool u_flip_y;      // offscreen targets are drawn upside down (facet.gl.targets)
uniform int u_strategy;     // STRATEGY_*
uniform sampler2D u_emitters;  // per emitting triangle: (instance, triangle, cumulative
uniform int u_emitter_count;   // share of the emitted power, -), facet.render.trace.emitters
#ifdef HAS_ENVIRONMENT
uniform samplerCube u_environment;
#endif
#ifdef SKY_DISTRIBUTION
// The environment's luminance distribution (facet.render.trace.env_sampling): cumulative
// shares per row (and of the rows, in column W), densities over the unit square.
uniform sampler2D u_sky_cdf;
uniform sampler2D u_sky_pdf;
uniform sampler2D u_sky_radiance;  // the grid the distribution was made from (RGB)
uniform ivec2 u_sky_size;  // W, H
#endif
out vec4 f_color;  // premultiplied colour and coverage of this sample

const int STRATEGY_MIS = 0, STRATEGY_LIGHT = 1, STRATEGY_BSDF = 2;
const int ROULETTE_AFTER = 5;  // bounces before Russian roulette may end a path (Mitsuba's)
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
    // The finest level: neighbouring pixels' random directions are no footprint (texture()
    // would pick a blurred level from their differences, dimming a small bright sun).
    return textureLod(u_environment, d, 0.0).rgb;
#else
    return u_ambient.rgb;
#endif
}

#ifdef SKY_DISTRIBUTION
// The texel of the sky's latitude-longitude grid that direction d falls in.
ivec2 sky_texel(vec3 d) {
    float u = 0.5 + atan(d.x, -d.z) / TWO_PI, v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    return clamp(ivec2(vec2(u, v) * vec2(u_sky_size)), ivec2(0), u_sky_size - 1);
}
#endif

// The sky's radiance lighting a surface from direction d: with a distribution, the
// grid's texel it was made from (the ratio of radiance to density stays bounded: the
// cube map's filtering spread a small sun where the density is low, each sample there a
// firefly); the camera sees the cube map (escaped).
vec3 sky_light(vec3 d) {
#ifdef SKY_DISTRIBUTION
    return texelFetch(u_sky_radiance, sky_texel(d), 0).rgb;
#else
    return escaped(d);
#endif
}

// The sky's density of direction d for light sampling (solid angle).
float sky_pdf(vec3 d) {
#ifdef SKY_DISTRIBUTION
    float sin_t = sqrt(max(1.0 - d.y * d.y, 0.0));
    return sin_t > 0.0 ? texelFetch(u_sky_pdf, sky_texel(d), 0).r / (2.0 * PI * PI * sin_t)
                       : 0.0;
#else
    return UNIFORM_SPHERE_PDF;
#endif
}

// A sky direction for light sampling, and its density: by luminance (a texel by two
// binary searches, then a point in it), or uniform on the sphere.
vec3 sample_sky(out float pdf) {
#ifdef SKY_DISTRIBUTION
    int w = u_sky_size.x;
    float r = random01(), c = random01();
    int lo = 0, hi = u_sky_size.y - 1;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (texelFetch(u_sky_cdf, ivec2(w, mid), 0).r > r) hi = mid; else lo = mid + 1;
    }
    int y = lo;
    lo = 0;
    hi = w - 1;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (texelFetch(u_sky_cdf, ivec2(mid, y), 0).r > c) hi = mid; else lo = mid + 1;
    }
    vec2 uv = (vec2(lo, y) + random2()) / vec2(u_sky_size);
    float phi = (uv.x - 0.5) * TWO_PI, theta = uv.y * PI;
    vec3 d = vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    pdf = sky_pdf(d);
    return d;
#else
    vec2 xi = random2();
    float z = 1.0 - 2.0 * xi.x, r = sqrt(max(1.0 - z * z, 0.0));
    pdf = UNIFORM_SPHERE_PDF;
    return vec3(r * cos(TWO_PI * xi.y), r * sin(TWO_PI * xi.y), z);
#endif
}

// The power heuristic's weight of a sample of density a against the other strategy's b.
float power_weight(float a, float b) {
    float a2 = a * a;
    return a2 > 0.0 ? a2 / (a2 + b * b) : 0.0;
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
        through *= lets_through(s, d, false);
        if (through <= 0.0) return 0.0;
        o = offset_ray(s.p, -s.ng);
        t_max -= h.t;
    }
    return 0.0;
#else
    return trace_shadow(o, d, t_max);
#endif
}

// A point uniformly by area on an analytic shape (facet.scene.shapes, object space; y up,
// centred): a sphere, a disk, a finite plane, a box's faces, a cylinder's or a cone's side
// and caps, each part chosen by its share of the area.
vec3 shape_point(int kind, vec4 q) {
    vec2 r = random2();
    float phi = 2.0 * PI * r.y, pick = random01();
    vec2 ring = vec2(cos(phi), sin(phi));
    if (kind == KIND_SPHERE) {
        float y = 1.0 - 2.0 * r.x, s = sqrt(max(1.0 - y * y, 0.0));
        return q.x * vec3(s * ring.x, y, s * ring.y);
    }
    if (kind == KIND_DISK) return vec3(q.x * sqrt(r.x) * ring.x, 0.0, q.x * sqrt(r.x) * ring.y);
    if (kind == KIND_PLANE) return vec3((r.x - 0.5) * q.x, 0.0, (r.y - 0.5) * q.y);
    float side = random01() < 0.5 ? -0.5 : 0.5;  // which of two opposite faces or caps
    if (kind == KIND_BOX) {
        vec3 a = vec3(q.y * q.z, q.x * q.z, q.x * q.y);  // the faces facing x, y, z
        pick *= a.x + a.y + a.z;
        if (pick < a.x) return vec3(side * q.x, (r.x - 0.5) * q.y, (r.y - 0.5) * q.z);
        if (pick < a.x + a.y) return vec3((r.x - 0.5) * q.x, side * q.y, (r.y - 0.5) * q.z);
        return vec3((r.x - 0.5) * q.x, (r.y - 0.5) * q.y, side * q.z);
    }
    float radius = q.x, h = q.y;
    if (kind == KIND_CYLINDER) {  // side 2 pi r h, caps 2 pi r^2
        if (pick * (h + radius) < h) return vec3(radius * ring.x, (r.x - 0.5) * h, radius * ring.y);
        return vec3(radius * sqrt(r.x) * ring.x, side * h, radius * sqrt(r.x) * ring.y);
    }
    // the cone: side pi r l (density along it grows with the distance from the apex), base
    float l = length(vec2(radius, h));
    if (pick * (l + radius) < l) {
        float t = sqrt(r.x);
        return vec3(radius * t * ring.x, 0.5 * h - h * t, radius * t * ring.y);
    }
    return vec3(radius * sqrt(r.x) * ring.x, -0.5 * h, radius * sqrt(r.x) * ring.y);
}

// The point p_obj of the emitting shape of instance inst as seen from p: the hit where the
// ray from p towards it meets the shape, when that is the point itself (else the shape
// hides it from p: false).
bool shape_hit_at(int inst, vec3 p_obj, vec3 p, out Hit h, out vec3 L, out float dist) {
    int base = inst * INSTANCE_TEXELS;
    vec3 to = apply_rows(base + 3, p_obj, 1.0) - p;
    dist = length(to);
    L = to / max(dist, 1e-20);
    vec3 oo = apply_rows(base, p, 1.0), od = apply_rows(base, L, 0.0);
    float t = dist * 1.001 + 1e-4;
    vec3 n;
    vec2 uv;
    if (!hit_shape(int(fetch(u_instances, base + 6).x), fetch(u_instances, base + 7), oo, od,
                   t, n, uv) || t < dist * 0.999 - 1e-4) return false;
    h = Hit(t, inst, -1, vec2(0.0), n, uv);
    dist = t;
    return true;
}

// A point on the emitters for the surface point p: an emitting triangle or shape chosen by
// power (binary search in the cumulative shares), then a point uniformly on it by area.
// Returns the radiance it sends towards p (0 from the back of a one-sided emitter, or
// where the shape hides the point), the direction L and distance to it, and the density
// of L in solid angle.
vec3 sample_emitter(vec3 p, out vec3 L, out float dist, out float pdf) {
    float u = random01();
    int lo = 0, hi = u_emitter_count - 1;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (fetch(u_emitters, mid).z > u) hi = mid; else lo = mid + 1;
    }
    vec4 e = fetch(u_emitters, lo);
    int inst = int(e.x), tri = int(e.y);
    Hit h;
    pdf = 0.0;
    if (tri < 0) {  // an analytic shape
        int base = inst * INSTANCE_TEXELS;
        vec3 p_obj = shape_point(int(fetch(u_instances, base + 6).x),
                                 fetch(u_instances, base + 7));
        if (!shape_hit_at(inst, p_obj, p, h, L, dist)) return vec3(0.0);
    } else {
        vec2 b = random2();
        if (b.x + b.y > 1.0) b = 1.0 - b;
        vec3 p_obj = fetch(u_tris, 3 * tri).xyz + b.x * fetch(u_tris, 3 * tri + 1).xyz
                   + b.y * fetch(u_tris, 3 * tri + 2).xyz;
        vec3 to = apply_rows(inst * INSTANCE_TEXELS + 3, p_obj, 1.0) - p;
        dist = length(to);
        L = to / max(dist, 1e-20);
        h = Hit(dist, inst, tri, b, vec3(0.0), vec2(0.0));
    }
    Surface s = surface_at(h, p, L);
    Material m = material_of(s);
    float cos_l = abs(dot(s.ng, L));
    pdf = cos_l > 0.0 ? m.emit_pdf * dist * dist / cos_l : 0.0;
    bool one_sided = (int(fetch(u_instances, inst * INSTANCE_TEXELS + 6).w)
                      & FLAG_ONE_SIDED) != 0;
    return s.front || !one_sided ? m.emission : vec3(0.0);
}

void main() {
    // The stream of this pixel of the picture (its row counted from the top whichever way
    // the target is drawn: a window refines to the offscreen picture), sample and seed.
    float row = u_flip_y ? gl_FragCoord.y : u_viewport.y - gl_FragCoord.y;
    g_rng = pcg_hash(uint(gl_FragCoord.x) + pcg_hash(uint(row) +
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
    float prev_pdf = 0.0;  // the BSDF's density of d (0: the eye ray, a delta or
                           // transmission lobe: not weighed against light sampling)
    vec3 sigma = vec3(0.0);  // absorption of the volume the ray is in (KHR_materials_volume)
    float eta_scale = 1.0;   // undoes refraction's radiance scale for Russian roulette
    bool light_nee = u_strategy != STRATEGY_BSDF, bsdf_hits = u_strategy != STRATEGY_LIGHT;
#ifdef HAS_ENVIRONMENT
    bool sample_environment = light_nee;
#else
    bool sample_environment = light_nee && any(greaterThan(u_ambient.rgb, vec3(0.0)));
#endif
    int bounce = 0;
    float travelled = 0.0;  // along the path so far: its ray cone's width (surface.glsl)
    for (int step = 0; step < u_max_depth + 2 + MAX_PASSES; ++step) {
        Hit h = trace_scene(o, d, t_max, false);
        g_travelled = travelled;
        travelled += h.t;
        if (sigma != vec3(0.0)) throughput *= exp(-sigma * min(h.t, 1e6));  // Beer-Lambert
        if (h.inst < 0) {
            if (bounce == 0) {
#ifdef HAS_ENVIRONMENT
                radiance = escaped(d);
#else
                radiance = u_background.rgb * u_background.a;
                alpha = u_background.a;
#endif
            } else if (!sample_environment || prev_pdf == 0.0) {
                radiance += throughput * sky_light(d);
            } else if (bsdf_hits) {
                radiance += throughput * sky_light(d) * power_weight(prev_pdf, sky_pdf(d));
            }
            break;
        }
        Surface s = surface_at(h, o, d);
#ifdef HAS_ALPHA
        if (passes(s, random01())) {  // not there for this ray: on, unchanged
            o = offset_ray(s.p, -s.ng);
            t_max -= h.t;
            continue;
        }
#endif
        Material mat = material_of(s);
        // What it emits towards the eye, or towards the last surface that sampled its BSDF.
        bool one_sided = (int(fetch(u_instances, h.inst * INSTANCE_TEXELS + 6).w)
                          & FLAG_ONE_SIDED) != 0;
        if ((s.front || !one_sided) && mat.emission != vec3(0.0)) {
            float w = 1.0;
            if (prev_pdf > 0.0 && mat.emit_pdf > 0.0 && u_emitter_count > 0) {
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
        mat.cc_n = valid_normal(mat.cc_n, s.ng, V);
        Bsdf b = make_bsdf(mat, s.front, N, V);
        vec3 from = offset_ray(s.p, s.ng);
        // Direct light from the scene's lights (delta lights: one shadow ray each).
        for (int i = 0; i < u_light_count.x; ++i) {
            vec3 L;
            float falloff = incident_light(i, s.p, L);
            float dist = LIGHT_KIND(i) == LIGHT_DIRECTIONAL
                       ? INF : length(u_lights[i].position.xyz - s.p);
            if (falloff <= 0.0) continue;
            if (dot(N, L) > 0.0 && dot(s.ng, L) > 0.0) {
                radiance += throughput * visibility(from, L, dist) * falloff
                          * u_lights[i].color.rgb * (PI * bsdf_eval(b, N, V, L));
            } else if (b.thin && !b.polished && dot(s.ng, L) < 0.0) {
                // A thin rough wall passes a light behind it through its transmission lobe
                // (a delta light: no path from the eye finds it otherwise).
                radiance += throughput * visibility(offset_ray(s.p, -s.ng), L, dist) * falloff
                          * u_lights[i].color.rgb * pbr_light_through(
                              b.m, b.c_trans, N, V, L, mat.roughness, max(mat.ior, 1.0));
            }
        }
        // One point on the emitting triangles.
        if (light_nee && u_emitter_count > 0) {
            vec3 L;
            float dist, pdf_light;
            vec3 Le = sample_emitter(s.p, L, dist, pdf_light);
            if (pdf_light > 0.0 && Le != vec3(0.0) && dot(N, L) > 0.0 && dot(s.ng, L) > 0.0) {
                float w = bsdf_hits ? power_weight(pdf_light, bsdf_pdf(b, N, V, L)) : 1.0;
                radiance += throughput * Le * bsdf_eval(b, N, V, L) * (w / pdf_light)
                          * visibility(from, L, dist * (1.0 - 1e-4));
            }
        }
        // One direction of the environment.
        if (sample_environment) {
            float pdf_sky;
            vec3 L = sample_sky(pdf_sky);
            if (pdf_sky > 0.0 && dot(N, L) > 0.0 && dot(s.ng, L) > 0.0) {
                float w = bsdf_hits ? power_weight(pdf_sky, bsdf_pdf(b, N, V, L)) : 1.0;
                radiance += throughput * sky_light(L) * bsdf_eval(b, N, V, L)
                          * (w / pdf_sky) * visibility(from, L, INF);
            }
        }
        // The next direction, from the BSDF.
        float u = random01();
        BsdfSample next = bsdf_sample(b, N, V, u, random2());
        // Absorbed: no direction, or one on the wrong side of the geometric surface.
        if (!next.ok || (next.through ? dot(s.ng, next.L) >= 0.0 : dot(s.ng, next.L) <= 0.0))
            break;
        throughput *= next.weight;
        prev_pdf = next.pdf;  // 0: a delta or transmission lobe, not weighed against lights
        if (next.through) {
            from = offset_ray(s.p, -s.ng);
            if (!b.thin) sigma = s.front ? mat.absorption : vec3(0.0);  // in or out
            else throughput *= thin_absorbed(mat);
            eta_scale *= b.eta * b.eta;
        }
        ++bounce;
        if (bounce > ROULETTE_AFTER) {
            // Paths that carry little go on with that probability (pbrt's rule; through
            // glass by what they carry before the 1 / eta^2 of refraction).
            float survive = clamp(max(throughput.r, max(throughput.g, throughput.b))
                                  * eta_scale, 0.05, 1.0);
            if (survive < 1.0) {
                if (random01() >= survive) break;
                throughput /= survive;
            }
        }
        o = from;
        d = next.L;
        t_max = INF;
    }
    f_color = vec4(radiance, alpha);
}
