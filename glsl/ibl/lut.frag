#version 330 core
// The split-sum table of glsl/lib/pbr.glsl's pbr_ambient: texel (i, j) of a u_size grid holds,
// for N.V = i / (size - 1) and roughness = j / (size - 1), with N = +z:
//   A = int f_spec (1 - Fc) cos,  B = int f_spec Fc cos  (GGX importance sampling)
//   C = int (1 - Fc) cos / pi                            (cosine sampling)
// Computed once per renderer (facet.render.ibl).
#include "lib/pbr.glsl"
#include "lib/sampling.glsl"

uniform vec2 u_size;
out vec4 f_lut;

const int SAMPLES = 1024;

void main() {
    vec2 c = (gl_FragCoord.xy - 0.5) / (u_size - 1.0);
    float n_dot_v = max(c.x, 1e-3);
    float alpha = max(c.y * c.y, MIN_ALPHA);
    vec3 V = vec3(sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    vec3 sums = vec3(0.0);
    for (int i = 0; i < SAMPLES; ++i) {
        vec2 xi = hammersley(i, SAMPLES);
        vec3 H = ggx_sample(xi, alpha);
        vec3 L = reflect(-V, H);
        float v_dot_h = dot(V, H);
        if (L.z > 0.0 && v_dot_h > 0.0) {
            // f_spec cos / pdf(L), pdf(L) = D (N.H) / (4 V.H)
            float w = 4.0 * smith_vis(L.z, n_dot_v, alpha) * L.z * v_dot_h / H.z;
            float fc = schlick_weight(v_dot_h);
            sums.xy += vec2(1.0 - fc, fc) * w;
        }
        vec3 Lc = cosine_sample(xi);
        sums.z += 1.0 - schlick_weight(max(dot(V, normalize(V + Lc)), 0.0));
    }
    f_lut = vec4(sums / float(SAMPLES), 1.0);
}
