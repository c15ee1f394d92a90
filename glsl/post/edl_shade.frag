#version 330 core
// Eye-dome lighting's shade per pixel (facet.render.raster.edl): from the cloud's linear
// depth (0: no point there), once per pixel rather than per fragment; the cloud's colour
// pass multiplies by it (glsl/lib/edl.glsl).
#include "lib/edl.glsl"
out vec4 f_shade;

void main() {
    float depth = texelFetch(u_edl_depth, ivec2(gl_FragCoord.xy), 0).r;
    f_shade = vec4(depth > 0.0 ? edl_shade(depth) : 1.0);
}
