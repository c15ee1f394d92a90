// The path tracer's BSDF at a hit (glsl/trace/path.frag): the glTF metallic-roughness
// model of lib/pbr.glsl (the rasterizer's, with its dielectric lobe and multiple-scattering
// scale) plus KHR_materials_transmission and _volume. Its lobes:
//   clear coat    GGX of the coat's roughness, its Fresnel factor (KHR_materials_clearcoat;
//                 the lobes below are dimmed by 1 - clearcoat F_c(N.V))
//   reflection    GGX with Schlick's F (F0 from ior, specular and metal)
//   diffuse       (1 - F_d) (1 - transmission) (1 - metallic) base / pi
//   diffuse transmission  (1 - F_d) dt (1 - transmission) (1 - metallic) dt_color / pi
//                 behind the surface (KHR_materials_diffuse_transmission)
//   transmission  (1 - F_d) transmission (1 - metallic) base, through the surface:
//                 thin-walled (thickness 0): on unbent, mirrored GGX when rough;
//                 a volume: Snell's refraction, GGX microfacet transmission when rough
//                 (Walter et al. 2007), radiance scaled by 1 / eta^2.
// A transmitting dielectric smoother than SMOOTH_ROUGHNESS is perfectly smooth: delta
// reflection and refraction split by the exact dielectric Fresnel factor. Sampling picks
// a lobe by its estimated share, then a direction from it; the reflection side's density
// (GGX and cosine mixture) is what multiple importance sampling weighs against light
// sampling; delta lobes and transmission (which light sampling never reaches through the
// opaque shadow rays) are not weighed.
#include "lib/layers.glsl"
#include "lib/sampling.glsl"

const float SMOOTH_ROUGHNESS = SMOOTH_GLASS;  // trace/material.glsl's

struct Bsdf {
    PbrSurface m;    // the reflection lobes (c_diff without the transmitted share)
    vec3 c_trans;    // what the transmission lobe passes: (1 - metallic) transmission base
    float eta;       // index beyond the surface / index on the ray's side (thin: 1)
    float fresnel;   // smooth: the exact dielectric Fresnel factor at this angle
    bool thin;
    bool polished;  // perfectly smooth (delta lobes)
    float p_spec;    // the lobes' probabilities (diffuse: the rest)
    float p_trans;
    float p_coat;
    float p_dt;      // diffuse transmission (KHR_materials_diffuse_transmission)
};

struct BsdfSample {
    vec3 L;
    vec3 weight;     // f |cos| / pdf
    float pdf;       // the reflection side's mixture density (0 for delta and transmission)
    bool through;    // L leaves on the far side
    bool ok;
};

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The unpolarised Fresnel reflectance of a smooth dielectric interface; eta = n_t / n_i.
float fresnel_dielectric(float cos_i, float eta) {
    float sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0) return 1.0;  // total internal reflection
    float cos_t = sqrt(1.0 - sin2_t);
    float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

