// The material record's accessor, one for every engine (facet.render.material_record packs
// the record; its layout constants REC_*, SLOT_*, ALPHA_MODE_* are defined by facet when it
// compiles). Before including this file an engine defines
//   vec4 record_texel(int rec, int k)           texel k of record rec
//   vec4 slot_image(int rec, int k, vec2 uv)    slot k's image at uv (repeat and clamp are
//                                               the engine's; mirrored axes are folded here)
// The rasterizer has one record per draw (a uniform array) and a sampler per slot; the
// tracers one per instance and a layer of one texture array per image.
#ifndef RECORD_TEXELS
#error the material record's layout is defined by facet.render.material_record
#endif

// Where a material is read: what the geometry gives at a point of a surface.
struct MaterialPoint {
    vec2 uv;       // texture coordinate sets (the engine's stand-in where a mesh has none)
    vec2 uv1;
    vec4 color;    // vertex colour, linear RGBA (1 without)
    vec3 n;        // unit interpolated normal, facing the viewer
    vec4 tangent;  // world tangent xyz, handedness w (0: no tangent frame)
    float side;    // 1 seen from the front, -1 from behind: the tangent frame turns round
};

struct Material {
    vec3 base;        // linear base colour: factor x texture x vertex colour
    float alpha;      // its coverage (1 for OPAQUE)
    int alpha_mode;   // ALPHA_MODE_*
    float cutoff;     // MASK: covered where alpha >= cutoff
    float metallic;
    float roughness;
    vec3 f0_d;        // the dielectric's lobe: reflectance at normal incidence
    float f90_d;      // and at grazing incidence (KHR_materials_ior, _specular)
    float transmission;  // KHR_materials_transmission: share of the diffuse part let through
    float thickness;  // KHR_materials_volume: factor x texture (object space)
    bool thin;        // thin-walled (thickness factor 0): light goes on unbent
    float ior;
    vec3 absorption;  // inside the volume, per unit length
    float clearcoat;  // KHR_materials_clearcoat: factor, roughness and normal (its normal
    float clearcoat_roughness;  // map's, else the surface's)
    vec3 cc_n;
    vec3 sheen;       // KHR_materials_sheen: colour and roughness
    float sheen_roughness;
    float iridescence;  // KHR_materials_iridescence: share, the film's index and thickness
    float iridescence_ior;  // (nm)
    float iridescence_thickness;
    float dispersion_spread;  // KHR_materials_dispersion: the ior's half spread over R, G, B
    float diffuse_transmission;  // KHR_materials_diffuse_transmission: share and colour
    vec3 dt_color;
    float anisotropy;     // KHR_materials_anisotropy: strength, and the direction the lobe
    vec3 aniso_t;         // stretches along (world, on the surface; 0 without a frame)
    vec3 emission;    // emitted radiance
    float occlusion;  // what reaches the surface of the ambient light (occlusionTexture)
    vec3 n;           // the shading normal, normal map applied, facing the viewer
    bool unlit;       // KHR_materials_unlit: shows its base colour, reflects nothing
    float emit_pdf;   // light sampling's density per unit area of this emitter (0: none)
};

vec4 slot_texel(int rec, int k, int t) {
    return record_texel(rec, SLOT_ROW + SLOT_TEXELS * k + t);
}

bool has_slot(int rec, int k) {
#ifdef NO_SLOT_IMAGES
    return false;  // no material of the scene has an image in any slot (a fetch saved)
#else
    return slot_texel(rec, k, 0).w >= 0.0;
#endif
}

// Slot k's texture coordinates at p: its coordinate set through its KHR_texture_transform
// matrix, mirrored axes folded (wrap code: set + 2 (s + 3 t), 2 the mirrored repeat).
vec2 slot_uv(int rec, int k, MaterialPoint p) {
    vec4 r0 = slot_texel(rec, k, 0), r1 = slot_texel(rec, k, 1);
    int code = int(r1.w);
    vec3 uvw = vec3((code & 1) != 0 ? p.uv1 : p.uv, 1.0);
    vec2 uv = vec2(dot(r0.xyz, uvw), dot(r1.xyz, uvw));
    int wraps = code >> 1;
    vec2 mirrored = vec2(wraps % 3 == 2 ? 1.0 : 0.0, wraps / 3 == 2 ? 1.0 : 0.0);
    return mix(uv, 1.0 - abs(mod(uv, 2.0) - 1.0), mirrored);
}

// Slot k at p; 1 where the material has no image there.
vec4 slot(int rec, int k, MaterialPoint p) {
    return has_slot(rec, k) ? slot_image(rec, k, slot_uv(rec, k, p)) : vec4(1.0);
}

// The coverage of record rec's material at p, its alpha mode and cutoff.
float coverage(int rec, MaterialPoint p, out int mode, out float cutoff) {
    vec4 a = record_texel(rec, REC_ALPHA);
    mode = int(a.y);
    cutoff = a.z;
    if (mode == ALPHA_MODE_OPAQUE) return 1.0;
    return a.x * p.color.a * slot(rec, SLOT_BASE_COLOR, p).a;
}

// The shading normal at p through the normal map in slot k (x and y scaled by ``scale``),
// in the tangent frame that turns with the normal seen from behind; p.n without one.
vec3 mapped_normal(int rec, int k, float scale, MaterialPoint p) {
    if (p.tangent.w == 0.0 || !has_slot(rec, k)) return p.n;
    vec3 N = p.n;
    vec3 T = normalize(p.tangent.xyz - N * dot(N, p.tangent.xyz)) * p.side;
    vec3 B = cross(N, T) * p.tangent.w;
    vec3 t = slot(rec, k, p).xyz * 2.0 - 1.0;
    vec3 n = mat3(T, B, N) * vec3(t.xy * scale, t.z);
    return dot(n, n) > 0.0 ? normalize(n) : N;
}

