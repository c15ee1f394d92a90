// Glossy reflection by accumulation, one tilt per supersample (facet.render.antialias):
// direction r tilted by gloss * jitter (a point of a jittered pattern in [-0.5, 0.5)^2)
// across r, so the mean over the samples blurs over a lobe as wide as gloss. The
// rasterizer's environment reflections and the ray tracer's rays share it.
vec3 gloss_tilt(vec3 r, float gloss, vec2 jitter) {
    vec3 t1 = normalize(cross(r, abs(r.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
    vec3 t2 = cross(r, t1);
    return normalize(r + 2.0 * gloss * (t1 * jitter.x + t2 * jitter.y));
}
