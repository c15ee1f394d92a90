// Phong lighting as pure functions (no uniforms), shared by facet's rasterizer, user shaders
// and the ray tracer. All vectors are unit length and in one common space (facet: world).
//   N: surface normal, L: towards the light, V: towards the eye, C: material colour.
// The notes' shading equation, per light i (ambient is added once by the caller):
//   I_i (k_d C max(N.L, 0) + k_s max(R.V, 0)^n), specular only where N.L > 0.

// Light kinds, as stored in the w component of a light's position (see lights.glsl).
const int LIGHT_DIRECTIONAL = 0;
const int LIGHT_POINT = 1;
const int LIGHT_SPOT = 2;

// x^n with 0^0 = 1, which GLSL's pow leaves undefined.
float safe_pow(float x, float n) {
    return n == 0.0 ? 1.0 : pow(max(x, 0.0), n);
}

// Diffuse + specular of one light with intensity I (colour x intensity x falloff).
vec3 phong_light(vec3 N, vec3 L, vec3 V, vec3 C, float kd, float ks, float n, vec3 I) {
    float n_dot_l = dot(N, L);
    if (n_dot_l <= 0.0) return vec3(0.0);
    vec3 R = reflect(-L, N);  // = 2 (N.L) N - L
    return I * (kd * C * n_dot_l + ks * safe_pow(dot(R, V), n));
}

// The same with Blinn's halfway vector H = (L + V) / |L + V| in place of R.V.
vec3 blinn_light(vec3 N, vec3 L, vec3 V, vec3 C, float kd, float ks, float n, vec3 I) {
    float n_dot_l = dot(N, L);
    if (n_dot_l <= 0.0) return vec3(0.0);
    vec3 H = normalize(L + V);
    return I * (kd * C * n_dot_l + ks * safe_pow(dot(N, H), n));
}

// 1 / (c + l d + q d^2) for attenuation k = (c, l, q) at distance d.
float light_attenuation(vec3 k, float d) {
    return 1.0 / max(k.x + k.y * d + k.z * d * d, 1e-6);
}

// Spot cone: 1 inside the inner half-angle, 0 outside the outer one, smooth between.
// travel: unit vector from the light to the point; axis: unit spot direction.
float spot_cone(vec3 travel, vec3 axis, float cos_inner, float cos_outer) {
    float c = dot(travel, axis);
    if (cos_inner <= cos_outer) return c >= cos_outer ? 1.0 : 0.0;
    return smoothstep(cos_outer, cos_inner, c);
}
