// The glTF metallic-roughness material at a hit, for the path tracer (glsl/trace/path.frag):
// an instance's factors (facet.render.trace.pack.material_rows) times its texture slots, each
// read through its coordinate set, KHR_texture_transform matrix and wrap modes from its layer
// of u_textures (colour images decoded to linear when packed, data images as stored), times
// the vertex colour. Texels from MATERIAL_ROW of the instance:
//   +0 (base colour rgb, metallic)             +1 (emitted radiance rgb, roughness)
//   +2 (base alpha, alpha mode, cutoff, normal scale)
//   +3 (the bare interface's reflectance at normal incidence x specular colour rgb,
//       specular: the dielectric's lobe before their textures and the clip to 1)
//   +4 (transmission, thickness: 0 thin-walled, ior, clearcoat)
//   +5 (absorption per length rgb, clearcoat roughness)   +6 (sheen colour rgb, roughness)
//   +7 (emitter density factor: luminance / total emitted power, or 0; unlit; 1 for an
//       object whose own material is metallic-roughness (the Whitted tracer's choice),
//   +7 .w: the clear coat's normal scale
// From SLOT_ROW, SLOT_TEXELS per slot (SLOT_*: facet.render.trace.pack.PATH_SLOTS' order):
//   (the uv transform's first row, layer or -1), (its second row, set + 2 (wrap s + 3 wrap t)),
//   (the image's own width and height, 1 for nearest filtering, -)
// with wrap 0 repeat (the sampler's), 1 clamp to the edge, 2 mirrored repeat. Nearest
// filtering reads the layer (resized to the array's size) at the centre of the image's
// own texel.
const int SLOT_BASE = 0, SLOT_MR = 1, SLOT_NORMAL = 2, SLOT_EMISSIVE = 3, SLOT_SPECULAR = 4,
          SLOT_SPECULAR_COLOR = 5, SLOT_TRANSMISSION = 6, SLOT_CLEARCOAT = 7,
          SLOT_CLEARCOAT_ROUGHNESS = 8, SLOT_CLEARCOAT_NORMAL = 9, SLOT_SHEEN_COLOR = 10,
          SLOT_SHEEN_ROUGHNESS = 11;
const int ALPHA_OPAQUE = 0, ALPHA_MASK = 1, ALPHA_BLEND = 2;

struct Material {
    vec3 base;        // linear base colour: factor x texture x vertex colour
    float alpha;      // its coverage (1 for OPAQUE)
    int alpha_mode;   // ALPHA_*
    float cutoff;     // MASK: covered where alpha >= cutoff
    float metallic;
    float roughness;
    vec3 f0_d;        // the dielectric's lobe: reflectance at normal incidence
    float f90_d;      // and at grazing incidence (KHR_materials_ior, _specular)
    float transmission;  // KHR_materials_transmission: share of the diffuse part let through
    bool thin;        // thin-walled (thickness 0): transmitted rays go on unbent
    float ior;
    vec3 absorption;  // inside the volume, per unit length (KHR_materials_volume)
    float clearcoat;  // KHR_materials_clearcoat: factor, roughness and normal (its normal
    float clearcoat_roughness;  // map's, else the surface's)
    vec3 cc_n;
    vec3 sheen;       // KHR_materials_sheen: colour and roughness
    float sheen_roughness;
    vec3 emission;    // emitted radiance
    vec3 n;           // the shading normal, normal map applied, on the side of Surface.n
    bool unlit;       // KHR_materials_unlit: shows its base colour, reflects nothing
    float emit_pdf;   // light sampling's density per unit area of this emitter (0: none)
};

vec4 material_texel(int inst, int k) {
    return fetch(u_instances, inst * INSTANCE_TEXELS + MATERIAL_ROW + k);
}

// One axis of a coordinate by its wrap mode; edges clamped half a texel in, so that the
// sampler's own (repeating) filter does not blend in the opposite edge.
float wrap_coordinate(float x, int mode, float half_texel) {
    if (mode == 1) return clamp(x, half_texel, 1.0 - half_texel);
    if (mode == 2) return clamp(1.0 - abs(mod(x, 2.0) - 1.0), half_texel, 1.0 - half_texel);
    return x;
}

bool has_slot(int inst, int k) {
    return fetch(u_instances, inst * INSTANCE_TEXELS + SLOT_ROW + SLOT_TEXELS * k).w >= 0.0;
}

// Slot k of instance inst at surface s; 1 where the slot is empty.
vec4 slot_texel(int inst, int k, Surface s) {
    int at = inst * INSTANCE_TEXELS + SLOT_ROW + SLOT_TEXELS * k;
    vec4 r0 = fetch(u_instances, at);
    if (r0.w < 0.0) return vec4(1.0);
    vec4 r1 = fetch(u_instances, at + 1);
    int code = int(r1.w);
    vec3 uvw = vec3((code & 1) != 0 ? s.uv1 : s.uv, 1.0);
    vec2 uv = vec2(dot(r0.xyz, uvw), dot(r1.xyz, uvw));
    vec4 r2 = fetch(u_instances, at + 2);
    if (r2.z > 0.5) uv = (floor(uv * r2.xy) + 0.5) / r2.xy;  // nearest: that texel's centre
    float half_texel = 0.5 / float(textureSize(u_textures, 0).x);
    int wraps = code >> 1;
    uv = vec2(wrap_coordinate(uv.x, wraps % 3, half_texel),
              wrap_coordinate(uv.y, wraps / 3, half_texel));
    return textureLod(u_textures, vec3(uv, r0.w), 0.0);
}

