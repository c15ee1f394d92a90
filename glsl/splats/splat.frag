#version 330 core
// A splat's Gaussian at this pixel, composited front to back by the blending (one minus
// destination alpha, one: C += T alpha c, T *= 1 - alpha, the destination's alpha being
// 1 - T), as the reference: alpha = min(0.99, opacity exp(power)), nothing below 1/255.
// The second target sums depth and the cloud's id by the same weights (facet's depth
// channel from splats: the expected depth; ids: the weighted id, facet.render.raster.splats).
#include "lib/color.glsl"

flat in vec3 v_conic;
flat in vec4 v_color;
flat in vec2 v_center;
flat in float v_depth;
flat in float v_id;

layout(location = 0) out vec4 f_color;
layout(location = 1) out vec4 f_aux;

void main() {
    vec2 d = v_center - gl_FragCoord.xy;
    float power = -0.5 * (v_conic.x * d.x * d.x + v_conic.z * d.y * d.y) -
                  v_conic.y * d.x * d.y;
    if (power > 0.0) discard;
    float alpha = min(0.99, v_color.a * exp(power));
    if (alpha < 1.0 / 255.0) discard;
#if defined(COLOR_SRGB) || defined(LINEAR_OUT)
    vec3 rgb = srgb_to_linear(v_color.rgb);  // the picture holds linear light then
#else
    vec3 rgb = v_color.rgb;
#endif
    f_color = vec4(rgb * alpha, alpha);
    f_aux = vec4(v_depth * alpha, v_id * alpha, 0.0, alpha);
}
