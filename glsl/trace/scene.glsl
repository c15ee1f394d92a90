// Placed objects (instances) and the top level over them; hits and the surfaces they give.
// An instance is INSTANCE_TEXELS texels (facet.render.rays.pack):
//   0-2  world -> object rows          3-5  object -> world rows
//   6    (kind, mesh root node, object id, flags: FLAG_COLORS | FLAG_ONE_SIDED)
//   7    shape parameters
//   MATERIAL_ROW...  its material's record (facet.render.material_record)
#include "trace/bvh.glsl"
#include "trace/shapes.glsl"

// FLAG_COLORS: the mesh has vertex colours; FLAG_ONE_SIDED: a single-sided material: a
// camera ray does not see its back faces (as the rasterizer culls them), every other ray
// does (for light a surface is opaque from both sides: shadow rays and bounces stop there;
// its back emits and reflects nothing). g_camera_ray says which kind is traced now.
bool g_camera_ray = false;

struct Hit {
    float t;     // along the world ray
    int inst;    // -1: nothing
    int tri;     // a mesh's triangle, or -1 for a shape
    vec2 bary;   // the triangle's (u, v)
    vec3 n_obj;  // a shape's object-space normal
    vec2 uv;     // a shape's texture coordinates
};

vec3 apply_rows(int base, vec3 p, float w) {  // rows base..base+2 times (p, w)
    return vec3(dot(instance_texel(base), vec4(p, w)),
                dot(instance_texel(base + 1), vec4(p, w)),
                dot(instance_texel(base + 2), vec4(p, w)));
}

float instance_opacity(int i) {
    return instance_texel(i * INSTANCE_TEXELS + MATERIAL_ROW + REC_PHONG).w;
}

// Whether instance i is opaque for the exact channels: not a transparent Phong material nor
// a glTF BLEND one (transparent whatever its factor's alpha: its texture's varies), as the
// rasterizer's transparent pass takes them (every engine's channels see the nearest opaque
// surface).
bool opaque_instance(int i) {
    int record = i * INSTANCE_TEXELS + MATERIAL_ROW;
    return instance_opacity(i) >= 1.0 &&
           int(instance_texel(record + REC_ALPHA).y) != ALPHA_MODE_BLEND;
}

