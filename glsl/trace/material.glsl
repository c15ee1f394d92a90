// The material at a tracer's hit: the record in each instance's row (from MATERIAL_ROW,
// facet.render.rays.pack) read through the shared accessor (lib/material.glsl), each slot's
// image from its layer of u_textures (colour images decoded to linear when packed, data as
// stored). The array's sampler repeats: clamped axes are clamped half a texel in here (so
// its filter does not blend in the opposite edge); nearest filtering reads the layer
// (resized to the array's side) at the centre of the image's own texel.

vec4 record_texel(int rec, int k) {
    return fetch(u_instances, rec * INSTANCE_TEXELS + MATERIAL_ROW + k);
}

vec4 slot_image(int rec, int k, vec2 uv) {
    int at = SLOT_ROW + SLOT_TEXELS * k;  // (lib/material.glsl's slot_texel, not yet there)
    vec4 r0 = record_texel(rec, at), r2 = record_texel(rec, at + 2);
    int wraps = int(record_texel(rec, at + 1).w) >> 1;
    if (r2.z > 0.5) uv = (floor(uv * r2.xy) + 0.5) / r2.xy;  // nearest: that texel's centre
    float half_texel = 0.5 / float(textureSize(u_textures, 0).x);
    bvec2 held = bvec2(wraps % 3 != 0, wraps / 3 != 0);  // clamped or mirrored (folded)
    uv = mix(uv, clamp(uv, half_texel, 1.0 - half_texel), vec2(held));
    return textureLod(u_textures, vec3(uv, r0.w), 0.0);
}

#include "lib/material.glsl"

// The record's view of surface s (trace/shade.glsl).
MaterialPoint point_of(Surface s) {
    return MaterialPoint(s.uv, s.uv1, vec4(s.albedo, s.alpha), s.n, s.tangent,
                         s.front ? 1.0 : -1.0);
}

Material material_of(Surface s) {
    return material_at(s.inst, point_of(s));
}

// Whether a ray passes by surface s here: a MASK material's cut-out, or (BLEND) with
// probability 1 - alpha, by the random number u.
bool passes(Surface s, float u) {
    int mode;
    float cutoff;
    float a = coverage(s.inst, point_of(s), mode, cutoff);
    return mode == ALPHA_MODE_MASK ? a < cutoff : mode == ALPHA_MODE_BLEND && u >= a;
}

// A MASK material's cut-out at s: the surface is not there.
bool cut_out(Surface s) {
    int mode;
    float cutoff;
    float a = coverage(s.inst, point_of(s), mode, cutoff);
    return mode == ALPHA_MODE_MASK && a < cutoff;
}

// What of the light on a shadow ray surface s lets through: 1 - a BLEND surface's
// coverage, all at a MASK cut-out, nothing at an opaque surface.
float lets_through(Surface s) {
    int mode;
    float cutoff;
    float a = coverage(s.inst, point_of(s), mode, cutoff);
    if (mode == ALPHA_MODE_OPAQUE || (mode == ALPHA_MODE_MASK && a >= cutoff)) return 0.0;
    return mode == ALPHA_MODE_BLEND ? 1.0 - a : 1.0;
}

// A shading normal (a normal map's, or interpolated) bent towards the geometric normal ng
// until V's mirror direction leaves the surface (as Cycles' ensure_valid_reflection does):
// otherwise the BSDF's main lobe points into the surface and its light is lost (dark rims
// on normal-mapped metal). Each step halves the angle between them.
vec3 valid_normal(vec3 n, vec3 ng, vec3 V) {
    float enough = min(0.9 * dot(ng, V), 0.01);
    for (int k = 0; k < 6 && dot(ng, reflect(-V, n)) < enough; ++k) n = normalize(n + ng);
    return n;
}
