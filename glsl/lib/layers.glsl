// The layers of a metallic-roughness surface, written once for every engine (the
// rasterizer's glsl/mesh/pbr.frag, the Whitted tracer's glsl/trace/shade.glsl, the path
// tracer's glsl/trace/bsdf.glsl): glTF's base BRDF (lib/pbr.glsl) with the dielectric lobe
// of KHR_materials_ior and _specular; the share of the diffuse part that
// KHR_materials_transmission lets through instead; KHR_materials_iridescence's thin film
// in the Fresnel terms; KHR_materials_sheen over them; and KHR_materials_clearcoat over all.
#include "lib/pbr.glsl"

// The roughness light through the surface is spread by: the surface's, scaled by how much
// its index bends (none at 1, full from 1.5; as the Khronos Sample Viewer's
// applyIorToRoughness).
float ior_roughness(float roughness, float ior) {
    return roughness * clamp(2.0 * ior - 2.0, 0.0, 1.0);
}

// What of light passing through the base is left by the layers the light also crosses: the
// dielectric's Fresnel at the viewer's angle (the thin film's with iridescence), the coat's
// and the sheen's.
vec3 kept_through_layers(PbrSurface s) {
    vec3 F_d = pbr_fresnel_d(s, schlick_weight(s.n_dot_v));
    return (1.0 - F_d) * (1.0 - s.cc * s.cc_fresnel) * (1.0 - s.sheen_dim);
}

// What a light of intensity 1 from direction L behind the surface adds through it, towards
// V: glTF's transmission lobe for a thin wall (KHR_materials_transmission), GGX about the
// mirrored direction at the roughness the ior scales (as the Khronos Sample Viewer's
// applyIorToRoughness), what the dielectric's Fresnel, the coat and the sheen leave, times
// ``c_trans`` (layered_surface's); pi f |cos|, as pbr_light (lib/pbr.glsl) is for light in
// front. 0 for a light in front.
vec3 pbr_light_through(PbrSurface s, vec3 c_trans, vec3 N, vec3 V, vec3 L, float roughness,
                       float ior) {
    if (dot(N, L) >= 0.0 || c_trans == vec3(0.0)) return vec3(0.0);
    float rough = ior_roughness(roughness, ior);
    float alpha = max(rough * rough, MIN_ALPHA);
    vec3 L_m = normalize(L - 2.0 * N * dot(N, L));  // mirrored to the viewer's side
    float n_dot_l = max(dot(N, L_m), 0.0);
    vec3 H = normalize(L_m + V);
    return kept_through_layers(s) * c_trans * PI * n_dot_l * ggx_d(max(dot(N, H), 0.0), alpha)
         * smith_vis(n_dot_l, s.n_dot_v, alpha);
}

// Material m (lib/material.glsl) seen from V with shading normal N and coat normal N_coat
// (unit, facing V); ``c_trans``: what transmission passes where the diffuse part was.
PbrSurface layered_surface(Material m, vec3 N, vec3 N_coat, vec3 V, out vec3 c_trans) {
    PbrSurface s = pbr_surface_full(m.base, m.metallic, m.roughness, clamp(dot(N, V), 0.0, 1.0),
                                    m.f0_d, m.f90_d);
    c_trans = s.c_diff * m.transmission;
    s.c_diff *= 1.0 - m.transmission;
#ifndef NO_DIFFUSE_TRANSMISSION
    // (transmission overrides it: of what it leaves, the share dt goes through, tinted)
    s.c_dt = (1.0 - m.metallic) * (1.0 - m.transmission) * m.diffuse_transmission
           * m.dt_color;
    s.c_diff *= 1.0 - m.diffuse_transmission;
#endif
#ifndef NO_IRIDESCENCE
    pbr_iridescence(s, m.base, m.metallic, m.iridescence, m.iridescence_ior,
                    m.iridescence_thickness);
#endif
#ifndef NO_ANISOTROPY
    pbr_anisotropy(s, m.anisotropy, m.aniso_t, N);
#endif
#ifndef NO_SHEEN
    pbr_sheen(s, m.sheen, m.sheen_roughness);
#endif
#ifndef NO_CLEARCOAT
    pbr_coat(s, m.clearcoat, m.clearcoat_roughness, N_coat, V);
#endif
    return s;
}