Bsdf make_bsdf(Material mat, bool front, vec3 N, vec3 V) {
    Bsdf b;
    b.m = layered_surface(mat, N, mat.cc_n, V, b.c_trans);
    b.thin = mat.thin;
    float ior = max(mat.ior, 1.0);
    b.eta = mat.thin ? 1.0 : (front ? ior : 1.0 / ior);
#ifdef NO_TRANSMISSION
    b.polished = false;  // (delta lobes are glass's)
#else
    b.polished = mat.transmission > 0.0 && mat.metallic <= 0.0 &&
               mat.roughness < SMOOTH_ROUGHNESS;
#endif
    float fc = schlick_weight(b.m.n_dot_v);
    vec3 kept = 1.0 - pbr_fresnel_d(b.m, fc);
    float spec;
    if (b.polished) {
        b.fresnel = (b.thin ? fresnel_dielectric(b.m.n_dot_v, ior)
                            : fresnel_dielectric(b.m.n_dot_v, b.eta)) * mat.f90_d;
        spec = b.fresnel;
        kept = vec3(1.0 - b.fresnel);
    } else {
        b.fresnel = 0.0;
        spec = luminance(pbr_fresnel(b.m, fc));
    }
    // (the sheen lobe is broad: the cosine-weighted one samples it too)
    float diff = luminance(b.m.c_diff * kept) + b.m.sheen_dim,
          trans = luminance(b.c_trans * kept), dt = luminance(b.m.c_dt * kept);
    float rest = diff + trans + dt;
    // The coat's share first (exactly by its weight), the rest below it as before.
    float coat = b.polished ? 0.0 : b.m.cc * b.m.cc_fresnel;
    float under = (spec + rest) * (1.0 - coat);
    b.p_coat = coat <= 0.0 ? 0.0 : coat / (coat + under);
    if (spec <= 0.0) b.p_spec = 0.0;
    else if (rest <= 0.0) b.p_spec = 1.0;
    else if (b.polished) b.p_spec = spec / (spec + rest);  // delta lobes: exactly by weight
    else b.p_spec = clamp(spec / (spec + rest), 0.1, 0.9);
    b.p_trans = rest <= 0.0 ? 0.0 : (1.0 - b.p_spec) * trans / rest;
    b.p_dt = rest <= 0.0 ? 0.0 : (1.0 - b.p_spec) * dt / rest;
    b.p_spec *= 1.0 - b.p_coat;
    b.p_trans *= 1.0 - b.p_coat;
    b.p_dt *= 1.0 - b.p_coat;
    return b;
}

// f cos on the reflection side (delta lobes excluded): what light sampling evaluates.
vec3 bsdf_eval(Bsdf b, vec3 N, vec3 V, vec3 L) {
    if (!b.polished) return pbr_light(b.m, N, V, L) * (1.0 / PI);
    float n_dot_l = max(dot(N, L), 0.0);
    return (1.0 - b.fresnel) * b.m.c_diff * (n_dot_l / PI);
}

// The density of the sampling mixture for L on the reflection side (solid angle).
float bsdf_pdf(Bsdf b, vec3 N, vec3 V, vec3 L) {
    float n_dot_l = dot(N, L);
    if (n_dot_l <= 0.0) return 0.0;
    float p_diff = 1.0 - b.p_spec - b.p_trans - b.p_coat - b.p_dt;
    float pdf = p_diff * n_dot_l / PI;
    if (!b.polished) {
        vec3 H = normalize(L + V);
        float n_dot_h = max(dot(N, H), 0.0), v_dot_h = max(dot(V, H), 1e-6);
        float n_dot_h_c = max(dot(b.m.cc_n, H), 0.0);
        pdf += (b.p_spec * pbr_ndf(b.m, N, H) * n_dot_h
                + b.p_coat * ggx_d(n_dot_h_c, b.m.cc_alpha) * n_dot_h_c) / (4.0 * v_dot_h);
    }
    return pdf;
}

