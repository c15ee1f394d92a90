// Eye-dome lighting (Boucheny 2009; as CloudCompare and Potree shade unlit point clouds):
// a point darkens where its neighbours on the screen are nearer, in log depth, so shape
// shows without normals. The cloud's own linear depth comes from a pass of its own
// (facet.render.raster.edl: 0 where it has no point); empty neighbours add nothing.
// glsl/post/edl_shade.frag evaluates it once per pixel; the colour pass reads the result.
uniform sampler2D u_edl_depth;
uniform float u_edl_strength;  // Potree's 1.0
uniform float u_edl_radius;    // neighbours this many pixels away (Potree's 1.4)

const vec2 EDL_DIRS[8] = vec2[8](vec2(1.0, 0.0), vec2(0.7071, 0.7071), vec2(0.0, 1.0),
                                 vec2(-0.7071, 0.7071), vec2(-1.0, 0.0),
                                 vec2(-0.7071, -0.7071), vec2(0.0, -1.0),
                                 vec2(0.7071, -0.7071));

float edl_shade(float depth) {
    vec2 size = vec2(textureSize(u_edl_depth, 0));
    float own = log2(max(depth, 1e-6));
    float sum = 0.0;
    for (int i = 0; i < 8; ++i) {
        float d = texture(u_edl_depth, (gl_FragCoord.xy + EDL_DIRS[i] * u_edl_radius) / size).r;
        if (d > 0.0) sum += max(0.0, own - log2(d));
    }
    return exp(-sum / 8.0 * 300.0 * u_edl_strength);
}
