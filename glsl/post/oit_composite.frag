#version 330 core
// Resolves weighted blended transparency over the opaque image (blending: src alpha,
// one minus src alpha): the weighted mean colour of the transparent layers, covering
// 1 - prod(1 - a_i) of the pixel.
uniform sampler2D u_accum;   // sum of w a C (rgb) and w a (a)
uniform sampler2D u_reveal;  // sum of -log(1 - a)
out vec4 f_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 accum = texelFetch(u_accum, p, 0);
    float reveal = exp(-texelFetch(u_reveal, p, 0).r);
    if (reveal >= 1.0) discard;  // nothing transparent here
    f_color = vec4(accum.rgb / clamp(accum.a, 1e-6, 5e4), 1.0 - reveal);
}
