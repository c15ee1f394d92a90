// Sample points and directions for integrating over the sphere (pure functions), and the
// latitude-longitude map facet's prefiltered environments are stored in. World space.

const float TWO_PI = 6.28318530717959;

// The i-th of n points of the Hammersley set in [0, 1)^2 (radical inverse in base 2).
vec2 hammersley(int i, int n) {
    uint bits = uint(i);
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return vec2(float(i) / float(n), float(bits) * 2.3283064365386963e-10);
}

// A half vector around +z distributed as D_GGX(h) (h.z) (pdf of h), for roughness^2 alpha.
vec3 ggx_sample(vec2 xi, float alpha) {
    float phi = TWO_PI * xi.x;
    float cos_t = sqrt((1.0 - xi.y) / (1.0 + (alpha * alpha - 1.0) * xi.y));
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    return vec3(sin_t * cos(phi), sin_t * sin(phi), cos_t);
}

// A direction around +z distributed as cos / pi.
vec3 cosine_sample(vec2 xi) {
    float phi = TWO_PI * xi.x;
    float r = sqrt(xi.y);
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(1.0 - xi.y, 0.0)));
}

// v (around +z) in the frame whose z axis is n.
vec3 around(vec3 v, vec3 n) {
    vec3 t = normalize(cross(abs(n.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), n));
    return v.x * t + v.y * cross(n, t) + v.z * n;
}

// Octahedral map (facet's prefiltered environments): the unit sphere folded onto the
// octahedron |x| + |y| + |z| = 1 and that unfolded onto [0, 1]^2, the upper half (y >= 0)
// in the inner diamond. Only abs and divisions: cheaper than a latitude-longitude map's
// atan and asin, with texels of more even size.
vec2 sign_not_zero(vec2 v) {
    return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
}

vec2 octahedral_uv(vec3 d) {
    d /= abs(d.x) + abs(d.y) + abs(d.z);
    vec2 p = d.y >= 0.0 ? d.xz : (1.0 - abs(d.zx)) * sign_not_zero(d.xz);
    return p * 0.5 + 0.5;
}

vec3 octahedral_dir(vec2 uv) {
    vec2 p = uv * 2.0 - 1.0;
    vec3 d = vec3(p.x, 1.0 - abs(p.x) - abs(p.y), p.y);
    if (d.y < 0.0) d.xz = (1.0 - abs(d.zx)) * sign_not_zero(d.xz);
    return normalize(d);
}
