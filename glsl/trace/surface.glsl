// Surfaces at hits: where the ray met an instance, its normals and tangent frame, texture
// coordinates, vertex colour and Phong terms (the instance's material record, from
// MATERIAL_ROW: facet.render.material_record), and rays leaving it (offset_ray).
#include "trace/scene.glsl"
#include "lib/color.glsl"

uniform sampler2DArray u_textures;  // materials' images, one layer each (resized alike)
// A pixel's ray cone (Akenine-Moller et al. 2019, "Texture level of detail strategies for
// real-time ray tracing"): its width at distance t along the ray is u_cone.x + u_cone.y t
// (a parallel projection's pixel, a perspective one's angle). Textures are read at the
// level whose texels are as wide as the cone where it meets the surface: a minified
// texture is filtered as the rasterizer's mipmaps filter it, not aliased.
uniform vec2 u_cone;
float g_travelled = 0.0;  // how far the ray came before the segment being traced

struct Surface {
    vec3 p;       // world position
    vec3 n;       // unit shading normal, facing the incoming ray (two-sided, as rasterized)
    vec3 ng;      // unit geometric normal, the same side
    bool front;   // the ray arrived on the outward side (entering a solid)
    vec2 uv;      // texture coordinates
    vec2 uv1;     // the second set (0 without)
    vec4 tangent; // world tangent (0 without: shapes, meshes without frames), handedness
    vec3 albedo;  // texture x vertex colour (1 for plain materials); PBR_SHADING: the vertex
                  // colour only (the metallic-roughness model samples its slots itself)
    float alpha;  // the vertex colour's alpha (1 without)
    vec3 color;   // the material colour C (linear)
    vec4 k;       // k_a, k_d, k_s, shininess
    vec4 fx;      // opacity, reflectivity, ior, gloss
    int id;       // object id
    int inst;     // the instance hit
    float footprint;  // texture coordinates the pixel's cone covers here (0: texel size)
};

// Texture coordinates per unit of world length on a triangle (its uv area over its world
// area, both of its edges e1, e2 carried by the object -> world rows at base).
float uv_density(int base, vec3 e1, vec3 e2, vec2 duv1, vec2 duv2) {
    vec3 w1 = apply_rows(base + 3, e1, 0.0), w2 = apply_rows(base + 3, e2, 0.0);
    float area = length(cross(w1, w2));
    return area > 0.0 ? sqrt(abs(duv1.x * duv2.y - duv1.y * duv2.x) / area) : 0.0;
}

// The mip level of a texture ``texels`` wide for ``footprint`` (its uv units per cone).
float texture_lod(float footprint, float texels) {
    return footprint > 0.0 ? log2(max(footprint * texels, 1e-8)) : 0.0;
}

