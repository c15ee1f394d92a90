// glTF 2.0's metallic-roughness BRDF (the specification's Appendix B), pure functions.
// World space; all colours linear. alpha = roughness^2.
//   f = mix(f_dielectric, f_metal, metallic)
//   f_dielectric = F_d f_specular + (1 - F_d) f_diffuse,  f_diffuse = base / pi
//   f_metal = F(base, 1) f_specular,   F(f0, f90) = f0 + (f90 - f0) (1 - |V.H|)^5
//   f_specular = D(alpha) Vis(alpha): GGX / Trowbridge-Reitz and height-correlated Smith.
// F_d = F(f0_d, specular): KHR_materials_ior and _specular (facet.scene.pbr.PbrMaterial
// .dielectric_f0; 0.04 and 1 without them, glTF's core model; specular 0: Lambert).
// KHR_materials_sheen (pbr_sheen): f = f min(1 - c E_s(N.V), 1 - c E_s(N.L)) + sheen D_c V_c,
// c = max(sheen colour): the Charlie distribution, Estevez and Kulla's shadowing, E_s its
// albedo (lib/sheen_albedo.glsl), under the coat.
// KHR_materials_diffuse_transmission (layers.glsl): c_dt = the diffuse part's share dt of
// colour dt_color through the surface, c_diff keeping 1 - dt; a light behind adds
// (1 - F_d) c_dt |N.L|.
// KHR_materials_anisotropy (pbr_anisotropy): the lobe's D and Vis stretched along a
// tangent direction (pbr_specular); the environment read about a bent normal.
// KHR_materials_iridescence (pbr_iridescence): F = mix(F, F_film, iridescence) and F_d
// alike, F_film the thin film's (lib/iridescence.glsl) at N.V over the dielectric's F0 and
// over the metal's, mixed by metallic (the Khronos Sample Viewer's evaluation).
// KHR_materials_clearcoat (pbr_coat): f = (1 - c F_c(N_c.V)) f + c F_c(V.H) f_specular(alpha_c),
// F_c with f0 = 0.04, on the coat's own normal N_c (its normal map's, else the surface's).
// facet's lights of intensity I give irradiance pi I (facet.scene.pbr), so a light adds
// pi f I (N.L); the pi cancels f_diffuse's.

// The lobe is scaled by 1 + F0 (1 - E) / E, E its directional albedo with F = 1
// (lib/ggx_albedo.glsl, facet.render.energy): light that bounces between microfacets,
// which the single-bounce model loses (a rough white metal then reflects all it receives).

#include "lib/constants.glsl"
#include "lib/ggx_albedo.glsl"
#include "lib/sheen_albedo.glsl"
#include "lib/iridescence.glsl"
const float DIELECTRIC_F0 = 0.04;  // ior 1.5
const float MIN_ALPHA = 1e-3;  // keeps D finite for a perfect mirror

float ggx_d(float n_dot_h, float alpha) {
    float a2 = alpha * alpha;
    float k = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * k * k);
}

// Vis = G / (4 |N.L| |N.V|), height-correlated Smith for GGX.
float smith_vis(float n_dot_l, float n_dot_v, float alpha) {
    float a2 = alpha * alpha;
    float gv = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    float gl = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    float g = gv + gl;
    return g > 0.0 ? 0.5 / g : 0.0;
}

float schlick_weight(float v_dot_h) {
    float m = clamp(1.0 - v_dot_h, 0.0, 1.0);
    float m2 = m * m;
    return m2 * m2 * m;
}

