// Surfaces at hits, and their shading by the rasterizer's own equation: lib/lights.glsl's
// shade_scene, with this hit's material products and shadow rays in place of the per-draw
// uniforms and shadow maps.
#include "trace/scene.glsl"
#include "lib/color.glsl"

uniform sampler2DArray u_textures;  // materials' images, one layer each (resized alike)

struct Surface {
    vec3 p;       // world position
    vec3 n;       // unit shading normal, facing the incoming ray (two-sided, as rasterized)
    vec3 ng;      // unit geometric normal, the same side
    bool front;   // the ray arrived on the outward side (entering a solid)
    vec2 uv;      // texture coordinates
    vec2 uv1;     // the second set (0 without)
    vec4 tangent; // world tangent (0 without: shapes, meshes without frames), handedness
    vec3 albedo;  // texture x vertex colour (1 for plain materials); PBR_SLOTS: the vertex
                  // colour only (the path tracer samples the material's slots itself)
    float alpha;  // the vertex colour's alpha (1 without)
    vec3 color;   // the material colour C (linear)
    vec4 k;       // k_a, k_d, k_s, shininess
    vec4 fx;      // opacity, reflectivity, ior, gloss
    int id;       // object id
    int inst;     // the instance hit
};

// The surface at hit h of the ray o + t d (d unit). The position is rebuilt from the
// object-space hit (barycentrics on the triangle, the shape's own point) and carried to
// world space, so its error is a few ulps of its own size: what offset_ray allows for.
Surface surface_at(Hit h, vec3 o, vec3 d) {
    int base = h.inst * INSTANCE_TEXELS;
    vec4 info = fetch(u_instances, base + 6);
    vec4 m0 = fetch(u_instances, base + 8), m1 = fetch(u_instances, base + 9);
    vec4 m2 = fetch(u_instances, base + 10);
    vec3 n_obj, ng_obj, p_obj;
    vec2 uv, uv1 = vec2(0.0);
    vec4 tangent = vec4(0.0);
    vec3 albedo = vec3(1.0);
    float alpha = 1.0;
    if (h.tri >= 0) {
        vec3 w = vec3(1.0 - h.bary.x - h.bary.y, h.bary);
        vec4 t0 = fetch(u_tris, 3 * h.tri);
        vec3 e1 = fetch(u_tris, 3 * h.tri + 1).xyz, e2 = fetch(u_tris, 3 * h.tri + 2).xyz;
        if (t0.w == PRIM_TRIANGLE) {
            p_obj = t0.xyz + h.bary.x * e1 + h.bary.y * e2;
            ng_obj = cross(e1, e2);
        } else {  // a point's sphere or a line's capsule: the normal from its axis
            p_obj = apply_rows(base, o + h.t * d, 1.0);
            vec3 axis = t0.w == PRIM_SPHERE ? t0.xyz : t0.xyz + e1 * h.bary.y;
            ng_obj = p_obj - axis;
        }
        ivec4 vi = fetch_int(u_tri_index, h.tri);
        ivec3 at = vi.xyz * VERTEX_TEXELS;
        vec4 a0 = fetch(u_vertices, at.x), b0 = fetch(u_vertices, at.x + 1);
        vec4 a1 = fetch(u_vertices, at.y), b1 = fetch(u_vertices, at.y + 1);
        vec4 a2 = fetch(u_vertices, at.z), b2 = fetch(u_vertices, at.z + 1);
        n_obj = t0.w == PRIM_TRIANGLE ? a0.xyz * w.x + a1.xyz * w.y + a2.xyz * w.z : ng_obj;
        uv = vec2(a0.w, b0.x) * w.x + vec2(a1.w, b1.x) * w.y + vec2(a2.w, b2.x) * w.z;
        if ((int(info.w) & FLAG_COLORS) != 0) {
            vec3 c = b0.yzw * w.x + b1.yzw * w.y + b2.yzw * w.z;
            // Vertex colours are stored sRGB-encoded: decoded in the sRGB mode, and
            // always for the metallic-roughness model (linear).
#if defined(COLOR_SRGB) || defined(PATH_TRACER)
            c = srgb_to_linear(c);
#elif defined(PBR_SLOTS)
            if (fetch(u_instances, base + MATERIAL_ROW + 7).z > 0.5) c = srgb_to_linear(c);
#endif
            albedo = c;
        }
#ifdef PBR_SLOTS
        vec3 extra = mat3(fetch(u_vertices, at.x + 3).xyz, fetch(u_vertices, at.y + 3).xyz,
                          fetch(u_vertices, at.z + 3).xyz) * w;  // (uv1, alpha)
        uv1 = extra.xy;
        alpha = extra.z;
        tangent = fetch(u_vertices, at.x + 2) * w.x + fetch(u_vertices, at.y + 2) * w.y
                + fetch(u_vertices, at.z + 2) * w.z;
#endif
    } else {
        n_obj = ng_obj = h.n_obj;
        uv = h.uv;
        p_obj = onto_shape(int(info.x), fetch(u_instances, base + 7),
                           apply_rows(base, o + h.t * d, 1.0), h.n_obj);
#ifdef PBR_SLOTS
        tangent = shape_tangent(int(info.x), p_obj, h.n_obj);
#endif
    }
    Surface s;
    s.p = apply_rows(base + 3, p_obj, 1.0);
    // Normals go by (M^-1)^T: the world -> object rows, as columns.
    mat3 to_world_n = mat3(fetch(u_instances, base).xyz, fetch(u_instances, base + 1).xyz,
                           fetch(u_instances, base + 2).xyz);
    s.n = normalize(to_world_n * n_obj);
    s.ng = normalize(to_world_n * ng_obj);
    s.front = dot(s.ng, d) < 0.0;
    if (!s.front) { s.n = -s.n; s.ng = -s.ng; }
#ifdef PBR_SLOTS
    // Tangents are directions on the surface: carried by M (the object -> world rows).
    vec3 t_world = apply_rows(base + 3, tangent.xyz, 0.0);
    // A mirroring placement (det M < 0) turns the frame's handedness round.
    mat3 m_rows = mat3(fetch(u_instances, base + 3).xyz, fetch(u_instances, base + 4).xyz,
                       fetch(u_instances, base + 5).xyz);
    float hand = (tangent.w < 0.0 ? -1.0 : 1.0) * (determinant(m_rows) < 0.0 ? -1.0 : 1.0);
    s.tangent = dot(tangent.xyz, tangent.xyz) > 0.0 ? vec4(normalize(t_world), hand)
                                                    : vec4(0.0);
    // A Phong material's image (the metallic-roughness model reads its own slots).
    if (m2.w >= 0.0 && fetch(u_instances, base + MATERIAL_ROW + 7).z < 0.5)
        albedo *= textureLod(u_textures, vec3(uv, m2.w), 0.0).rgb;
#else
    s.tangent = vec4(0.0);
    if (m2.w >= 0.0) albedo *= textureLod(u_textures, vec3(uv, m2.w), 0.0).rgb;
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

// The material of the surface being shaded, for lib/lights.glsl's macros.
vec3 g_ambient_term, g_kd_c, g_ks;
float g_shininess;
vec3 g_ng;  // its geometric normal, for the shadow rays' offset
float light_visibility(int i, vec3 p, vec3 N, vec3 L, float falloff);
#ifdef ALPHA_SHADOWS
float alpha_shadow(vec3 o, vec3 d, float t_max);
#endif
#define AMBIENT_TERM g_ambient_term
#define LIGHT_DIFFUSE(i) (u_lights[i].color.rgb * g_kd_c)
#define LIGHT_SPECULAR(i) (u_lights[i].color.rgb * g_ks)
#define SHININESS g_shininess
#define SHADOW(i, p, N, L, falloff) light_visibility(i, p, N, L, falloff)
#include "lib/lights.glsl"

// Shadow rays: towards the light from the side of the surface the light is on, up to the
// light (directional lights: without end); none where the light adds nothing anyway
// (outside a spot's cone, or behind the shading normal, where N.L <= 0).
float light_visibility(int i, vec3 p, vec3 N, vec3 L, float falloff) {
#ifdef SHADOWS
    if (falloff <= 0.0 || dot(N, L) <= 0.0) return 1.0;
    float dist = LIGHT_KIND(i) == LIGHT_DIRECTIONAL ? INF
                                                    : length(u_lights[i].position.xyz - p);
    vec3 side = dot(g_ng, L) >= 0.0 ? g_ng : -g_ng;
#ifdef ALPHA_SHADOWS
    return alpha_shadow(offset_ray(p, side), L, dist);
#else
    return trace_shadow(offset_ray(p, side), L, dist);
#endif
#else
    return 1.0;
#endif
}

#ifdef PBR_SLOTS
#include "trace/material.glsl"
#include "lib/pbr.glsl"

// Below this roughness the Whitted tracer traces the scene's reflection in a glTF material
// (glsl/trace/trace.frag), and g_traced_specular of the ambient light's specular part is
// left to that ray.
const float TRACED_ROUGHNESS = 0.6;
float g_traced_specular = 0.0;

#ifdef ALPHA_SHADOWS
// A shadow ray through what is not opaque, nearest first: a BLEND surface lets 1 - its
// coverage (factor x texture x vertex alpha) through, a MASK cut-out all, anything else
// nothing (the path tracer's visibility, without its random choices).
float alpha_shadow(vec3 o, vec3 d, float t_max) {
    float through = 1.0;
    for (int k = 0; k < 8; ++k) {
        Hit h = trace_scene(o, d, t_max, false);
        if (h.inst < 0) return through;
        Surface s = surface_at(h, o, d);
        int mode;
        float cutoff;
        float a = coverage(h.inst, s, mode, cutoff);
        if (mode == ALPHA_OPAQUE || (mode == ALPHA_MASK && a >= cutoff)) return 0.0;
        if (mode == ALPHA_BLEND) through *= 1.0 - a;
        if (through <= 0.0) return 0.0;
        o = offset_ray(s.p, -s.ng);
        t_max -= h.t;
    }
    return 0.0;
}
#endif

// A metallic-roughness surface by the rasterizer's BRDF (lib/pbr.glsl): each light with
// its shadow ray, the ambient light as a uniform sky (its split sum by the lobe's albedo),
// emission; encoded for display outside the sRGB mode, as glsl/mesh/pbr.frag writes it.
vec3 shade_pbr(Surface s, vec3 V) {
    Material mat = material_at(s.inst, s);
    vec3 rgb = mat.base;
    if (!mat.unlit) {
        vec3 N = valid_normal(mat.n, s.ng, V);
        PbrSurface m = pbr_surface_full(mat.base, mat.metallic, mat.roughness, dot(N, V),
                                        mat.f0_d, mat.f90_d);
        m.c_diff *= 1.0 - mat.transmission;  // the rest passes: glsl/trace/trace.frag
        pbr_sheen(m, mat.sheen, mat.sheen_roughness);
        pbr_coat(m, mat.clearcoat, mat.clearcoat_roughness, valid_normal(mat.cc_n, s.ng, V), V);
        g_ng = s.ng;
        rgb = vec3(0.0);
        for (int i = 0; i < u_light_count.x; ++i) {
            vec3 L;
            float falloff = incident_light(i, s.p, L);
            falloff *= light_visibility(i, s.p, N, L, falloff);
            rgb += falloff * u_lights[i].color.rgb * pbr_light(m, N, V, L);
        }
        float fc = schlick_weight(m.n_dot_v);
        vec3 F = m.f0 + (m.f90 - m.f0) * fc, F_d = m.f0_d + (m.f90_d - m.f0_d) * fc;
        vec3 sky = pbr_ambient_sheen(m, F * ggx_albedo(m.n_dot_v, mat.roughness) * m.ms
                                         * (1.0 - g_traced_specular)
                                         + (1.0 - F_d) * m.c_diff, vec3(1.0));
        sky = sky * (1.0 - m.cc * m.cc_fresnel)
            + m.cc * m.cc_fresnel * ggx_albedo(m.cc_n_dot_v, mat.clearcoat_roughness);
        rgb += sky * u_ambient.rgb;
    }
    rgb += mat.emission;
#if !defined(COLOR_SRGB) && !defined(LINEAR_OUT)
    rgb = linear_to_srgb(clamp(rgb, 0.0, 1.0));
#endif
    return rgb;
}
#endif

// The Phong models' local colour of a surface seen from V (not clamped).
vec3 local_colour(Surface s, vec3 V) {
    vec3 c = s.color;
    g_ambient_term = u_ambient.rgb * s.k.x * c;
    g_kd_c = s.k.y * c;
    g_ks = vec3(s.k.z);
    g_shininess = s.k.w;
    g_ng = s.ng;
#if defined(SHADE_UNLIT)
    return c * s.albedo;
#elif defined(SHADE_NORMALS)
    return (s.front ? s.n : -s.n) * 0.5 + 0.5;  // the outward normal, as rasterized
#elif defined(SHADE_FLAT)
    return light_scene(s.p, s.ng, V, s.albedo, false);
#elif defined(SHADE_BLINN)
    return light_scene(s.p, s.n, V, s.albedo, true);
#else  // SHADE_PHONG; SHADE_GOURAUD is a rasterizer's per-vertex shortcut: traced as Phong
    return light_scene(s.p, s.n, V, s.albedo, false);
#endif
}

// The local colour of a surface seen from direction V (towards the viewer), times the
// share ``keep`` it adds beside its reflection (1 - reflectivity). The Phong models clamp
// that share as a pixel is clamped, not the local colour before it is shared: a highlight
// brighter than 1 still shows through (1 - reflectivity), as the notes' equation has it.
vec3 shade_surface(Surface s, vec3 V, float keep) {
#ifdef PBR_SLOTS
    if (material_texel(s.inst, 7).z > 0.5) return keep * shade_pbr(s, V);
#endif
    return clamp(keep * local_colour(s, V), 0.0, 1.0);
}
