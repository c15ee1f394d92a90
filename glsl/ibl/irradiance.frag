#version 330 core
// The environment's irradiance / pi around each direction N of an octahedral map
// (facet.render.ibl): the mean of the radiance over cosine-distributed directions, so an
// environment of radiance L everywhere gives L. Samples read a coarse mip of the source
// (the integrand is smooth at the scale of the cosine lobe).
#include "lib/sampling.glsl"

uniform samplerCube u_source;
uniform float u_lod;
uniform vec2 u_size;
out vec4 f_color;

const int SAMPLES = 512;

void main() {
    vec3 N = octahedral_dir(gl_FragCoord.xy / u_size);
    vec3 sum = vec3(0.0);
    for (int i = 0; i < SAMPLES; ++i) {
        vec3 L = around(cosine_sample(hammersley(i, SAMPLES)), N);
        sum += textureLod(u_source, L, u_lod).rgb;
    }
    f_color = vec4(sum / float(SAMPLES), 1.0);
}
