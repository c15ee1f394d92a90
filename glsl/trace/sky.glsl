// The sky of the path tracer: the radiance of escaped rays (the environment, or the
// scene's ambient light as a constant sky) and light sampling of it (by the environment
// image's luminance, facet.render.path.env_sampling, or uniform on the sphere).
#include "lib/lights.glsl"
#include "lib/sampling.glsl"
#include "trace/random.glsl"

#if defined(SKY_CONSTANT)
// An environment of one colour (facet.render.rays.scene): a value, not a cube map, whose
// lookups cost llvmpipe a tenth of a path-traced view of one object under a white sky.
uniform vec3 u_sky_color;
#elif defined(HAS_ENVIRONMENT)
uniform samplerCube u_environment;
#endif
#ifdef SKY_DISTRIBUTION
// The environment's luminance distribution (facet.render.path.env_sampling): cumulative
// shares per row (and of the rows, in column W), densities over the unit square.
uniform sampler2D u_sky_cdf;
uniform sampler2D u_sky_pdf;
uniform sampler2D u_sky_radiance;  // the grid the distribution was made from (RGB)
uniform ivec2 u_sky_size;  // W, H
#endif


#ifdef SKY_DISTRIBUTION
// Where direction d falls in the sky's latitude-longitude grid, (u, v) in [0, 1]^2 (row 0
// at the zenith; facet.render.path.env_sampling).
vec2 sky_uv(vec3 d) {
    return vec2(0.5 + atan(d.x, -d.z) / TWO_PI, acos(clamp(d.y, -1.0, 1.0)) / PI);
}
#endif

// The radiance of the sky seen in direction d (what the eye sees behind everything): the
// environment, or without one the scene's ambient light as a constant sky (the
// rasterizer's pbr model lights by it the same way). With the environment's grid at hand,
// the grid itself, filtered between texel centres as Mitsuba's envmap is: a pixel then
// sees the light the grid holds. The cube map (256 texels a face, resampled from a 2K
// image) spread a small sun seen directly into a different amount of light (a 1-texel sun
// 5x too bright, a 3 x 3 one 20% too dark: the picture's mean with it).
vec3 escaped(vec3 d) {
#if defined(SKY_CONSTANT)
    return u_sky_color;
#elif defined(SKY_DISTRIBUTION)
    return textureLod(u_sky_radiance, sky_uv(d), 0.0).rgb;
#elif defined(HAS_ENVIRONMENT)
    // The finest level: neighbouring pixels' random directions are no footprint (texture()
    // would pick a blurred level from their differences, dimming a small bright sun).
    return textureLod(u_environment, d, 0.0).rgb;
#else
    return u_ambient.rgb;
#endif
}

#ifdef SKY_DISTRIBUTION
// The texel of the sky's latitude-longitude grid that direction d falls in.
ivec2 sky_texel(vec3 d) {
    return clamp(ivec2(sky_uv(d) * vec2(u_sky_size)), ivec2(0), u_sky_size - 1);
}
#endif

// The sky's radiance lighting a surface from direction d: with a distribution, the
// grid's texel it was made from (the ratio of radiance to density stays bounded: the
// cube map's filtering spread a small sun where the density is low, each sample there a
// firefly); the camera sees the cube map (escaped).
vec3 sky_light(vec3 d) {
#ifdef SKY_DISTRIBUTION
    return texelFetch(u_sky_radiance, sky_texel(d), 0).rgb;
#else
    return escaped(d);
#endif
}

// The sky's density of direction d for light sampling (solid angle) from a surface of
// geometric normal ng (facing the side the light is gathered on).
float sky_pdf(vec3 ng, vec3 d) {
#ifdef SKY_DISTRIBUTION
    float sin_t = sqrt(max(1.0 - d.y * d.y, 0.0));
    return sin_t > 0.0 ? texelFetch(u_sky_pdf, sky_texel(d), 0).r / (2.0 * PI * PI * sin_t)
                       : 0.0;
#else
    return max(dot(ng, d), 0.0) / PI;
#endif
}

// A sky direction for light sampling from a surface of geometric normal ng, and its
// density: by luminance (a texel by two binary searches, then a point in it), or, for a
// constant sky, by the cosine about ng: a Lambertian surface's light from it then has no
// noise but its shadows' (uniform on the sphere, half the samples fell below the surface
// and the rest were weighed by a cosine they did not follow).
vec3 sample_sky(vec3 ng, out float pdf) {
#ifdef SKY_DISTRIBUTION
    int w = u_sky_size.x;
    vec2 rc = sample2(QMC_SKY);
    float r = rc.x, c = rc.y;
    int lo = 0, hi = u_sky_size.y - 1;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (texelFetch(u_sky_cdf, ivec2(w, mid), 0).r > r) hi = mid; else lo = mid + 1;
    }
    int y = lo;
    lo = 0;
    hi = w - 1;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (texelFetch(u_sky_cdf, ivec2(mid, y), 0).r > c) hi = mid; else lo = mid + 1;
    }
    vec2 uv = (vec2(lo, y) + random2()) / vec2(u_sky_size);
    float phi = (uv.x - 0.5) * TWO_PI, theta = uv.y * PI;
    vec3 d = vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    pdf = sky_pdf(ng, d);
    return d;
#else
    vec3 d = around(cosine_sample(sample2(QMC_SKY)), ng);
    pdf = sky_pdf(ng, d);
    return d;
#endif
}
