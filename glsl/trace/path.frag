#version 330 core
#ifdef SCENE_IMAGES  // (glsl/trace/data.glsl)
#extension GL_ARB_shader_image_load_store : require
#extension GL_ARB_shading_language_420pack : require
#endif
// The path tracer: one path per fragment and supersample, added to the accumulation
// (facet.render.path.engine), on the ray tracer's hierarchy (trace/scene.glsl).
// Unidirectional. At each hit the material (trace/material.glsl: glTF metallic-roughness
// with its texture slots) adds what it emits and the direct light of
//   - the scene's point, spot and directional lights (delta lights: a shadow ray each),
//   - the emitting triangles (one point, chosen by power, then uniformly by area),
//   - the environment, or the scene's ambient light as a constant one (one direction: by
//     the environment image's luminance, or for a constant sky by the cosine about the
//     surface's geometric normal),
// then the path goes on in a direction drawn from the BSDF (lib/pbr.glsl, the rasterizer's:
// a mixture of cosine-weighted diffuse and GGX half-vector sampling). Light sampling and
// BSDF sampling both find emitters and the environment; each is weighted by the power
// heuristic (Veach's multiple importance sampling, beta = 2), or u_strategy keeps only
// one of them (for tests). Cut-outs (alpha MASK) and BLEND surfaces (with probability
// 1 - alpha) let the ray by; shadow rays pass cut-outs and take 1 - alpha of each BLEND
// surface. Russian roulette after the fifth bounce (paths carrying less than 1 survive
// with that probability); u_max_depth bounces after the eye ray
// at most (the last only gathers what it hits). Colour is linear radiance. The sky is
// trace/sky.glsl's, light sampling trace/light_sampling.glsl's (direct_light).
#include "trace/shade.glsl"
#include "trace/material.glsl"
#include "trace/bsdf.glsl"
#include "trace/sky.glsl"
#include "trace/light_sampling.glsl"

#ifndef MOSAIC
#error MOSAIC: how many samples one draw may stack (facet.render.path.engine)
#endif
// Window NDC -> world of up to MOSAIC samples drawn at once, one above the other (a small
// picture fills more of the rasterizer's tiles: facet.render.sequence), each with its
// camera and shift; one sample is a mosaic of one.
uniform mat4 u_inv_view_projections[MOSAIC];
uniform int u_count;         // samples in this draw (at most MOSAIC)
uniform int u_per_fragment;  // samples each fragment runs, one after the other
uniform vec2 u_viewport;
uniform vec4 u_background;  // straight RGB (linear) and alpha, for eye rays that escape
uniform int u_max_depth;    // bounces after the eye ray
uniform int u_sample;       // this supersample's index: with the pixel, the random stream
uniform int u_seed;
uniform bool u_flip_y;      // offscreen targets are drawn upside down (facet.gl.targets)
uniform bool u_own_positions;  // each path's position in its pixel by sample2 (else the
                               // centre, or the shift in the sample's camera)
uniform int u_strategy;     // STRATEGY_*
#ifdef ADAPTIVE
uniform sampler2D u_active;  // 0 where the pixel has stopped (facet.render.budget)
#endif
out vec4 f_color;  // premultiplied colour and coverage of this sample

const int STRATEGY_MIS = 0, STRATEGY_LIGHT = 1, STRATEGY_BSDF = 2;
const int ROULETTE_AFTER = 5;  // bounces before Russian roulette may end a path (Mitsuba's)

// A traced segment: its length added to the path's, the volume's absorption over it
// (Beer-Lambert); true when it hit something.
bool segment(Hit h, vec3 sigma, inout float travelled, inout vec3 throughput) {
    travelled += h.t;
    if (sigma != vec3(0.0)) throughput *= exp(-sigma * min(h.t, 1e6));
    return h.inst >= 0;
}

// A ray that escaped along d: the background behind the eye ray, else the sky's light
// (weighed against sampling the sky where the last bounce was weighed).
void escape(inout vec3 radiance, inout float alpha, int bounce, vec3 d, vec3 throughput,
            float prev_pdf, vec3 prev_ng, bool sample_environment, bool bsdf_hits) {
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
        radiance += throughput * sky_light(d) * power_weight(prev_pdf, sky_pdf(prev_ng, d));
    }
}

