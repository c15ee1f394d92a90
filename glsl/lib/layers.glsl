// The layers of a metallic-roughness surface, written once for every engine (the
// rasterizer's glsl/mesh/pbr.frag, the Whitted tracer's glsl/trace/shade.glsl, the path
// tracer's glsl/trace/bsdf.glsl): glTF's base BRDF (lib/pbr.glsl) with the dielectric lobe
// of KHR_materials_ior and _specular; the share of the diffuse part that
// KHR_materials_transmission lets through instead; KHR_materials_sheen over them; and
// KHR_materials_clearcoat over all.
#include "lib/pbr.glsl"

// Material m (lib/material.glsl) seen from V with shading normal N and coat normal N_coat
// (unit, facing V); ``c_trans``: what transmission passes where the diffuse part was.
PbrSurface layered_surface(Material m, vec3 N, vec3 N_coat, vec3 V, out vec3 c_trans) {
    PbrSurface s = pbr_surface_full(m.base, m.metallic, m.roughness, clamp(dot(N, V), 0.0, 1.0),
                                    m.f0_d, m.f90_d);
    c_trans = s.c_diff * m.transmission;
    s.c_diff *= 1.0 - m.transmission;
    pbr_sheen(s, m.sheen, m.sheen_roughness);
    pbr_coat(s, m.clearcoat, m.clearcoat_roughness, N_coat, V);
    return s;
}