// The coverage of instance inst's material at s, and its alpha mode and cutoff.
float coverage(int inst, Surface s, out int mode, out float cutoff) {
    vec4 a = material_texel(inst, 2);
    mode = int(a.y);
    cutoff = a.z;
    if (mode == ALPHA_OPAQUE) return 1.0;
    return a.x * s.alpha * slot_texel(inst, SLOT_BASE, s).a;
}

// Whether a ray passes by the surface s of instance inst here: a MASK material's cut-out,
// or (BLEND) with probability 1 - alpha, by the random number u.
bool passes(int inst, Surface s, float u) {
    int mode;
    float cutoff;
    float a = coverage(inst, s, mode, cutoff);
    return mode == ALPHA_MASK ? a < cutoff : mode == ALPHA_BLEND && u >= a;
}

// A MASK material's cut-out at s: the surface is not there.
bool cut_out(int inst, Surface s) {
    int mode;
    float cutoff;
    float a = coverage(inst, s, mode, cutoff);
    return mode == ALPHA_MASK && a < cutoff;
}

// The shading normal at s through the normal map in slot k (x and y scaled by ``scale``);
// the interpolated normal without one.
vec3 mapped_normal(int inst, int k, float scale, Surface s) {
    if (s.tangent.w == 0.0 || !has_slot(inst, k)) return s.n;
    // The tangent frame turns with the shading normal when seen from behind (as the
    // rasterizer's glsl/mesh/pbr.frag): T flips with N, so B = w (N x T) stays.
    vec3 N = s.n;
    vec3 T = normalize(s.tangent.xyz - N * dot(N, s.tangent.xyz)) * (s.front ? 1.0 : -1.0);
    vec3 B = cross(N, T) * s.tangent.w;
    vec3 t = slot_texel(inst, k, s).xyz * 2.0 - 1.0;
    t.xy *= scale;
    vec3 n = mat3(T, B, N) * t;
    return dot(n, n) > 0.0 ? normalize(n) : N;
}

Material material_at(int inst, Surface s) {
    vec4 m0 = material_texel(inst, 0), m1 = material_texel(inst, 1);
    vec4 m2 = material_texel(inst, 2), m7 = material_texel(inst, 7);
    Material m;
    vec4 base = vec4(m0.rgb * s.albedo, m2.x * s.alpha) * slot_texel(inst, SLOT_BASE, s);
    m.base = base.rgb;
    m.alpha_mode = int(m2.y);
    m.alpha = m.alpha_mode == ALPHA_OPAQUE ? 1.0 : base.a;
    m.cutoff = m2.z;
    vec4 mr = slot_texel(inst, SLOT_MR, s);  // glTF: green roughness, blue metalness
    m.metallic = m0.w * mr.b;
    m.roughness = m1.w * mr.g;
    m.emission = m1.rgb * slot_texel(inst, SLOT_EMISSIVE, s).rgb;
    vec4 m3 = material_texel(inst, 3);
    m.f90_d = m3.w * slot_texel(inst, SLOT_SPECULAR, s).a;
    m.f0_d = min(m3.rgb * slot_texel(inst, SLOT_SPECULAR_COLOR, s).rgb, 1.0) * m.f90_d;
    vec4 m4 = material_texel(inst, 4);
    m.transmission = m4.x * slot_texel(inst, SLOT_TRANSMISSION, s).r;
    m.thin = m4.y <= 0.0;
    m.ior = m4.z;
    vec4 m5 = material_texel(inst, 5);
    m.absorption = m5.rgb;
    m.clearcoat = m4.w * slot_texel(inst, SLOT_CLEARCOAT, s).r;
    m.clearcoat_roughness = m5.w * slot_texel(inst, SLOT_CLEARCOAT_ROUGHNESS, s).g;
    vec4 m6 = material_texel(inst, 6);
    m.sheen = m6.rgb * slot_texel(inst, SLOT_SHEEN_COLOR, s).rgb;
    m.sheen_roughness = m6.w * slot_texel(inst, SLOT_SHEEN_ROUGHNESS, s).a;
    m.n = mapped_normal(inst, SLOT_NORMAL, m2.w, s);
    m.cc_n = m.clearcoat > 0.0 ? mapped_normal(inst, SLOT_CLEARCOAT_NORMAL, m7.w, s) : s.n;
    m.unlit = m7.y > 0.5;
    m.emit_pdf = m7.x;
    return m;
}

// A shading normal (a normal map's, or interpolated) bent towards the geometric normal ng
// until V's mirror direction leaves the surface (as Cycles' ensure_valid_reflection does):
// otherwise the BSDF's main lobe points into the surface and its light is lost (dark rims
// on normal-mapped metal). Each step halves the angle between them.
vec3 valid_normal(vec3 n, vec3 ng, vec3 V) {
    float enough = min(0.9 * dot(ng, V), 0.01);
    for (int k = 0; k < 6 && dot(ng, reflect(-V, n)) < enough; ++k) n = normalize(n + ng);
    return n;
}
