#version 330 core
#ifdef SCENE_IMAGES  // (glsl/trace/data.glsl)
#extension GL_ARB_shader_image_load_store : require
#extension GL_ARB_shading_language_420pack : require
#endif
// The ray tracer (notes §2.6-2.11): one supersample of one pixel per fragment, added to the
// accumulation (facet.render.trace.engine). The eye ray goes through this sample's point of the
// pixel (and lens, and shutter time: the camera and instances of this sample); at each hit
// the surface is shaded by the rasterizer's equation with shadow rays, and spawns up to
// three rays: reflection (reflectivity; with ior > 0 split with refraction by Schlick's
// Fresnel, total internal reflection sending all to reflection), and straight on through
// what is not opaque. Rays are kept on a small stack, each with the weight it carries;
// reflection and refraction go at most u_max_depth bounces deep, where an unfinished ray
// takes the environment's colour (black without one). A glTF material's transmission
// (KHR_materials_transmission, _volume) is a refraction ray (Snell's law at its ior; on
// unbent when thin-walled) carrying what the dielectric's Fresnel factor lets through,
// tinted by the base colour, tilted by the roughness across supersamples, and absorbed by
// Beer-Lambert on its way out of the volume.
#include "trace/shade.glsl"
#include "lib/gloss.glsl"

uniform mat4 u_inv_view_projection;  // window NDC -> world, this sample's camera and shift
uniform vec2 u_viewport;
uniform vec4 u_background;  // straight RGB (linear) and alpha, for eye rays that escape
uniform int u_max_depth;
uniform vec2 u_gloss_jitter;  // this sample's tilt of glossy reflection and transmission
#if defined(SKY_CONSTANT)
uniform vec3 u_sky_color;  // an environment of one colour (facet.render.rays.scene)
#elif defined(HAS_ENVIRONMENT)
uniform samplerCube u_environment;
#endif
out vec4 f_color;  // premultiplied colour and coverage of this sample

const int RAY_STACK = 12;
const int MAX_SEGMENTS = 32;        // bounds the work per sample
const float MIN_WEIGHT = 1.0 / 1024.0;  // rays that would change nothing are not traced

vec3 escaped(vec3 d) {
#if defined(SKY_CONSTANT)
    return u_sky_color;
#elif defined(HAS_ENVIRONMENT)
    return texture(u_environment, d).rgb;
#else
    return u_background.rgb;
#endif
}

vec3 tilt(vec3 r, float gloss) {  // the rasterizer's glossy tilt
    return gloss_tilt(r, gloss, u_gloss_jitter);
}

// The ray stack (SECONDARY): origin, direction (w: 1 for the eye ray and what passes
// straight through it, which decide coverage; 2 a reflection of the scene in a glTF
// material, whose sky is the ambient light; 0 the rest), weight (w: bounces so far), and
// the segment's end.
vec4 ray_o[RAY_STACK], ray_d[RAY_STACK], ray_w[RAY_STACK];
float ray_end[RAY_STACK];
int sp = 0;
float g_hit_t = 0.0;  // the segment being shaded's length (its rays start that much further)

void push(vec3 o, vec3 d, float kind, vec3 w, int depth, float end) {
    if (sp >= RAY_STACK || max(w.r, max(w.g, w.b)) <= MIN_WEIGHT) return;
    ray_o[sp] = vec4(o, g_travelled + g_hit_t);  // w: how far the ray came (its cone)
    ray_d[sp] = vec4(d, kind);
    ray_w[sp] = vec4(w, float(depth));
    ray_end[sp++] = end;
}

#ifdef PBR_SLOTS
// The GGX lobe's directional albedo with multiple scattering kept (lib/pbr.glsl's scale).
vec3 lobe_albedo(float n_dot_v, float roughness, vec3 f0) {
    float e = ggx_albedo(n_dot_v, roughness);
    return e + f0 * (1.0 - e);
}

// The scene reflected in a glossy lobe about N: a ray carrying ``albedo`` (the lobe's
// reflectance, weighted), tilted by the roughness across supersamples. It takes over from
// the ambient split sum's part as the roughness falls from TRACED_ROUGHNESS to half of it;
// returns how much it took over (0: none traced).
float push_reflection(Surface s, vec3 d, vec3 N, float roughness, vec3 albedo, int depth) {
    float traced = clamp(2.0 - 2.0 * roughness / TRACED_ROUGHNESS, 0.0, 1.0);
    vec3 w = albedo * traced;
    if (traced <= 0.0 || sp >= RAY_STACK || max(w.r, max(w.g, w.b)) <= MIN_WEIGHT) return 0.0;
    push(offset_ray(s.p, s.ng), gloss_tilt(reflect(d, N), roughness * roughness,
                                          u_gloss_jitter), 2.0, w, depth + 1, INF);
    return traced;
}