// One direction from the BSDF by one 2D sample xi: its x chooses the lobe and, rescaled
// within the lobe's share, is the direction's first coordinate with y (so a pixel's
// stratified samples stay stratified within each lobe). (The reflection side's lobes
// share one evaluation and one density at the end: each call site is the whole layered
// model inlined, which llvmpipe runs whichever lobe a lane took.)
BsdfSample bsdf_sample(Bsdf b, vec3 N, vec3 V, vec2 xi) {
    BsdfSample s = BsdfSample(vec3(0.0), vec3(0.0), 0.0, false, false);
    float u = xi.x - b.p_coat;
    // the lobe's share of [0, 1): [lo, lo + share) in u
    float lo = -b.p_coat, share = b.p_coat;
    if (u >= 0.0) { lo = 0.0; share = b.p_spec; }
    if (u >= b.p_spec) { lo = b.p_spec; share = b.p_trans; }
    if (u >= b.p_spec + b.p_trans) { lo += b.p_trans; share = b.p_dt; }
    if (u >= b.p_spec + b.p_trans + b.p_dt) { lo += b.p_dt; share = 1.0 - b.p_coat - lo; }
    xi.x = clamp((u - lo) / max(share, 1e-30), 0.0, 0.99999994);
    if (u < 0.0) {  // the clear coat
        s.L = reflect(-V, around(ggx_sample(xi, b.m.cc_alpha), b.m.cc_n));
    } else if (u < b.p_spec) {  // reflection
        if (b.polished) {
            s.L = reflect(-V, N);
            s.weight = vec3(b.fresnel / b.p_spec);
            s.ok = true;
            return s;
        }
#ifndef NO_ANISOTROPY
        if (b.m.aniso > 0.0) {  // slopes of the alpha-1 lobe stretched by (alpha_t, alpha)
            vec3 h = ggx_sample(xi, 1.0), T = b.m.aniso_t;
            h = normalize(vec3(b.m.alpha_t * h.x, b.m.alpha * h.y, h.z));
            s.L = reflect(-V, h.x * T + h.y * cross(N, T) + h.z * N);
        } else
#endif
        s.L = reflect(-V, around(ggx_sample(xi, b.m.alpha), N));
    }
#ifndef NO_TRANSMISSION
    else if (u < b.p_spec + b.p_trans) {  // transmission
        s.through = true;
        float n_dot_v = b.m.n_dot_v;
        if (b.polished) {
            s.L = b.thin ? -V : refract(-V, N, 1.0 / b.eta);
            if (dot(s.L, s.L) == 0.0) return s;  // total internal reflection: F was 1
            s.weight = (1.0 - b.fresnel) * b.c_trans / (b.p_trans * b.eta * b.eta);
            s.ok = true;
            return s;
        }
        vec3 H = around(ggx_sample(xi, b.m.alpha), N);
        float v_dot_h = dot(V, H), n_dot_h = dot(N, H);
        if (v_dot_h <= 0.0) return s;
        if (b.thin) {
            vec3 R = reflect(-V, H);
            s.L = R - 2.0 * dot(R, N) * N;  // mirrored through the surface: on unbent
        } else {
            s.L = refract(-V, H, 1.0 / b.eta);
            if (dot(s.L, s.L) == 0.0) return s;  // total internal reflection
        }
        float n_dot_l = -dot(N, s.L);
        if (n_dot_l <= 0.0) return s;
        float fc = schlick_weight(v_dot_h);
        vec3 F_d = b.m.f0_d + (b.m.f90_d - b.m.f0_d) * fc;
        // f |cos| / pdf of GGX transmission: |V.H| (1 - F) G2 / (|N.V| N.H), the same
        // form as reflection's; G2 = 4 Vis |N.L| |N.V|.
        float g = 4.0 * smith_vis(n_dot_l, n_dot_v, b.m.alpha) * n_dot_l * n_dot_v;
        s.weight = (1.0 - F_d) * b.c_trans * (v_dot_h * g / (n_dot_v * n_dot_h))
                 / (b.p_trans * b.eta * b.eta);
        s.ok = true;
        return s;
    }
#endif
#ifndef NO_DIFFUSE_TRANSMISSION
    else if (u < b.p_spec + b.p_trans + b.p_dt) {  // diffuse transmission: cosine, behind
        s.L = around(cosine_sample(xi), -N);
        s.through = true;
        s.weight = (1.0 - pbr_fresnel_d(b.m, schlick_weight(b.m.n_dot_v))) * b.m.c_dt / b.p_dt;
        s.ok = true;
        return s;
    }
#endif
    else {  // diffuse
        s.L = around(cosine_sample(xi), N);
    }
    s.pdf = bsdf_pdf(b, N, V, s.L);
    if (s.pdf <= 0.0) return s;
    s.weight = bsdf_eval(b, N, V, s.L) / s.pdf;
    s.ok = true;
    return s;
}
