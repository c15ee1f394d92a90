#version 330 core
// One level of the prefiltered environment (facet.render.ibl): the environment cube seen
// through a GGX lobe of u_roughness around each direction of an octahedral map,
// with N = V = R (the split-sum assumption). Filtered importance sampling: each sample
// reads the source mip whose texels are about as large as the sample's solid angle.
#include "lib/pbr.glsl"
#include "lib/sampling.glsl"

uniform samplerCube u_source;
uniform float u_source_size;  // texels along a cube face's side
uniform float u_roughness;
uniform vec2 u_size;
uniform int u_samples;
out vec4 f_color;

void main() {
    vec3 N = octahedral_dir(gl_FragCoord.xy / u_size);
    if (u_roughness <= 0.0) {
        f_color = vec4(textureLod(u_source, N, 0.0).rgb, 1.0);
        return;
    }
    float alpha = max(u_roughness * u_roughness, MIN_ALPHA);
    float texel = 4.0 * PI / (6.0 * u_source_size * u_source_size);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (int i = 0; i < u_samples; ++i) {
        vec3 H = around(ggx_sample(hammersley(i, u_samples), alpha), N);
        vec3 L = reflect(-N, H);
        float n_dot_l = dot(N, L);
        if (n_dot_l <= 0.0) continue;
        float pdf = ggx_d(max(dot(N, H), 0.0), alpha) * 0.25;  // N = V: N.H = V.H
        float lod = max(0.5 * log2(1.0 / (float(u_samples) * pdf * texel)) + 1.0, 0.0);
        sum += textureLod(u_source, L, lod).rgb * n_dot_l;
        weight += n_dot_l;
    }
    f_color = vec4(sum / max(weight, 1e-6), 1.0);
}