// KHR_materials_transmission: a refraction ray (Snell's law at the ior; on unbent when
// thin-walled) carrying what the dielectric's Fresnel factor lets through, tinted by the
// base colour and absorbed on the way out of a volume (w: the ray that arrived, after t).
// Past the critical angle the same share turns back inside, no more: its Fresnel part is
// already the reflection ray's (counting both as all of it added light at every internal
// bounce: glass rims went white).
void push_transmission(Surface s, vec3 d, float t, Material mat, inout vec3 w, int depth) {
    float trans = mat.transmission * (1.0 - mat.metallic);
    if (trans <= 0.0) return;
    // Leaving a volume through its far side: what it absorbed over the t it crossed.
    if (!s.front && !mat.thin) w *= exp(-mat.absorption * t);
    vec3 crossed = mat.thin ? thin_absorbed(mat) : vec3(1.0);
    float eta = mat.thin ? 1.0 : (s.front ? 1.0 / max(mat.ior, 1.0) : max(mat.ior, 1.0));
    vec3 t_dir = mat.thin ? d : refract(d, s.n, eta);
    float cos_v = clamp(-dot(d, s.n), 0.0, 1.0);
    vec3 f_d = mat.f0_d + (mat.f90_d - mat.f0_d) * pow(1.0 - cos_v, 5.0);
    vec3 passed = w * trans * mat.base * (1.0 - f_d) * crossed;
    bool inward = dot(t_dir, t_dir) > 0.0;
    if (!inward) t_dir = reflect(d, s.n);  // total internal reflection
    if (depth < u_max_depth)
        push(offset_ray(s.p, inward ? -s.ng : s.ng), gloss_tilt(
            normalize(t_dir), mat.roughness * mat.roughness, u_gloss_jitter), 0.0, passed,
            depth + 1, INF);
}
#endif

// A one-sided surface's back is black (its back emits and reflects nothing), except a
// transmitting material's: there refraction rays leave the volume it bounds (glTF's glass
// is single-sided; its far side, seen from inside, is where light comes out).
bool passes_back(Surface s) {
#ifdef PBR_SHADING
    if (own_pbr(s)) {
        Material m = material_of(s);
        return m.transmission * (1.0 - m.metallic) > 0.0;
    }
#endif
    return false;
}