// The surface at hit h of the ray o + t d (d unit). The position is rebuilt from the
// object-space hit (barycentrics on the triangle, the shape's own point) and carried to
// world space, so its error is a few ulps of its own size: what offset_ray allows for.
Surface surface_at(Hit h, vec3 o, vec3 d) {
    int base = h.inst * INSTANCE_TEXELS;
    vec4 info = instance_texel(base + 6);
    int record = base + MATERIAL_ROW;
    vec4 m0 = instance_texel(record + REC_COLOR), m1 = instance_texel(record + REC_PHONG);
    vec4 m2 = instance_texel(record + REC_EFFECTS);
    bool own_pbr = instance_texel(record + REC_FLAGS).z > 0.5;  // metallic-roughness
    vec3 n_obj, ng_obj, p_obj;
    vec2 uv, uv1 = vec2(0.0);
    vec4 tangent = vec4(0.0);
    vec3 albedo = vec3(1.0);
    float alpha = 1.0, density = 0.0;
#if defined(NO_MESHES)
    if (false) {  // (shapes only)
#elif !defined(NO_SHAPES)
    if (h.tri >= 0) {
#else
    {
#endif
        vec3 w = vec3(1.0 - h.bary.x - h.bary.y, h.bary);
        vec4 t0 = TEXEL(u_tris, 3 * h.tri);
        vec3 e1 = TEXEL(u_tris, 3 * h.tri + 1).xyz, e2 = TEXEL(u_tris, 3 * h.tri + 2).xyz;
#ifdef NO_SPRITES
        t0.w = PRIM_TRIANGLE;
#endif
        if (t0.w == PRIM_TRIANGLE) {
            p_obj = t0.xyz + h.bary.x * e1 + h.bary.y * e2;
            ng_obj = cross(e1, e2);
        } else {  // a point's sphere or a line's capsule: the normal from its axis
            p_obj = apply_rows(base, o + h.t * d, 1.0);
            vec3 axis = t0.w == PRIM_SPHERE ? t0.xyz : t0.xyz + e1 * h.bary.y;
            ng_obj = p_obj - axis;
        }
        ivec4 vi = TEXEL(u_tri_index, h.tri);
        ivec3 at = vi.xyz * VERTEX_TEXELS;
        vec4 a0 = TEXEL(u_vertices, at.x), b0 = TEXEL(u_vertices, at.x + 1);
        vec4 a1 = TEXEL(u_vertices, at.y), b1 = TEXEL(u_vertices, at.y + 1);
        vec4 a2 = TEXEL(u_vertices, at.z), b2 = TEXEL(u_vertices, at.z + 1);
        n_obj = t0.w == PRIM_TRIANGLE ? a0.xyz * w.x + a1.xyz * w.y + a2.xyz * w.z : ng_obj;
        uv = vec2(a0.w, b0.x) * w.x + vec2(a1.w, b1.x) * w.y + vec2(a2.w, b2.x) * w.z;
#ifndef NO_SLOT_IMAGES
        if (t0.w == PRIM_TRIANGLE)
            density = uv_density(base, e1, e2, vec2(a1.w, b1.x) - vec2(a0.w, b0.x),
                                 vec2(a2.w, b2.x) - vec2(a0.w, b0.x));
#endif
        if ((int(info.w) & FLAG_COLORS) != 0) {
            // Vertex colours are stored sRGB-encoded: decoded in the sRGB mode, and
            // always for the metallic-roughness model (linear), each vertex's before they
            // are interpolated, as the rasterizer's vertex stage decodes them (glTF's
            // COLOR_0 is linear: blended in linear light).
#if defined(COLOR_SRGB) || defined(PATH_TRACER)
            bool decode = true;
#elif defined(PBR_SHADING)
            bool decode = own_pbr;
#else
            bool decode = false;
#endif
            mat3 c = mat3(b0.yzw, b1.yzw, b2.yzw);
            if (decode) c = mat3(srgb_to_linear(c[0]), srgb_to_linear(c[1]),
                                 srgb_to_linear(c[2]));
            albedo = c * w;
        }
#if defined(PBR_SLOTS) && (!defined(NO_SLOT_IMAGES) || defined(HAS_ALPHA) || \
                           !defined(NO_ANISOTROPY))
        // (uv1 and tangents are for images and anisotropy; the alpha of vertex colours for
        // BLEND / MASK)
        vec3 extra = mat3(TEXEL(u_vertices, at.x + 3).xyz, TEXEL(u_vertices, at.y + 3).xyz,
                          TEXEL(u_vertices, at.z + 3).xyz) * w;  // (uv1, alpha)
        uv1 = extra.xy;
        alpha = extra.z;
        tangent = TEXEL(u_vertices, at.x + 2) * w.x + TEXEL(u_vertices, at.y + 2) * w.y
                + TEXEL(u_vertices, at.z + 2) * w.z;
#endif
    }
#ifndef NO_SHAPES
    else {
        n_obj = ng_obj = h.n_obj;
        uv = h.uv;
        p_obj = onto_shape(int(info.x), instance_texel(base + 7),
                           apply_rows(base, o + h.t * d, 1.0), h.n_obj);
#ifdef PBR_SLOTS
        tangent = shape_tangent(int(info.x), p_obj, h.n_obj);
#endif
    }
#endif
    Surface s;
    s.p = apply_rows(base + 3, p_obj, 1.0);
    // Normals go by (M^-1)^T: the world -> object rows, as columns.
    mat3 to_world_n = mat3(instance_texel(base).xyz, instance_texel(base + 1).xyz,
                           instance_texel(base + 2).xyz);
    s.n = normalize(to_world_n * n_obj);
    s.ng = normalize(to_world_n * ng_obj);
    s.front = dot(s.ng, d) < 0.0;
    if (!s.front) { s.n = -s.n; s.ng = -s.ng; }
    s.footprint = density * (u_cone.x + u_cone.y * (g_travelled + h.t))
                / max(abs(dot(s.ng, d)), 0.05);
#if defined(PBR_SLOTS) && (!defined(NO_SLOT_IMAGES) || !defined(NO_ANISOTROPY))
    // Tangents are directions on the surface: carried by M (the object -> world rows).
    vec3 t_world = apply_rows(base + 3, tangent.xyz, 0.0);
    // A mirroring placement (det M < 0) turns the frame's handedness round.
    mat3 m_rows = mat3(instance_texel(base + 3).xyz, instance_texel(base + 4).xyz,
                       instance_texel(base + 5).xyz);
    float hand = (tangent.w < 0.0 ? -1.0 : 1.0) * (determinant(m_rows) < 0.0 ? -1.0 : 1.0);
    s.tangent = dot(tangent.xyz, tangent.xyz) > 0.0 ? vec4(normalize(t_world), hand)
                                                    : vec4(0.0);
#else
    s.tangent = vec4(0.0);
#endif
#ifdef NO_SLOT_IMAGES
    // (no images at all)
#elif defined(PBR_SHADING)
    // A Phong material's image (the metallic-roughness model reads its own slots).
    float lod = texture_lod(s.footprint, float(textureSize(u_textures, 0).x));
    if (m2.w >= 0.0 && !own_pbr) albedo *= textureLod(u_textures, vec3(uv, m2.w), lod).rgb;
#else
    float lod = texture_lod(s.footprint, float(textureSize(u_textures, 0).x));
    if (m2.w >= 0.0) albedo *= textureLod(u_textures, vec3(uv, m2.w), lod).rgb;
#endif
    s.albedo = albedo;
    s.alpha = alpha;
    s.uv = uv;
    s.uv1 = uv1;
    s.color = m0.rgb;
    s.k = vec4(m0.w, m1.xyz);
    s.fx = vec4(m1.w, m2.xyz);
    s.id = int(info.z);
    s.inst = h.inst;
    return s;
}

// Whether the surface's own material is metallic-roughness (shaded by that model; a
// Phong material by its Phong terms, but in the path tracer).
bool own_pbr(Surface s) {
    return instance_texel(s.inst * INSTANCE_TEXELS + MATERIAL_ROW + REC_FLAGS).z > 0.5;
}

// Wächter and Binder (Ray Tracing Gems, ch. 6): p moved off its surface along n by
// OFFSET_INT ulps of each coordinate (a fixed tiny step near the origin, where ulps
// vanish), more than the rounding error of p, so a ray from it cannot hit the surface it
// leaves, and little enough that contact shadows stay attached.
const float OFFSET_ORIGIN = 1.0 / 32.0;
const float OFFSET_FLOAT = 1.0 / 65536.0;
const float OFFSET_INT = 256.0;

vec3 offset_ray(vec3 p, vec3 n) {
    ivec3 step_i = ivec3(OFFSET_INT * n);
    ivec3 bits = floatBitsToInt(p);
    vec3 p_i = intBitsToFloat(bits + ivec3(p.x < 0.0 ? -step_i.x : step_i.x,
                                           p.y < 0.0 ? -step_i.y : step_i.y,
                                           p.z < 0.0 ? -step_i.z : step_i.z));
    return mix(p_i, p + OFFSET_FLOAT * n, lessThan(abs(p), vec3(OFFSET_ORIGIN)));
}
