// Shadow maps: every shadow-casting light has tiles in one depth atlas (facet.render.shadow):
// one for directional and spot lights, six (a cube) for point lights. LIGHT_SHADOW[i] is the
// index of light i's first tile (-1: no shadow); u_shadow_matrix[t] maps world space to tile
// t in [0, 1]^3 (xy in the atlas, z the light's depth). Compiled in with SHADOWS.

uniform sampler2DShadow u_shadow_atlas;
uniform mat4 u_shadow_matrix[SHADOW_TILES];
// x: world size of one shadow texel at distance 0, y: its growth per unit of distance from
// the light (spot and point lights); z, w: unused.
uniform vec4 u_shadow_texel[LIGHT_COUNT];

const int LIGHT_SHADOW[LIGHT_COUNT] = LIGHT_SHADOW_LIST;

#ifndef SHADOW_PCF
#define SHADOW_PCF 1  // kernel radius in texels: 0 = one tap, 1 = 3 x 3, 2 = 5 x 5
#endif
// Self-shadowing ("shadow acne") is avoided by moving the lookup point off the surface along
// its normal by SHADOW_NORMAL_OFFSET texels and by a depth bias that grows with the slope.
const float SHADOW_NORMAL_OFFSET = 1.5;
const float SHADOW_BIAS = 0.0005;
const float SHADOW_SLOPE_BIAS = 0.002;

// 1 = fully lit, 0 = fully shadowed. p, N, L in world space (L towards the light).
float shadow_factor(int i, vec3 p, vec3 N, vec3 L, float distance_to_light) {
    if (LIGHT_SHADOW[i] < 0) return 1.0;
    int tile = LIGHT_SHADOW[i];
    if (LIGHT_KIND(i) == LIGHT_POINT) {  // the cube face this point is seen through
        vec3 v = p - u_lights[i].position.xyz;
        vec3 a = abs(v);
        tile += a.x >= a.y && a.x >= a.z ? (v.x > 0.0 ? 0 : 1)
              : a.y >= a.z ? (v.y > 0.0 ? 2 : 3) : (v.z > 0.0 ? 4 : 5);
    }
    vec4 texel = u_shadow_texel[i];
    float world_texel = texel.x + texel.y * distance_to_light;
    float n_dot_l = clamp(dot(N, L), 0.05, 1.0);
    vec3 lifted = p + N * (SHADOW_NORMAL_OFFSET * world_texel);
    vec4 q = u_shadow_matrix[tile] * vec4(lifted, 1.0);
    q.xyz /= q.w;
    float bias = SHADOW_BIAS + SHADOW_SLOPE_BIAS * sqrt(1.0 - n_dot_l * n_dot_l) / n_dot_l;
    vec2 step_uv = vec2(1.0) / vec2(textureSize(u_shadow_atlas, 0));
    float lit = 0.0;
    for (int y = -SHADOW_PCF; y <= SHADOW_PCF; ++y)
        for (int x = -SHADOW_PCF; x <= SHADOW_PCF; ++x)
            lit += texture(u_shadow_atlas, vec3(q.xy + vec2(x, y) * step_uv, q.z - bias));
    float taps = float((2 * SHADOW_PCF + 1) * (2 * SHADOW_PCF + 1));
    return lit / taps;
}
