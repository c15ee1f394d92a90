// Shadertoy-style: a ray-marched signed-distance-field scene (a sphere melting into a
// torus above a checkered floor), lit with the library's Phong term.
// Try: facet shader glsl/examples/sdf.frag
#include "lib/lighting.glsl"

const int MAX_STEPS = 96;
const float HIT_EPSILON = 1e-3;
const float FAR = 30.0;

float smin(float a, float b, float k) {
    float h = clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
    return mix(b, a, h) - k * h * (1.0 - h);
}

float scene(vec3 p) {
    float t = iTime;
    float sphere = length(p - vec3(0.0, 1.0 + 0.3 * sin(t), 0.0)) - 0.7;
    vec2 q = vec2(length(p.xz) - 1.1, p.y - 0.6);
    float torus = length(q) - 0.25;
    float floor_ = p.y + 0.2;
    return min(smin(sphere, torus, 0.4), floor_);
}

vec3 normal_at(vec3 p) {
    vec2 e = vec2(1e-3, 0.0);
    return normalize(vec3(scene(p + e.xyy) - scene(p - e.xyy),
                          scene(p + e.yxy) - scene(p - e.yxy),
                          scene(p + e.yyx) - scene(p - e.yyx)));
}

void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec2 uv = (2.0 * fragCoord - iResolution.xy) / iResolution.y;
    float a = 0.3 * iTime;
    vec3 eye = vec3(4.0 * sin(a), 2.2, 4.0 * cos(a));
    vec3 w = normalize(vec3(0.0, 0.6, 0.0) - eye);
    vec3 u = normalize(cross(w, vec3(0.0, 1.0, 0.0)));
    vec3 v = cross(u, w);
    vec3 dir = normalize(uv.x * u + uv.y * v + 1.6 * w);
    float t = 0.0;
    bool hit = false;
    for (int i = 0; i < MAX_STEPS && t < FAR; ++i) {
        float d = scene(eye + dir * t);
        if (d < HIT_EPSILON) { hit = true; break; }
        t += d;
    }
    vec3 sky = mix(vec3(0.6, 0.75, 0.95), vec3(0.2, 0.3, 0.55), uv.y * 0.5 + 0.5);
    if (!hit) { fragColor = vec4(sky, 1.0); return; }
    vec3 p = eye + dir * t;
    vec3 N = normal_at(p);
    vec3 L = normalize(vec3(-0.5, 1.0, 0.3));
    vec3 albedo = p.y < -0.19 ? mix(vec3(0.25), vec3(0.85),
                                     mod(floor(p.x) + floor(p.z), 2.0))
                              : vec3(0.9, 0.45, 0.2);
    vec3 color = 0.15 * albedo + phong_light(N, L, -dir, albedo, vec3(0.5), 48.0);
    fragColor = vec4(mix(color, sky, smoothstep(10.0, FAR, t)), 1.0);
}
