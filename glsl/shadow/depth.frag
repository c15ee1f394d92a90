#version 330 core
// Depth only (the shadow atlas has no colour attachment).
//
// Transparent casters (opacity < 1) are screen-door shadows: a 4x4 ordered-dither mask in
// shadow-map texels keeps a fraction `opacity` of each caster's texels, so the lighting's
// percentage-closer filter sees about `opacity` of the light blocked. u_dither_shift moves
// the mask per accumulation sample, so a supersampled render averages it out exactly.
// The caster's opacity, alpha and cutoff are its material record's (mesh/record.glsl).
#include "mesh/record.glsl"
uniform ivec2 u_dither_shift;
#ifdef ALPHA_MASK
// glTF alphaMode MASK: cut-outs cast no shadow (base alpha x the base-colour image's alpha
// against the cutoff, as glsl/mesh/pbr.frag cuts them from the picture).
in vec2 v_uv;
uniform sampler2D u_texture;
#endif

const float BAYER4[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0,
                                   3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);

void main() {
#ifdef ALPHA_MASK
    if (base_alpha() * texture(u_texture, base_color_uv(v_uv)).a < alpha_cutoff()) discard;
#endif
    float opacity = shadow_opacity();
    if (opacity < 1.0) {
        ivec2 p = (ivec2(gl_FragCoord.xy) + u_dither_shift) & 3;
        if ((BAYER4[p.y * 4 + p.x] + 0.5) / 16.0 >= opacity) discard;
    }
}