// What the BRDF needs of a surface point, computed once for all its lights. Both
// Fresnel terms fold into one: (1 - metallic) F(0.04) + metallic F(base) = F(f0) with
// f0 = mix(0.04, base, metallic); the diffuse part keeps (1 - metallic) (1 - F(0.04)).
struct PbrSurface {
    vec3 c_diff;    // (1 - metallic) base
    vec3 f0;        // reflectance at normal incidence, dielectric and metal mixed
    float f90;      // at grazing incidence
    vec3 f0_d;      // the dielectric's alone, and at grazing: its diffuse part is what
    float f90_d;    // its Fresnel leaves, (1 - F_d)
    float alpha;    // roughness^2
    float n_dot_v;
    vec3 ms;        // the lobe's multiple-scattering scale, 1 + f0 (1 - E) / E
    float cc;       // clearcoat: its factor, roughness^2, the Fresnel factor at N_c.V,
    float cc_alpha; // its normal N_c and N_c.V
    float cc_fresnel;
    vec3 cc_n;
    float cc_n_dot_v;
    vec3 sheen;     // sheen colour (0: none), its roughness, and max(colour) E_s(N.V)
    float sheen_roughness;
    float sheen_dim;
    float irid;     // iridescence: its share of F, the film's F and the dielectric's alone
    vec3 irid_f;
    vec3 irid_fd;
    float aniso;    // anisotropy: its strength, alpha along the stretch direction T and T
    float alpha_t;  // (B = N x T, alpha along it: alpha)
    vec3 aniso_t;
    vec3 c_dt;      // diffuse transmission: the Lambertian lobe through the surface
};

// E: the GGX lobe's directional albedo (F = 1), bilinear in the table.
float ggx_albedo(float n_dot_v, float roughness) {
    vec2 c = vec2(sqrt(clamp(n_dot_v, 0.0, 1.0)), clamp(roughness, 0.0, 1.0))
           * float(GGX_ALBEDO_SIZE - 1);
    ivec2 i = min(ivec2(c), ivec2(GGX_ALBEDO_SIZE - 2));
    vec2 f = c - vec2(i);
    int k = i.y * GGX_ALBEDO_SIZE + i.x;
    return mix(mix(GGX_ALBEDO[k], GGX_ALBEDO[k + 1], f.x),
               mix(GGX_ALBEDO[k + GGX_ALBEDO_SIZE], GGX_ALBEDO[k + GGX_ALBEDO_SIZE + 1], f.x),
               f.y);
}

// A surface with the dielectric's lobe f0_d at normal incidence and f90_d at grazing.
PbrSurface pbr_surface_full(vec3 base, float metallic, float roughness, float n_dot_v,
                            vec3 f0_d, float f90_d) {
    vec3 f0 = mix(f0_d, base, metallic);
    n_dot_v = max(n_dot_v, 1e-4);
    float e = ggx_albedo(n_dot_v, roughness);
    return PbrSurface((1.0 - metallic) * base, f0, mix(f90_d, 1.0, metallic), f0_d, f90_d,
                      max(roughness * roughness, MIN_ALPHA), n_dot_v,
                      1.0 + f0 * ((1.0 - e) / e), 0.0, 1.0, 0.0, vec3(0.0, 0.0, 1.0),
                      n_dot_v, vec3(0.0), 1.0, 0.0, 0.0, vec3(0.0), vec3(0.0), 0.0, 0.0,
                      vec3(1.0, 0.0, 0.0), vec3(0.0));
}

// An anisotropic specular lobe (KHR_materials_anisotropy): ``strength``, stretched along
// ``t`` (on the surface of normal N): alpha_t = mix(alpha, 1, strength^2) along it.
void pbr_anisotropy(inout PbrSurface s, float strength, vec3 t, vec3 N) {
    s.aniso = strength;
    if (strength <= 0.0) return;
    s.aniso_t = normalize(t - N * dot(N, t));
    s.alpha_t = mix(s.alpha, 1.0, strength * strength);
}

// GGX's distribution of normals at H: isotropic, or stretched (s.aniso > 0).
float pbr_ndf(PbrSurface s, vec3 N, vec3 H) {
    float n_dot_h = max(dot(N, H), 0.0);
#ifndef NO_ANISOTROPY
    if (s.aniso > 0.0) {
        vec3 T = s.aniso_t, B = cross(N, T);
        float at = s.alpha_t, ab = s.alpha, a2 = at * ab;
        vec3 f = vec3(ab * dot(T, H), at * dot(B, H), a2 * n_dot_h);
        float w2 = a2 / max(dot(f, f), 1e-30);
        return a2 * w2 * w2 / PI;
    }
#endif
    return ggx_d(n_dot_h, s.alpha);
}

