// The material at a tracer's hit: the record in each instance's row (from MATERIAL_ROW,
// facet.render.rays.pack) read through the shared accessor (lib/material.glsl), each slot's
// image from its layer of u_textures (colour images decoded to linear when packed, data as
// stored). The array's sampler repeats: clamped axes are clamped half a texel in here (so
// its filter does not blend in the opposite edge); nearest filtering reads the layer
// (resized to the array's side) at the centre of the image's own texel.

vec4 record_texel(int rec, int k) {
    return instance_texel(rec * INSTANCE_TEXELS + MATERIAL_ROW + k);
}

float g_footprint = 0.0;  // the surface being read's (point_of): its textures' mip level

vec4 slot_image(int rec, int k, vec2 uv) {
    int at = SLOT_ROW + SLOT_TEXELS * k;  // (lib/material.glsl's slot_texel, not yet there)
    vec4 r0 = record_texel(rec, at), r1 = record_texel(rec, at + 1);
    vec4 r2 = record_texel(rec, at + 2);
    int wraps = int(r1.w) >> 1;
    float side = float(textureSize(u_textures, 0).x);
    // The cone's footprint in this slot's coordinates (its transform scales them).
    float lod = texture_lod(g_footprint * sqrt(abs(r0.x * r1.y - r0.y * r1.x)), side);
    if (r2.z > 0.5) {  // nearest: that texel's centre, of the image's own resolution
        uv = (floor(uv * r2.xy) + 0.5) / r2.xy;
        lod = 0.0;
    }
    float half_texel = 0.5 * exp2(max(lod, 0.0)) / side;  // of the level read
    bvec2 held = bvec2(wraps % 3 != 0, wraps / 3 != 0);  // clamped or mirrored (folded)
    uv = mix(uv, clamp(uv, half_texel, 1.0 - half_texel), vec2(held));
    return textureLod(u_textures, vec3(uv, r0.w), lod);
}

#include "lib/material.glsl"
#include "lib/pbr.glsl"

// Below this roughness a transmitting dielectric is perfectly smooth (the path tracer's
// delta lobes, glsl/trace/bsdf.glsl).
const float SMOOTH_GLASS = 0.03;

// The record's view of surface s (trace/shade.glsl).
MaterialPoint point_of(Surface s) {
    g_footprint = s.footprint;
    return MaterialPoint(s.uv, s.uv1, vec4(s.albedo, s.alpha), s.n, s.tangent,
                         s.front ? 1.0 : -1.0);
}

// Surface s's material; a glass volume on a surface that bounds none (FLAG_OPEN_VOLUME,
// facet.render.rays.pack.open_volume) is thin-walled here, absorbing over its thickness.
Material material_of(Surface s) {
    Material m = material_at(s.inst, point_of(s));
    int flags = int(instance_texel(s.inst * INSTANCE_TEXELS + 6).w);
    if ((flags & FLAG_OPEN_VOLUME) != 0) m.thin = true;
    return m;
}

// What thin-walled glass absorbs as light crosses it: over the thickness of a volume traced
// thin (FLAG_OPEN_VOLUME), nothing for glTF's thin walls (thickness 0).
vec3 thin_absorbed(Material m) {
    return exp(-m.absorption * m.thickness);
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

// What of the light on a shadow ray along d surface s lets through: all at a MASK cut-out;
// where covered, what its transmission passes (transmission x (1 - metallic) x base colour
// x (1 - F) at this angle, the mean over RGB: facet.render.materials.shadow_opacity's at
// normal incidence), and a BLEND surface 1 - its coverage more. ``refracting``: glass that
// bends light counts too (the Whitted tracer's approximation); the path tracer lets shadow
// rays through thin-walled smooth glass only, which passes light unbent, exactly.
float lets_through(Surface s, vec3 d, bool refracting) {
    int mode;
    float cutoff;
    MaterialPoint p = point_of(s);
    float a = coverage(s.inst, p, mode, cutoff);
    if (mode == ALPHA_MODE_MASK && a < cutoff) return 1.0;
    float passed = 0.0;
    if (record_texel(s.inst, REC_TRANSMISSION).x > 0.0) {
        Material m = material_of(s);
        if (refracting || (m.thin && m.roughness < SMOOTH_GLASS)) {
            float f = schlick_weight(abs(dot(d, s.n)));
            vec3 through = m.base * (1.0 - m.f0_d - (m.f90_d - m.f0_d) * f)
                         * (m.thin ? thin_absorbed(m) : vec3(1.0));
            passed = m.transmission * (1.0 - m.metallic) * dot(through, vec3(1.0 / 3.0));
        }
    }
    return mode == ALPHA_MODE_BLEND ? 1.0 - a + a * passed : passed;
}

// A shading normal (a normal map's, or interpolated) bent towards the geometric normal ng
// until V's mirror direction leaves the surface (as Cycles' ensure_valid_reflection does):
// otherwise the BSDF's main lobe points into the surface and its light is lost (dark rims
// on normal-mapped metal). The mirror direction R is lifted just above the surface and the
// normal made the half vector of V and it (Keller et al. 2017, "The Iray light transport
// simulation and rendering system"): continuous in n, so normals that lean far from the
// surface's (a cube's smoothed corners) shade without a visible edge where the bend begins.
vec3 valid_normal(vec3 n, vec3 ng, vec3 V) {
    float enough = min(0.9 * dot(ng, V), 0.01);
    vec3 R = reflect(-V, n);
    float above = dot(ng, R);
    if (above >= enough) return n;
    return normalize(V + normalize(R + (enough - above) * ng));
}