void main() {
    vec2 ndc = gl_FragCoord.xy / u_viewport * 2.0 - 1.0;
    vec4 near = u_inv_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far = u_inv_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 o0 = near.xyz / near.w;
    vec3 span = far.xyz / far.w - o0;
#ifndef SECONDARY
    // No material reflects or lets light through (facet compiles this variant for such
    // scenes): the eye ray alone, without the stack.
    vec3 d0 = normalize(span);
    g_camera_ray = true;
    Hit h0 = trace_scene(o0, d0, length(span), false);
    g_camera_ray = false;
    if (h0.inst < 0) {
#ifdef HAS_ENVIRONMENT
        f_color = vec4(escaped(d0), 1.0);
#else
        f_color = vec4(u_background.rgb * u_background.a, u_background.a);
#endif
    } else {
        f_color = vec4(shade_surface(surface_at(h0, o0, d0), -d0, 1.0), 1.0);
    }
#else
    push(o0, normalize(span), 1.0, vec3(1.0), 0, length(span));  // ends at the far plane
    vec3 color = vec3(0.0);
    float alpha = 0.0;
    for (int segment = 0; segment < MAX_SEGMENTS && sp > 0; ++segment) {
        --sp;
        vec3 o = ray_o[sp].xyz, d = ray_d[sp].xyz, w = ray_w[sp].xyz;
        float kind = ray_d[sp].w;  // 1: the eye ray (or on through it), 2: a reflection
        bool eye = kind == 1.0;    // of the scene in a glTF material, 0: the rest
        int depth = int(ray_w[sp].w);
        float end = ray_end[sp];
        g_travelled = ray_o[sp].w;
        g_camera_ray = eye;
        Hit h = trace_scene(o, d, end, false);
        g_camera_ray = false;
        g_hit_t = h.t;
        if (h.inst < 0) {
            if (eye) {
#ifdef HAS_ENVIRONMENT
                color += w * escaped(d);
                alpha += w.x;
#else
                color += w * u_background.rgb * u_background.a;
                alpha += w.x * u_background.a;
#endif
            } else {
#ifndef HAS_ENVIRONMENT
                // A glTF material's sky is the ambient light (glsl/trace/shade.glsl).
                if (kind == 2.0) { color += w * u_ambient.rgb; continue; }
#endif
                color += w * escaped(d);
            }
            continue;
        }
        Surface s = surface_at(h, o, d);
        if (!s.front && (int(instance_texel(h.inst * INSTANCE_TEXELS + 6).w)
                         & FLAG_ONE_SIDED) != 0 && !passes_back(s))
            continue;  // a one-sided back: black (passes_back)
#ifdef PBR_SLOTS
        if (cut_out(s)) {  // a cut-out (alpha MASK): on through, unchanged
            push(offset_ray(s.p, -s.ng), d, kind, w, depth, eye ? end - h.t : INF);
            continue;
        }
#endif
        float opacity = s.fx.x, reflectivity = s.fx.y, ior = s.fx.z, gloss = s.fx.w;
#ifdef PBR_SHADING
        g_traced_specular = g_traced_coat = 0.0;
        if (own_pbr(s)) {
            Material mat = material_of(s);
            // BLEND: covered by the factor x texture x vertex alpha here, not the factor's.
            if (mat.alpha_mode == ALPHA_MODE_BLEND) opacity = mat.alpha;
            if (!mat.unlit && depth < u_max_depth) {
                vec3 N = valid_normal(mat.n, s.ng, -d);
                float n_dot_v = max(dot(N, -d), 1e-4);
                vec3 f0 = mix(mat.f0_d, mat.base, mat.metallic);
                vec3 F = (f0 + (mix(mat.f90_d, 1.0, mat.metallic) - f0)
                          * schlick_weight(n_dot_v));
#ifndef NO_IRIDESCENCE
                if (mat.iridescence > 0.0)  // (a thin film's F: lib/pbr.glsl pbr_iridescence)
                    F = mix(F, mix(thin_film_fresnel(1.0, mat.iridescence_ior, n_dot_v,
                                                     mat.iridescence_thickness, mat.f0_d),
                                   thin_film_fresnel(1.0, mat.iridescence_ior, n_dot_v,
                                                     mat.iridescence_thickness, mat.base),
                                   mat.metallic), mat.iridescence);
#endif
                vec3 spec = F * lobe_albedo(n_dot_v, mat.roughness, f0);
                vec3 N_c = valid_normal(mat.cc_n, s.ng, -d);
                float cc_v = clamp(dot(N_c, -d), 1e-4, 1.0);
                    float f_c = mat.clearcoat * (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0)
                                             * schlick_weight(cc_v));
                // The coat above dims what lies under it (lib/layers.glsl's order); its
                // own reflection shows its normal map in what the scene reflects.
                g_traced_specular = push_reflection(s, d, N, mat.roughness, w * opacity
                                                    * (1.0 - f_c) * spec, depth);
                g_traced_coat = push_reflection(s, d, N_c, mat.clearcoat_roughness,
                                                w * opacity * f_c * ggx_albedo(
                                                    cc_v, mat.clearcoat_roughness), depth);
            }
            push_transmission(s, d, h.t, mat, w, depth);
        }
#endif
        color += w * opacity * shade_surface(s, -d, 1.0 - reflectivity);
        if (eye) alpha += w.x * opacity;
        vec3 carried = w * opacity * reflectivity;
        if (reflectivity > 0.0 && max(carried.r, max(carried.g, carried.b)) > MIN_WEIGHT) {
            vec3 r = tilt(reflect(d, s.n), gloss);
            float fresnel = 1.0;
            vec3 t_dir = vec3(0.0);
            if (ior > 0.0) {
                float eta = s.front ? 1.0 / ior : ior;
                t_dir = refract(d, s.n, eta);
                float f0 = pow((ior - 1.0) / (ior + 1.0), 2.0);
                // Schlick with the angle on the less dense side (continuous at total
                // internal reflection, where refract() gives 0 and all is reflected).
                float cos_i = s.front ? -dot(d, s.n) : dot(t_dir, -s.n);
                fresnel = dot(t_dir, t_dir) == 0.0 ? 1.0
                        : f0 + (1.0 - f0) * pow(1.0 - clamp(cos_i, 0.0, 1.0), 5.0);
            }
            if (depth >= u_max_depth) {
                color += carried * escaped(r);  // the recursion ends here
            } else {
                if (fresnel < 1.0)
                    push(offset_ray(s.p, -s.ng), tilt(normalize(t_dir), gloss), 0.0,
                         carried * (1.0 - fresnel), depth + 1, INF);
                push(offset_ray(s.p, s.ng), r, 0.0, carried * fresnel, depth + 1, INF);
            }
        }
        if (opacity < 1.0)
            push(offset_ray(s.p, -s.ng), d, kind, w * (1.0 - opacity), depth,
                 eye ? end - h.t : INF);
    }
    f_color = vec4(color, alpha);
#endif
}