// GGX's D times Smith's height-correlated Vis, isotropic or (s.aniso > 0) anisotropic as
// KHR_materials_anisotropy gives them (D = a^2 w^2 w^2 / pi, w^2 = a^2 / |f|^2).
float pbr_specular(PbrSurface s, vec3 N, vec3 V, vec3 L, vec3 H, float n_dot_l) {
#ifndef NO_ANISOTROPY
    if (s.aniso > 0.0) {
        vec3 T = s.aniso_t, B = cross(N, T);
        float at = s.alpha_t, ab = s.alpha;
        float d = pbr_ndf(s, N, H);
        float gv = n_dot_l * length(vec3(at * dot(T, V), ab * dot(B, V), s.n_dot_v));
        float gl = s.n_dot_v * length(vec3(at * dot(T, L), ab * dot(B, L), n_dot_l));
        return d * (gv + gl > 0.0 ? 0.5 / (gv + gl) : 0.0);
    }
#endif
    return ggx_d(max(dot(N, H), 0.0), s.alpha) * smith_vis(n_dot_l, s.n_dot_v, s.alpha);
}

// The normal the environment's prefiltered radiance is read about for an anisotropic
// lobe: bent towards the stretch as the Khronos Sample Viewer bends it; N otherwise.
vec3 pbr_bent_normal(PbrSurface s, vec3 N, vec3 V, float roughness) {
#ifndef NO_ANISOTROPY
    if (s.aniso > 0.0) {
        vec3 B = cross(N, s.aniso_t);
        vec3 bent = normalize(cross(cross(B, V), B));
        float a = pow(1.0 - s.aniso * (1.0 - roughness), 4.0);
        return normalize(mix(bent, N, a));
    }
#endif
    return N;
}

// A thin film on the surface (KHR_materials_iridescence): ``factor`` its share, index
// ``film_ior``, ``nm`` thick, over a base of colour ``base`` and ``metallic``.
void pbr_iridescence(inout PbrSurface s, vec3 base, float metallic, float factor,
                     float film_ior, float nm) {
    s.irid = factor;
    if (factor <= 0.0) return;
    s.irid_fd = thin_film_fresnel(1.0, film_ior, s.n_dot_v, nm, s.f0_d);
    s.irid_f = mix(s.irid_fd, thin_film_fresnel(1.0, film_ior, s.n_dot_v, nm, base), metallic);
}

// The specular Fresnel term at Schlick weight fc (F(f0, f90), the film's mixed in), and the
// dielectric's alone (what its diffuse part keeps 1 - of).
vec3 pbr_fresnel(PbrSurface s, float fc) {
    return mix(s.f0 + (s.f90 - s.f0) * fc, s.irid_f, s.irid);
}
vec3 pbr_fresnel_d(PbrSurface s, float fc) {
    return mix(s.f0_d + (s.f90_d - s.f0_d) * fc, s.irid_fd, s.irid);
}

const float SHEEN_MIN_ROUGHNESS = 0.07;  // facet.render.energy's

// E_s: the sheen lobe's directional albedo (colour 1), bilinear in its table.
float sheen_albedo(float n_dot_v, float roughness) {
    vec2 c = vec2(sqrt(clamp(n_dot_v, 0.0, 1.0)), clamp(roughness, 0.0, 1.0))
           * float(SHEEN_ALBEDO_SIZE - 1);
    ivec2 i = min(ivec2(c), ivec2(SHEEN_ALBEDO_SIZE - 2));
    vec2 f = c - vec2(i);
    int k = i.y * SHEEN_ALBEDO_SIZE + i.x;
    return min(mix(mix(SHEEN_ALBEDO[k], SHEEN_ALBEDO[k + 1], f.x),
                   mix(SHEEN_ALBEDO[k + SHEEN_ALBEDO_SIZE],
                       SHEEN_ALBEDO[k + SHEEN_ALBEDO_SIZE + 1], f.x), f.y), 1.0);
}