// What record rec's material emits at p (its emissive factor times its texture), and its
// emit_pdf: all light sampling needs of a point on an emitter (material_at reads the rest).
vec3 emission_at(int rec, MaterialPoint p, out float emit_pdf) {
    emit_pdf = record_texel(rec, REC_FLAGS).x;
    return record_texel(rec, REC_EMISSION).rgb * slot(rec, SLOT_EMISSIVE, p).rgb;
}

// Record rec's material at p: each factor times its texture (glTF's channels: green
// roughness, blue metalness, red occlusion ...), the normal maps applied.
Material material_at(int rec, MaterialPoint p) {
    vec4 base_f = record_texel(rec, REC_BASE), em = record_texel(rec, REC_EMISSION);
    vec4 al = record_texel(rec, REC_ALPHA), fl = record_texel(rec, REC_FLAGS);
    Material m;
    vec4 base = vec4(base_f.rgb, al.x) * p.color * slot(rec, SLOT_BASE_COLOR, p);
    m.base = base.rgb;
    m.alpha_mode = int(al.y);
    m.alpha = m.alpha_mode == ALPHA_MODE_OPAQUE ? 1.0 : base.a;
    m.cutoff = al.z;
    vec4 mr = slot(rec, SLOT_METALLIC_ROUGHNESS, p);
    m.metallic = base_f.w * mr.b;
    m.roughness = em.w * mr.g;
    m.emission = em.rgb * slot(rec, SLOT_EMISSIVE, p).rgb;
    vec4 sp = record_texel(rec, REC_SPECULAR);
    m.f90_d = sp.w * slot(rec, SLOT_SPECULAR, p).a;
    m.f0_d = min(sp.rgb * slot(rec, SLOT_SPECULAR_COLOR, p).rgb, 1.0) * m.f90_d;
    vec4 tr = record_texel(rec, REC_TRANSMISSION), ab = record_texel(rec, REC_ABSORPTION);
    m.transmission = tr.x * slot(rec, SLOT_TRANSMISSION, p).r;
    m.thickness = tr.y * slot(rec, SLOT_THICKNESS, p).g;
    m.thin = tr.y <= 0.0;
    m.ior = tr.z;
    m.absorption = ab.rgb;
    m.clearcoat = tr.w * slot(rec, SLOT_CLEARCOAT, p).r;
    m.clearcoat_roughness = ab.w * slot(rec, SLOT_CLEARCOAT_ROUGHNESS, p).g;
    vec4 sh = record_texel(rec, REC_SHEEN);
    m.sheen = sh.rgb * slot(rec, SLOT_SHEEN_COLOR, p).rgb;
    m.sheen_roughness = sh.w * slot(rec, SLOT_SHEEN_ROUGHNESS, p).a;
    vec4 ir = record_texel(rec, REC_IRIDESCENCE);
    m.iridescence = ir.x * slot(rec, SLOT_IRIDESCENCE, p).r;
    m.iridescence_ior = ir.y;
    m.iridescence_thickness = mix(ir.z, ir.w, slot(rec, SLOT_IRIDESCENCE_THICKNESS, p).g);
    m.dispersion_spread = record_texel(rec, REC_DISPERSION).x;
#ifdef NO_DIFFUSE_TRANSMISSION
    m.diffuse_transmission = 0.0;
    m.dt_color = vec3(0.0);
#else
    vec4 dt = record_texel(rec, REC_DIFFUSE_T);
    m.diffuse_transmission = dt.w * slot(rec, SLOT_DIFFUSE_TRANSMISSION, p).a;
    m.dt_color = dt.rgb * slot(rec, SLOT_DIFFUSE_TRANSMISSION_COLOR, p).rgb;
#endif
#ifdef NO_ANISOTROPY
    m.anisotropy = 0.0;
    m.aniso_t = vec3(0.0);
#else
    // The direction in the tangent frame: the texture's RG (to [-1, 1]; (1, 0) without
    // one) turned by the rotation; its strength the factor times B.
    vec4 an = record_texel(rec, REC_ANISOTROPY);
    vec4 at = has_slot(rec, SLOT_ANISOTROPY) ? slot(rec, SLOT_ANISOTROPY, p)
                                             : vec4(1.0, 0.5, 1.0, 1.0);
    vec2 dir = at.rg * 2.0 - 1.0;
    dir = vec2(an.y * dir.x - an.z * dir.y, an.z * dir.x + an.y * dir.y);
    m.anisotropy = an.x * at.b;
    m.aniso_t = vec3(0.0);
    if (p.tangent.w != 0.0) {
        vec3 T = normalize(p.tangent.xyz - p.n * dot(p.n, p.tangent.xyz)) * p.side;
        vec3 B = cross(p.n, T) * p.tangent.w;
        m.aniso_t = T * dir.x + B * dir.y;
    }
    if (dot(m.aniso_t, m.aniso_t) == 0.0) m.anisotropy = 0.0;  // (no frame: isotropic)
#endif
#ifdef ORM_PACKED
    float occluded = mr.r;  // glTF's "ORM" image: occlusion in the red of the same fetch
#else
    float occluded = slot(rec, SLOT_OCCLUSION, p).r;
#endif
    m.occlusion = 1.0 + record_texel(rec, REC_OCCLUSION).x * (occluded - 1.0);
    m.n = mapped_normal(rec, SLOT_NORMAL, al.w, p);
    m.cc_n = m.clearcoat > 0.0 ? mapped_normal(rec, SLOT_CLEARCOAT_NORMAL, fl.w, p) : p.n;
    m.unlit = fl.y > 0.5;
    m.emit_pdf = fl.x;
    return m;
}
