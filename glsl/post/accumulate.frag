#version 330 core
// Adds one supersample to the accumulation target (additive blending is on): the colour
// of the same pixel in the sample's float image.
uniform sampler2D u_sample;
out vec4 f_color;

void main() {
    f_color = texelFetch(u_sample, ivec2(gl_FragCoord.xy), 0);
}