// A sheen of ``colour`` and ``roughness`` on the surface (KHR_materials_sheen).
void pbr_sheen(inout PbrSurface s, vec3 colour, float roughness) {
    s.sheen = colour;
    s.sheen_roughness = max(roughness, SHEEN_MIN_ROUGHNESS);
    s.sheen_dim = max(colour.r, max(colour.g, colour.b))
                * sheen_albedo(s.n_dot_v, s.sheen_roughness);
}

// Estevez and Kulla's fit of the Charlie lobe's shadowing (their paper's coefficients).
float sheen_lambda(float cos_t, float alpha) {
    float t = (1.0 - alpha) * (1.0 - alpha);
    float a = mix(21.5473, 25.3245, t), b = mix(3.82987, 3.32435, t);
    float c = mix(0.19823, 0.16801, t), d = mix(-1.97760, -1.27393, t);
    float e = mix(-4.32054, -4.85967, t);
    float x = cos_t < 0.5 ? cos_t : 1.0 - cos_t;
    float fit = a / (1.0 + b * pow(x, c)) + d * x + e;
    if (cos_t < 0.5) return exp(fit);
    float half_fit = a / (1.0 + b * pow(0.5, c)) + d * 0.5 + e;
    return exp(2.0 * half_fit - fit);
}

// A clear coat of factor ``clearcoat`` and ``roughness`` with normal ``n`` (unit) on the
// surface seen from V.
void pbr_coat(inout PbrSurface s, float clearcoat, float roughness, vec3 n, vec3 V) {
    s.cc = clearcoat;
    s.cc_alpha = max(roughness * roughness, MIN_ALPHA);
    s.cc_n = n;
    s.cc_n_dot_v = clamp(dot(n, V), 1e-4, 1.0);
    s.cc_fresnel = DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * schlick_weight(s.cc_n_dot_v);
}

// glTF's core model: the dielectric of ior 1.5.
PbrSurface pbr_surface(vec3 base, float metallic, float roughness, float n_dot_v) {
    return pbr_surface_full(base, metallic, roughness, n_dot_v, vec3(DIELECTRIC_F0), 1.0);
}

// pi f(L, V) (N.L): what a light of intensity 1 from direction L adds (module comment).
// Branch-free: lights behind the surface get n_dot_l = 0 (a branch that only some
// fragments of a SIMD group take costs a CPU rasteriser more than the arithmetic).
vec3 pbr_light(PbrSurface s, vec3 N, vec3 V, vec3 L) {
    float n_dot_l = max(dot(N, L), 0.0);
    vec3 H = (L + V) * inversesqrt(max(dot(L + V, L + V), 1e-12));
    float fc = schlick_weight(max(dot(V, H), 0.0));
    float spec = pbr_specular(s, N, V, L, H, n_dot_l);
    vec3 F = pbr_fresnel(s, fc);
    vec3 F_d = pbr_fresnel_d(s, fc);
    vec3 f = n_dot_l * (PI * spec * F * s.ms + (1.0 - F_d) * s.c_diff);
#ifndef NO_DIFFUSE_TRANSMISSION
    // A light behind: what the diffuse transmission lobe passes (under the viewer's side's
    // Fresnel, as the diffuse part is).
    f += (1.0 - pbr_fresnel_d(s, schlick_weight(s.n_dot_v))) * s.c_dt * max(-dot(N, L), 0.0);
#endif
#ifndef NO_SHEEN
    if (s.sheen != vec3(0.0) && n_dot_l > 0.0) {
        float alpha = s.sheen_roughness * s.sheen_roughness;
        float n_dot_h = max(dot(N, H), 0.0);
        float sin_h = sqrt(max(1.0 - n_dot_h * n_dot_h, 0.0));
        float d = (2.0 + 1.0 / alpha) * pow(sin_h, 1.0 / alpha) / (2.0 * PI);
        float vis = clamp(1.0 / ((1.0 + sheen_lambda(s.n_dot_v, alpha)
                                  + sheen_lambda(n_dot_l, alpha)) * 4.0 * s.n_dot_v * n_dot_l),
                          0.0, 1.0);
        float c = max(s.sheen.r, max(s.sheen.g, s.sheen.b));
        float dim = min(1.0 - s.sheen_dim, 1.0 - c * sheen_albedo(n_dot_l, s.sheen_roughness));
        f = f * dim + n_dot_l * PI * s.sheen * d * vis;
    }
#endif
#ifndef NO_CLEARCOAT
    if (s.cc > 0.0) {
        float n_dot_l_c = max(dot(s.cc_n, L), 0.0);
        float coat = ggx_d(max(dot(s.cc_n, H), 0.0), s.cc_alpha)
                   * smith_vis(n_dot_l_c, s.cc_n_dot_v, s.cc_alpha)
                   * (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * fc);
        f = f * (1.0 - s.cc * s.cc_fresnel) + n_dot_l_c * PI * s.cc * coat;
    }
#endif
    return f;
}

