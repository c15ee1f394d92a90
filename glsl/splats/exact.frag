#version 330 core
// The exact channels where splats cover at least half the pixel (facet.render.raster
// splats): their expected depth and the weighted id of their clouds, written where that
// depth is nearer than the opaque scene's (the depth test, gl_FragDepth from u_projection).
uniform sampler2D u_splat_aux;  // sums of depth alpha T, id alpha T, -, alpha T
uniform mat4 u_projection;
layout(location = 0) out vec4 f_color;
layout(location = OUT_DEPTH_IDS) out uvec2 f_depth_ids;

void main() {
    vec4 sum = texelFetch(u_splat_aux, ivec2(gl_FragCoord.xy), 0);
    if (sum.a < 0.5) discard;
    float depth = sum.r / sum.a;
    vec4 clip = u_projection * vec4(0.0, 0.0, -depth, 1.0);
    gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;
    f_color = vec4(0.0);
    f_depth_ids = uvec2(floatBitsToUint(depth), uint(floor(sum.g / sum.a + 0.5)));
}
