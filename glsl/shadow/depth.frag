#version 330 core
// Depth only (the shadow atlas has no colour attachment).
//
// Transparent casters (opacity < 1) are screen-door shadows: a 4x4 ordered-dither mask in
// shadow-map texels keeps a fraction `opacity` of each caster's texels, so the lighting's
// percentage-closer filter sees about `opacity` of the light blocked. u_dither_shift moves
// the mask per accumulation sample, so a supersampled render averages it out exactly.
uniform float u_opacity;
uniform ivec2 u_dither_shift;
#ifdef ALPHA_MASK
// glTF alphaMode MASK: cut-outs cast no shadow (base alpha x the base-colour image's alpha
// against the cutoff, as glsl/mesh/pbr.frag cuts them from the picture).
in vec2 v_uv;
uniform sampler2D u_texture;
uniform mat3 u_uv_transform;
uniform float u_base_alpha;
uniform float u_alpha_cutoff;
#endif

const float BAYER4[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0,
                                   3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);

void main() {
#ifdef ALPHA_MASK
    vec2 uv = (u_uv_transform * vec3(v_uv, 1.0)).xy;
    if (u_base_alpha * texture(u_texture, uv).a < u_alpha_cutoff) discard;
#endif
    if (u_opacity < 1.0) {
        ivec2 p = (ivec2(gl_FragCoord.xy) + u_dither_shift) & 3;
        if ((BAYER4[p.y * 4 + p.x] + 0.5) / 16.0 >= u_opacity) discard;
    }
}