void main() {
    vec2 frag = gl_FragCoord.xy;  // in the picture
    int part = int(frag.y / u_viewport.y);
    frag.y -= float(part) * u_viewport.y;
#ifdef ADAPTIVE
    if (texelFetch(u_active, ivec2(frag), 0).r == 0.0) discard;  // (adds 0)
#endif
    // This fragment's samples: [first, last) of the draw's u_count, each a path of its own
    // (camera and shift u_inv_view_projections[j], random stream of sample u_sample + j).
    // One loop runs them all, a new path starting in a lane where the last one ended: the
    // SIMD lanes llvmpipe runs together (8 fragments) stay busy until the longest sum of
    // paths ends, not each sample's longest path.
    int first = part * u_per_fragment, last = min(first + u_per_fragment, u_count);
    // The stream of this pixel of the picture (its row counted from the top whichever way
    // the target is drawn: a window refines to the offscreen picture), sample and seed.
    float row = u_flip_y ? frag.y : u_viewport.y - frag.y;
    vec2 ndc = frag / u_viewport * 2.0 - 1.0;
    bool light_nee = u_strategy != STRATEGY_BSDF, bsdf_hits = u_strategy != STRATEGY_LIGHT;
#ifdef HAS_ENVIRONMENT
    bool sample_environment = light_nee;
#else
    bool sample_environment = light_nee && any(greaterThan(u_ambient.rgb, vec3(0.0)));
#endif
    g_pixel = pcg_hash(uint(frag.x) + pcg_hash(uint(row) + pcg_hash(uint(u_seed))));
    vec4 total = vec4(0.0);  // premultiplied colour and coverage of the samples
    // One path's state.
    vec3 o, d, radiance, throughput;
    float t_max, alpha;
    float prev_pdf;    // the BSDF's density of d (0: the eye ray, a delta or transmission
                       // lobe: not weighed against light sampling)
    vec3 prev_ng;      // the geometric normal of the surface d left (sky_pdf)
    vec3 sigma;        // absorption of the volume the ray is in (KHR_materials_volume)
    float eta_scale;   // undoes refraction's radiance scale for Russian roulette
    int bounce, step;
    int channel;       // the colour a dispersive refraction chose (-1: none yet)
    float travelled;   // along the path so far: its ray cone's width (surface.glsl)
    int j = first - 1;
    bool fresh = true, done = false;
    do {
        // Rays until this lane's hits something: an escaping ray ends its path (its sky
        // or background) and the next sample's eye ray is traced in the same turn, so a
        // turn's shading below (which llvmpipe runs for all 8 lanes of a SIMD group, a lane
        // using it or not) is paid for hits alone: a path under a sky ended with a turn
        // that shaded nothing, and an eye ray that missed cost a turn of its own. One call
        // site of trace_scene (each inlines a whole traversal).
        Hit h;
        bool going;
        do {
            if (fresh) {  // the next sample's eye ray
                ++j;
                g_rng = pcg_hash(uint(frag.x) + pcg_hash(uint(row) +
                                 pcg_hash(uint(u_sample + j) + pcg_hash(uint(u_seed)))));
                g_index = uint(u_sample + j);
                g_bounce = 0;
                vec2 at = ndc;
                if (u_own_positions) {  // (its offset from the picture's top left)
                    vec2 xi = sample2(QMC_PIXEL);
                    at = (floor(frag) + vec2(xi.x, u_flip_y ? xi.y : 1.0 - xi.y)) / u_viewport
                       * 2.0 - 1.0;
                }
                mat4 inv_view_projection = u_inv_view_projections[j];
                vec4 near = inv_view_projection * vec4(at, -1.0, 1.0);
                vec4 far = inv_view_projection * vec4(at, 1.0, 1.0);
                o = near.xyz / near.w;
                vec3 span = far.xyz / far.w - o;
                d = normalize(span);
                t_max = length(span);  // the eye ray stops at the far plane, as rasterized
                radiance = vec3(0.0);
                throughput = vec3(1.0);
                alpha = 1.0;
                prev_pdf = 0.0;
                prev_ng = vec3(0.0);
                sigma = vec3(0.0);
                eta_scale = 1.0;
                bounce = 0;
                step = 0;
                channel = -1;
                travelled = 0.0;
                fresh = false;
            }
            g_camera_ray = bounce == 0;  // (past cut-outs, the eye ray goes on)
            h = trace_scene(o, d, t_max, false);
            g_camera_ray = false;
            going = segment(h, sigma, travelled, throughput);
            if (!going) {
                escape(radiance, alpha, bounce, d, throughput, prev_pdf, prev_ng,
                       sample_environment, bsdf_hits);
                total += vec4(radiance, alpha);
                fresh = true;
                done = j + 1 >= last;
            }
        } while (!going && !done);
        if (!going) break;  // (every sample of this fragment is done)
        {
            g_travelled = travelled - h.t;
            Surface s = surface_at(h, o, d);
#ifdef HAS_ALPHA
            if (passes(s, random01())) {  // not there for this ray: on, unchanged
                o = offset_ray(s.p, -s.ng);
                t_max -= h.t;
            } else
#endif
            {
                Material mat = material_of(s);
                // What it emits towards the eye, or towards the last surface that sampled
                // its BSDF.
                bool one_sided = (int(instance_texel(h.inst * INSTANCE_TEXELS + 6).w)
                                  & FLAG_ONE_SIDED) != 0;
                // A one-sided surface's back: opaque, black; but a transmitting material's
                // back is where light leaves the volume it bounds (glTF's glass is
                // single-sided): paths go on through it.
                going = s.front || !one_sided ||
                        mat.transmission * (1.0 - mat.metallic) > 0.0;
                if (going && mat.emission != vec3(0.0)) {
                    float w = 1.0;
#ifndef NO_EMITTERS
                    if (prev_pdf > 0.0 && mat.emit_pdf > 0.0 && u_emitter_count > 0) {
                        float pdf_light = emitter_pdf(h.inst, mat.emit_pdf, o, d, h.t, s.ng);
                        w = !light_nee ? 1.0 : bsdf_hits ? power_weight(prev_pdf, pdf_light)
                                                         : 0.0;
                    }
#endif
                    radiance += throughput * mat.emission * w;
                }
                if (going && mat.unlit) {  // KHR_materials_unlit: its colour, no reflection
                    radiance += throughput * mat.base;
                    going = false;
                }
                going = going && bounce <= u_max_depth;  // else it only gathered its hit
                vec3 V = -d, N = valid_normal(mat.n, s.ng, V);
#ifndef NO_CLEARCOAT
                mat.cc_n = valid_normal(mat.cc_n, s.ng, V);
#endif
#ifndef NO_DISPERSION
                // KHR_materials_dispersion: a path through a dispersive volume follows one
                // colour (chosen at the first, 1 in 3, its throughput that channel's 3x),
                // refracting at that colour's index.
                if (mat.dispersion_spread > 0.0 && mat.transmission > 0.0) {
                    if (channel < 0) {
                        channel = min(int(random01() * 3.0), 2);
                        throughput *= 3.0 * vec3(equal(ivec3(channel), ivec3(0, 1, 2)));
                    }
                    mat.ior += mat.dispersion_spread * float(channel - 1);
                }
#endif
                Bsdf b = make_bsdf(mat, s.front, N, V);
                g_bounce = bounce;  // sample2's dimensions
                if (going)
                    radiance += throughput * direct_light(s, mat, b, N, V, light_nee,
                                                          sample_environment, bsdf_hits);
                // The next direction, from the BSDF.
                BsdfSample next = bsdf_sample(b, N, V, sample2(QMC_BSDF));
                // Absorbed: no direction, or one on the wrong side of the geometric
                // surface.
                going = going && next.ok && (next.through ? dot(s.ng, next.L) < 0.0
                                                          : dot(s.ng, next.L) > 0.0);
                if (going) {
                    throughput *= next.weight;
                    prev_pdf = next.pdf;  // 0: a delta or transmission lobe (not weighed)
                    prev_ng = s.ng;
                    if (next.through) {
                        // in or out of a volume
                        if (!b.thin) sigma = s.front ? mat.absorption : vec3(0.0);
                        else throughput *= thin_absorbed(mat);
                        eta_scale *= b.eta * b.eta;
                    }
                    ++bounce;
                    if (bounce > ROULETTE_AFTER) {
                        // Paths that carry little go on with that probability (pbrt's
                        // rule; through glass by what they carry before the 1 / eta^2 of
                        // refraction).
                        float survive = clamp(max(throughput.r, max(throughput.g,
                                                                    throughput.b))
                                              * eta_scale, 0.05, 1.0);
                        if (survive < 1.0) {
                            going = random01() < survive;
                            throughput /= survive;
                        }
                    }
                    o = offset_ray(s.p, next.through ? -s.ng : s.ng);
                    d = next.L;
                    t_max = INF;
                }
            }
        }
        if (!going || ++step >= u_max_depth + 2 + MAX_PASSES) {
            total += vec4(radiance, alpha);
            fresh = true;
            done = j + 1 >= last;
        }
    } while (!done);
    f_color = total;
}
