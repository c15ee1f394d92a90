// The path tracer's random numbers. Two kinds:
// - sample2(purpose): the decisions that shape a path's first bounces (where in its pixel
//   it starts, where the BSDF sends it, which direction of the sky and which point of an
//   emitter a shadow ray tries) come
//   from a padded, Owen-scrambled Sobol sequence (Burley, "Practical Hash-based Owen
//   Scrambling", JCGT 2020; the hash of Vegdahl's improved version, as Cycles' and
//   pbrt-v4's default samplers do): each (bounce, purpose) is a 2D Sobol (0, 2)-sequence
//   over the pixel's samples, scrambled and shuffled by a hash of the pixel, the seed and
//   the dimension. A pixel's N samples then cover each of these squares evenly (any N,
//   best at powers of two), where independent numbers clump, so the error falls faster
//   than 1 / sqrt(N) where the integrand is smooth, and every sample is still uniform
//   (the estimate stays unbiased).
// - random01() / random2(): a PCG hash stream for the rest (Russian roulette, cut-outs,
//   deeper bounces), seeded per pixel, sample and seed (path.frag).
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

// The sequence's state: the pixel's hash (with the seed), the sample's index among the
// pixel's samples, and the bounce (path.frag sets all three).
uint g_pixel;
uint g_index;
int g_bounce;
// sample2's purposes, each a 2D dimension of every bounce.
const int QMC_BSDF = 0, QMC_SKY = 1, QMC_EMITTER = 2, QMC_PIXEL = 3;
const int QMC_PURPOSES = 4;
const int QMC_BOUNCES = 6;  // deeper bounces draw from the PCG stream

uint reverse_bits(uint x) {
    x = (x << 16u) | (x >> 16u);
    x = ((x & 0x00FF00FFu) << 8u) | ((x & 0xFF00FF00u) >> 8u);
    x = ((x & 0x0F0F0F0Fu) << 4u) | ((x & 0xF0F0F0F0u) >> 4u);
    x = ((x & 0x33333333u) << 2u) | ((x & 0xCCCCCCCCu) >> 2u);
    return ((x & 0x55555555u) << 1u) | ((x & 0xAAAAAAAAu) >> 1u);
}

// A random permutation of bit-reversed numbers in which each bit flips by a hash of the
// bits below it (Laine and Karras 2011; Vegdahl's constants): on reversed bits, an Owen
// scramble.
uint lk_hash(uint x, uint seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Owen scrambling of a 32-bit fraction: each bit flipped by a hash of the bits above it.
uint owen_scramble(uint x, uint seed) { return reverse_bits(lk_hash(reverse_bits(x), seed)); }

// Sobol's second dimension of index i, its bits reversed (bit j of the result is the
// fraction's bit 31 - j). Its generator matrix is Pascal's triangle mod 2: by Lucas'
// theorem bit j sums (mod 2) the index's bits k whose set bits include j's, a sum over
// supersets taken one bit of the position at a time (five shifts, where a loop over the
// index's bits took 24 turns). The top 24 bits of the fraction, all a float keeps, depend
// on the index's 24 lowest bits only.
uint sobol1_reversed(uint i) {
    uint x = i & 0xFFFFFFu;
    x ^= (x >> 1u) & 0x55555555u;
    x ^= (x >> 2u) & 0x33333333u;
    x ^= (x >> 4u) & 0x0F0F0F0Fu;
    x ^= (x >> 8u) & 0x00FF00FFu;
    return x ^ ((x >> 16u) & 0x0000FFFFu);
}

// The next two dimensions of this path's sample for ``purpose`` (QMC_*) at this bounce,
// uniform in [0, 1)^2.
vec2 sample2(int purpose) {
    if (g_bounce >= QMC_BOUNCES) return random2();
    uint dim = uint(g_bounce * QMC_PURPOSES + purpose);
    uint seed = pcg_hash(g_pixel ^ pcg_hash(dim));
    uint i = owen_scramble(g_index, seed);  // the pixel's own order of the points
    // The first dimension is the bit-reversed index: scrambled, reverse(lk_hash(i)).
    uint x = reverse_bits(lk_hash(i, pcg_hash(seed + 1u)));
    uint y = reverse_bits(lk_hash(sobol1_reversed(i), pcg_hash(seed + 2u)));  // (scrambled)
    return vec2(float(x >> 8u), float(y >> 8u)) * (1.0 / 16777216.0);
}
