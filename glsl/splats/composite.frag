#version 330 core
// The splats' sum (premultiplied, its alpha 1 - T) over the picture (blending: one, one
// minus source alpha): C + T x what lies behind, as the reference puts its background.
uniform sampler2D u_accum;
out vec4 f_color;

void main() {
    vec4 sum = texelFetch(u_accum, ivec2(gl_FragCoord.xy), 0);
    if (sum.a <= 0.0) discard;
    f_color = sum;
}
