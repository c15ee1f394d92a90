#version 330 core
// Adds supersamples to the accumulation target (additive blending is on): the colour of
// the same pixel in the sample's float image, or in each of u_slices pictures stacked in
// it u_slice_height rows apart (a mosaic of samples: facet.render.sequence).
uniform sampler2D u_sample;
uniform int u_slices;
uniform int u_slice_height;
out vec4 f_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < u_slices; ++i)
        sum += texelFetch(u_sample, p + ivec2(0, i * u_slice_height), 0);
    f_color = sum;
}
