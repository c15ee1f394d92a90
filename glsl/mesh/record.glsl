// The rasterizer's material record (facet.render.material_record): the drawn object's record
// as one uniform array, set per draw. Every mesh program reads its material here: the pbr
// model through lib/material.glsl's accessor (mesh/slots.glsl), the Phong family and the
// sprites through the terms below (lib/lights.glsl's products, glsl/mesh/phong.frag), the
// shadow pass its opacity and cut-outs (glsl/shadow/depth.frag); users' mesh shaders
// through lib/lights.glsl's shade_scene.
// The tracers read a record per hit (glsl/trace/material.glsl) and define RECORD_PER_HIT.
#ifndef RECORD_PER_HIT
#ifndef RECORD_TEXELS
#error the material record's layout is defined by facet.render.material_record
#endif

uniform vec4 u_material[RECORD_TEXELS];

vec4 record_texel(int rec, int k) {
    return u_material[k];
}

// The Phong family's terms: C (in the space lighting happens in) and k_a; k_d, k_s, the
// exponent n and the opacity; the reflectivity, the refractive index and the gloss of the
// environment it reflects.
vec3 phong_c() { return u_material[REC_COLOR].rgb; }
float phong_ka() { return u_material[REC_COLOR].w; }
float phong_kd() { return u_material[REC_PHONG].x; }
float phong_ks() { return u_material[REC_PHONG].y; }
float phong_shininess() { return u_material[REC_PHONG].z; }
float phong_opacity() { return u_material[REC_PHONG].w; }
float phong_reflectivity() { return u_material[REC_EFFECTS].x; }
float phong_ior() { return u_material[REC_EFFECTS].y; }
float phong_gloss() { return u_material[REC_EFFECTS].z; }

// glTF's alpha: the base alpha factor and the MASK cutoff; and how much of a light the
// surface stops for shadow maps (facet.render.materials.shadow_opacity).
float base_alpha() { return u_material[REC_ALPHA].x; }
float alpha_cutoff() { return u_material[REC_ALPHA].z; }
float shadow_opacity() { return u_material[REC_OCCLUSION].y; }

// ``uv`` through the base-colour image's texture transform (KHR_texture_transform's
// matrix rows in its slot; the identity for a Phong material's image).
vec2 base_color_uv(vec2 uv) {
    int k = SLOT_ROW + SLOT_TEXELS * SLOT_BASE_COLOR;
    vec3 uvw = vec3(uv, 1.0);
    return vec2(dot(u_material[k].xyz, uvw), dot(u_material[k + 1].xyz, uvw));
}
#endif  // RECORD_PER_HIT