// The same BRDF under light arriving from everywhere, by the split sum: ``lut`` holds, for
// this N.V and roughness, A = int f_spec (1 - Fc) cos, B = int f_spec Fc cos and
// C = int (1 - Fc) cos / pi over the hemisphere (glsl/ibl/lut.frag); so int F f_spec cos
// = f0 A + f90 B and int (1 - F_d) cos / pi = (1 - f0_d) - (f90_d - f0_d) (1 - C).
// ``diffuse`` is
// the irradiance / pi around N (radiance L everywhere gives L), ``specular`` the
// environment prefiltered by the GGX lobe around the mirror direction. Exact for a uniform
// environment.
vec3 pbr_ambient(PbrSurface s, vec3 diffuse, vec3 specular, vec3 lut) {
    vec3 kept = mix(1.0 - s.f0_d - (s.f90_d - s.f0_d) * (1.0 - lut.z), 1.0 - s.irid_fd,
                    s.irid);  // (a film's F is constant over the lobe: F (A + B))
    vec3 spec = mix(s.f0 * lut.x + s.f90 * lut.y, s.irid_f * (lut.x + lut.y), s.irid);
    return kept * s.c_diff * diffuse + spec * s.ms * specular;
}

// What the diffuse transmission lobe adds under light arriving from behind, ``back`` the
// irradiance / pi around -N.
vec3 pbr_ambient_through(PbrSurface s, vec3 back, vec3 lut) {
    vec3 kept = mix(1.0 - s.f0_d - (s.f90_d - s.f0_d) * (1.0 - lut.z), 1.0 - s.irid_fd,
                    s.irid);
    return kept * s.c_dt * back;
}

// The sheen over ``ambient`` (pbr_ambient's): its albedo lights it by ``diffuse`` (the
// irradiance / pi, as its lobe is broad).
vec3 pbr_ambient_sheen(PbrSurface s, vec3 ambient, vec3 diffuse) {
    if (s.sheen == vec3(0.0)) return ambient;
    return ambient * (1.0 - s.sheen_dim)
         + s.sheen * sheen_albedo(s.n_dot_v, s.sheen_roughness) * diffuse;
}

// The clear coat over ``ambient`` (pbr_ambient's): ``specular`` the environment along
// the mirror direction prefiltered for the coat's roughness, ``lut`` the table there.
vec3 pbr_ambient_coat(PbrSurface s, vec3 ambient, vec3 specular, vec3 lut) {
    return ambient * (1.0 - s.cc * s.cc_fresnel)
         + s.cc * (DIELECTRIC_F0 * lut.x + lut.y) * specular;
}
