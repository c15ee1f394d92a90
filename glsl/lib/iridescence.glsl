// KHR_materials_iridescence: the Fresnel reflectance of a thin dielectric film on the
// surface (Belcour and Barla 2017, "A Practical Extension to Microfacet Theory for the
// Modeling of Varying Iridescence", in the approximation the extension's implementation
// notes give: Schlick's Fresnel at both interfaces, phase shifts of 0 or pi, the spectral
// integral in closed form by Gaussian fits of the CIE XYZ sensitivities, XYZ -> linear
// Rec. 709). tests/test_iridescence.py holds its numpy transcription.
#include "lib/constants.glsl"

const mat3 XYZ_TO_REC709 = mat3(3.2404542, -0.9692660, 0.0556434,
                                -1.5371385, 1.8760108, -0.2040259,
                                -0.4985314, 0.0415560, 1.0572252);

// The film's reflectance in Fourier space for the optical path difference opd (nm) and
// phase shift per channel: the interference term of order m once scaled by m.
vec3 film_sensitivity(float opd, vec3 shift) {
    float phase = 2.0 * PI * opd * 1.0e-9;
    vec3 val = vec3(5.4856e-13, 4.4201e-13, 5.2481e-13);
    vec3 pos = vec3(1.6810e+06, 1.7953e+06, 2.2084e+06);
    vec3 var = vec3(4.3278e+09, 9.3046e+09, 6.6121e+09);
    vec3 xyz = val * sqrt(2.0 * PI * var) * cos(pos * phase + shift)
             * exp(-phase * phase * var);
    xyz.x += 9.7470e-14 * sqrt(2.0 * PI * 4.5282e+09) * cos(2.2399e+06 * phase + shift.x)
           * exp(-4.5282e+09 * phase * phase);
    return XYZ_TO_REC709 * (xyz / 1.0685e-7);
}

float film_f0(float n_t, float n_i) {  // normal-incidence reflectance between two indices
    float r = (n_t - n_i) / (n_t + n_i);
    return r * r;
}

vec3 film_schlick(vec3 f0, float c) {
    float m = clamp(1.0 - c, 0.0, 1.0);
    return f0 + (1.0 - f0) * (m * m * m * m * m);
}

// F of a film of index film_ior and thickness nm (nanometres) between a medium of index
// outside_ior and a base of normal-incidence reflectance base_f0, seen at cos_1 to the
// normal. A film thinner than 30 nm fades to the outside's index (no film).
vec3 thin_film_fresnel(float outside_ior, float film_ior, float cos_1, float nm,
                       vec3 base_f0) {
    float n_film = mix(outside_ior, film_ior, smoothstep(0.0, 0.03, nm));
    float sin2_2 = (outside_ior / n_film) * (outside_ior / n_film) * (1.0 - cos_1 * cos_1);
    if (sin2_2 >= 1.0) return vec3(1.0);  // total internal reflection in the film
    float cos_2 = sqrt(1.0 - sin2_2);
    // First interface: outside -> film.
    float r12 = film_schlick(vec3(film_f0(n_film, outside_ior)), cos_1).x;
    float t121 = 1.0 - r12;
    float phi12 = n_film < outside_ior ? PI : 0.0;
    float phi21 = PI - phi12;
    // Second interface: film -> base (its index from its F0, extinction taken as 0).
    vec3 sq = sqrt(clamp(base_f0, 0.0, 0.9999));
    vec3 base_ior = (1.0 + sq) / (1.0 - sq);
    vec3 r1 = (base_ior - n_film) / (base_ior + n_film);
    vec3 r23 = film_schlick(r1 * r1, cos_2);
    vec3 phi23 = vec3(base_ior.x < n_film ? PI : 0.0, base_ior.y < n_film ? PI : 0.0,
                      base_ior.z < n_film ? PI : 0.0);
    float opd = 2.0 * n_film * nm * cos_2;
    vec3 phi = vec3(phi21) + phi23;
    vec3 r123 = clamp(r12 * r23, 1e-5, 0.9999);
    vec3 sqrt_r123 = sqrt(r123);
    vec3 rs = t121 * t121 * r23 / (1.0 - r123);
    vec3 f = r12 + rs;          // the m = 0 term
    vec3 c = rs - t121;
    c *= sqrt_r123;             // m = 1
    f += c * 2.0 * film_sensitivity(opd, phi);
    c *= sqrt_r123;             // m = 2
    f += c * 2.0 * film_sensitivity(2.0 * opd, 2.0 * phi);
    return max(f, 0.0);
}
