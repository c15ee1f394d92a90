// Colour-space conversions (pure functions). sRGB uses the exact piecewise curve of
// IEC 61966-2-1, not a 2.2 power.

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(0.04045, c));
}

vec3 linear_to_srgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

// The encoding curve from square roots (no pow: a third of the cost on a CPU rasteriser),
// within 0.4/255 of linear_to_srgb over [0, 1] (facet's 8-bit outputs differ by at most one
// level). For shaders that encode every fragment themselves.
vec3 linear_to_srgb_fast(vec3 c) {
    vec3 s1 = sqrt(c), s2 = sqrt(s1), s3 = sqrt(s2);
    vec3 curve = 0.585122381 * s1 + 0.783140355 * s2 - 0.368262736 * s3;
    return mix(c * 12.92, curve, step(0.0031308, c));
}
