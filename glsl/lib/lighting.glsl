// Phong lighting as pure functions (no uniforms), shared by facet's rasterizer, user shaders
// and the ray tracer. All vectors are unit length and in one common space (facet: world).
//   N: surface normal, L: towards the light, V: towards the eye, C: material colour.
// The notes' shading equation, per light i (ambient is added once by the caller):
//   I_i (k_d C max(N.L, 0) + k_s max(R.V, 0)^n), specular only where N.L > 0.

// Light kinds, as stored in the w component of a light's position (see lights.glsl).
const int LIGHT_DIRECTIONAL = 0;
const int LIGHT_POINT = 1;
const int LIGHT_SPOT = 2;

// Written without branches: a software rasteriser shades many pixels in lockstep, and
// selects are cheaper there than divergent control flow.

// Smallest base given to pow: pow(0, n) is undefined in GLSL; MIN_POW_BASE^0 = 1 and
// MIN_POW_BASE^n underflows to 0 for any shininess n >= 1, as x^n should.
const float MIN_POW_BASE = 1e-30;

// max(x, 0)^n with 0^0 = 1.
float safe_pow(float x, float n) {
    return pow(max(x, MIN_POW_BASE), n);
}

// Diffuse + specular of one light. The light's intensity I and the material come
// pre-multiplied: diffuse = I k_d C, specular = I k_s, so this returns
// I (k_d C max(N.L, 0) + k_s max(R.V, 0)^n) with the specular term only where N.L > 0.
vec3 phong_light(vec3 N, vec3 L, vec3 V, vec3 diffuse, vec3 specular, float n) {
    float n_dot_l = dot(N, L);
    vec3 R = reflect(-L, N);  // = 2 (N.L) N - L
    float highlight = n_dot_l > 0.0 ? safe_pow(dot(R, V), n) : 0.0;
    return diffuse * max(n_dot_l, 0.0) + specular * highlight;
}

// The same with Blinn's halfway vector H = (L + V) / |L + V| in place of R.V.
vec3 blinn_light(vec3 N, vec3 L, vec3 V, vec3 diffuse, vec3 specular, float n) {
    float n_dot_l = dot(N, L);
    vec3 H = normalize(L + V);
    float highlight = n_dot_l > 0.0 ? safe_pow(dot(N, H), n) : 0.0;
    return diffuse * max(n_dot_l, 0.0) + specular * highlight;
}

// 1 / (c + l d + q d^2) for attenuation k = (c, l, q) at distance d.
float light_attenuation(vec3 k, float d) {
    return 1.0 / max(k.x + k.y * d + k.z * d * d, 1e-6);
}

// Spot cone: 1 inside the inner half-angle, 0 outside the outer one, smooth between.
// travel: unit vector from the light to the point; axis: unit spot direction.
float spot_cone(vec3 travel, vec3 axis, float cos_inner, float cos_outer) {
    float c = dot(travel, axis);
    // A hard cone when inner == outer (smoothstep is undefined for equal edges).
    return cos_inner > cos_outer ? smoothstep(cos_outer, cos_inner, c) : step(cos_outer, c);
}
