// The path tracer's random numbers: a PCG hash stream (path.frag seeds g_rng per
// pixel, supersample and seed).
// PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020).
uint g_rng;
uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
float random01() {  // uniform in [0, 1)
    g_rng = pcg_hash(g_rng);
    return float(g_rng >> 8u) * (1.0 / 16777216.0);
}
vec2 random2() { return vec2(random01(), random01()); }
