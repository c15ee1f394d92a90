#version 330 core
// Colour finishing, the last pass of a render (facet.render.finish), at this pixel: the
// mean of the accumulated samples (u_scale = 1 / samples; 1 for one picture), straight
// alpha from premultiplied colour over a transparent background (pixels nothing covers take
// u_empty), clamped to [0, 1] (but for radiance into float output), and the sRGB encoding
// in the colour-managed mode.
#include "lib/color.glsl"

uniform sampler2D u_source;  // linear, premultiplied colour, or a sum of such samples
uniform float u_scale;
uniform bool u_unpremultiply;
uniform vec3 u_empty;        // straight colour of empty pixels, linear
uniform bool u_encode_srgb;
uniform bool u_clamp;        // false: colour above 1 kept (linear radiance, float output)
out vec4 f_color;

void main() {
    vec4 c = texelFetch(u_source, ivec2(gl_FragCoord.xy), 0) * u_scale;
    if (u_unpremultiply) {
        c.rgb = c.a > 0.0 ? c.rgb / c.a : u_empty;
    }
    c = u_clamp ? clamp(c, 0.0, 1.0) : vec4(max(c.rgb, 0.0), clamp(c.a, 0.0, 1.0));
    if (u_encode_srgb) {
        c.rgb = linear_to_srgb(c.rgb);
    }
    f_color = c;
}
