#version 330 core
// Shows the mean of the samples accumulated so far: accumulation x (1 / samples).
uniform sampler2D u_accum;
uniform float u_scale;
out vec4 f_color;

void main() {
    f_color = texelFetch(u_accum, ivec2(gl_FragCoord.xy), 0) * u_scale;
}