// Instance i against the ray, in its object space (t keeps its world meaning).
bool hit_instance(int i, vec3 o, vec3 d, inout Hit h, bool any_hit) {
    int base = i * INSTANCE_TEXELS;
    vec4 r0 = instance_texel(base), r1 = instance_texel(base + 1);
    vec4 r2 = instance_texel(base + 2);
    vec3 oo = vec3(dot(r0, vec4(o, 1.0)), dot(r1, vec4(o, 1.0)), dot(r2, vec4(o, 1.0)));
    vec3 od = vec3(dot(r0.xyz, d), dot(r1.xyz, d), dot(r2.xyz, d));
    vec4 info = instance_texel(base + 6);
    int kind = int(info.x);
    bool one_sided = g_camera_ray && (int(info.w) & FLAG_ONE_SIDED) != 0;
#ifdef NO_SHAPES
    if (!trace_mesh(int(info.y), oo, od, h.t, h.tri, h.bary, any_hit, one_sided))
        return false;
#else
#ifdef NO_MESHES
    if (false) {
#else
    if (kind == KIND_MESH) {
#endif
        if (!trace_mesh(int(info.y), oo, od, h.t, h.tri, h.bary, any_hit, one_sided))
            return false;
    } else {
        // out parameters are written back even on a miss: take them only on a hit.
        vec3 n;
        vec2 uv;
        float t = h.t;
        if (!hit_shape(kind, instance_texel(base + 7), oo, od, t, n, uv)) return false;
        if (one_sided && dot(n, od) > 0.0) return false;  // its back, to the camera
        h.t = t;
        h.tri = -1;
        h.n_obj = n;
        h.uv = uv;
    }
#endif
    h.inst = i;
    return true;
}

// The candidates of a ray, one instance at a time: first the instances outside the top
// level ([0, u_unbounded), and u_single = u_unbounded when there is no top level), then the
// leaves of the top level as the ray enters their boxes (tested against the nearest hit so
// far), nearer child first. One loop with one call of hit_instance: every call site of it
// inlines a whole mesh traversal, and on CPU-emulated GL (llvmpipe) each copy costs time
// even where it never runs. WALK(t_max, body) runs body with int i for each candidate;
// the stack (trace/stack.glsl TOP_STACK) holds top-level children: a node index, or a
// leaf -1 - (first | count << 24). Two inner loops, as trace_mesh's: the candidates a lane
// holds, then top-level nodes until it holds more (a turn of one loop paid for a whole
// mesh traversal in every lane). A body ends the walk with ``over_ = true``.
int leaf_entry(float first_ref, float count) {  // (a top-level leaf's texels' w)
    return -1 - (int(-first_ref - 1.0) | int(count) << 24);
}

#define WALK(T_MAX, BODY) {                                                             \
    vec3 inv_ = safe_inverse(d);                                                       \
    TOP_STACK_DECLARE                                                                  \
    bool over_ = false;                                                                \
    int k_ = 0, node_ = u_has_tlas ? 0 : -1;                                           \
    int end_ = u_unbounded + (!u_has_tlas && u_single >= 0 ? 1 : 0);                   \
    do {                                                                               \
        while (k_ < end_) {                                                            \
            int i = k_++;                                                              \
            BODY                                                                       \
        }                                                                              \
        while (k_ >= end_ && !over_ && (node_ >= 0 || !TOP_STACK_EMPTY)) {             \
            if (node_ < 0) {                                                           \
                int e_;                                                                \
                TOP_STACK_POP(e_)                                                      \
                if (e_ >= 0) node_ = e_;                                               \
                else { k_ = (-1 - e_) & 0xFFFFFF; end_ = k_ + ((-1 - e_) >> 24); }     \
                continue;                                                              \
            }                                                                          \
            int b_ = node_ * NODE_TEXELS;                                              \
            vec4 lo0 = tlas_texel(b_), hi0 = tlas_texel(b_ + 1);                       \
            vec4 lo1 = tlas_texel(b_ + 2), hi1 = tlas_texel(b_ + 3);                   \
            float e0 = box_entry(lo0.xyz, hi0.xyz, o, inv_, T_MAX);                    \
            float e1 = box_entry(lo1.xyz, hi1.xyz, o, inv_, T_MAX);                    \
            bool near0 = e0 <= e1;                                                     \
            int ref0 = lo0.w >= 0.0 ? int(lo0.w) : leaf_entry(lo0.w, hi0.w);          \
            int ref1 = lo1.w >= 0.0 ? int(lo1.w) : leaf_entry(lo1.w, hi1.w);          \
            node_ = -1;                                                                \
            if (max(e0, e1) < INF) TOP_STACK_PUSH(near0 ? ref1 : ref0)                 \
            if (min(e0, e1) < INF) TOP_STACK_PUSH(near0 ? ref0 : ref1)                 \
        }                                                                              \
    } while (k_ < end_);                                                               \
}

// The nearest hit of o + t d for t in (0, t_max); ``opaque_only`` skips transparent objects
// (the exact channels describe the nearest opaque surface, as the rasterizer's do).
// ESCAPED: the program of the pixels whose eye rays all miss the scene's bounds
// (facet.render.rays.scene RayScene.draw_colour): nothing is ever hit, so the compiler
// leaves out every traversal and all shading, and such a pixel costs its sky alone.
Hit trace_scene(vec3 o, vec3 d, float t_max, bool opaque_only) {
    Hit h = Hit(t_max, -1, -1, vec2(0.0), vec3(0.0), vec2(0.0));
#ifndef ESCAPED
    WALK(h.t, if (!opaque_only || opaque_instance(i)) hit_instance(i, o, d, h, false);)
#endif
    return h;
}

// An instance shadow rays pass (-1: none): an emitting shape (convex) aimed at a point
// that is its first hit from the ray's start, which a grazing ray from the offset start
// could otherwise find a little sooner (the path tracer's light sampling sets it).
int g_shadow_skip = -1;

// The light that gets through from o along d within t_max: 0 behind an opaque object,
// times (1 - opacity) for each transparent one (as the rasterizer's shadow maps count it).
float trace_shadow(vec3 o, vec3 d, float t_max) {
    float through = 1.0;
#ifndef ESCAPED
    WALK(t_max, {
        Hit h = Hit(t_max, -1, -1, vec2(0.0), vec3(0.0), vec2(0.0));
        if (i != g_shadow_skip && hit_instance(i, o, d, h, true))
            through *= 1.0 - instance_opacity(i);
        if (through <= 0.0) { end_ = k_; over_ = true; }  // (the walk ends)
    })
#endif
    return through;
}
