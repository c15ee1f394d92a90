// Placed objects (instances) and the top level over them; hits and the surfaces they give.
// An instance is INSTANCE_TEXELS texels (facet.render.trace.pack):
//   0-2  world -> object rows          3-5  object -> world rows
//   6    (kind, mesh root node, object id, 1 if the mesh has vertex colours)
//   7    shape parameters              8    material (C rgb, k_a)
//   9    (k_d, k_s, shininess, opacity)  10 (reflectivity, ior, gloss, texture layer or -1)
#include "trace/bvh.glsl"
#include "trace/shapes.glsl"

const int INSTANCE_TEXELS = 11;
const int KIND_MESH = 0;

struct Hit {
    float t;     // along the world ray
    int inst;    // -1: nothing
    int tri;     // a mesh's triangle, or -1 for a shape
    vec2 bary;   // the triangle's (u, v)
    vec3 n_obj;  // a shape's object-space normal
    vec2 uv;     // a shape's texture coordinates
};

vec3 apply_rows(int base, vec3 p, float w) {  // rows base..base+2 times (p, w)
    return vec3(dot(fetch(u_instances, base), vec4(p, w)),
                dot(fetch(u_instances, base + 1), vec4(p, w)),
                dot(fetch(u_instances, base + 2), vec4(p, w)));
}

float instance_opacity(int i) {
    return fetch(u_instances, i * INSTANCE_TEXELS + 9).w;
}

// Instance i against the ray, in its object space (t keeps its world meaning).
bool hit_instance(int i, vec3 o, vec3 d, inout Hit h, bool any_hit) {
    int base = i * INSTANCE_TEXELS;
    vec4 r0 = fetch(u_instances, base), r1 = fetch(u_instances, base + 1);
    vec4 r2 = fetch(u_instances, base + 2);
    vec3 oo = vec3(dot(r0, vec4(o, 1.0)), dot(r1, vec4(o, 1.0)), dot(r2, vec4(o, 1.0)));
    vec3 od = vec3(dot(r0.xyz, d), dot(r1.xyz, d), dot(r2.xyz, d));
    vec4 info = fetch(u_instances, base + 6);
    int kind = int(info.x);
    if (kind == KIND_MESH) {
        if (!trace_mesh(int(info.y), oo, od, h.t, h.tri, h.bary, any_hit)) return false;
    } else {
        // out parameters are written back even on a miss: take them only on a hit.
        vec3 n;
        vec2 uv;
        if (!hit_shape(kind, fetch(u_instances, base + 7), oo, od, h.t, n, uv)) return false;
        h.tri = -1;
        h.n_obj = n;
        h.uv = uv;
    }
    h.inst = i;
    return true;
}

float h_entry;  // the entry distance of the last tlas_child (a second result)

// Child c of top-level node ``node``: its instances are tested when it is a leaf; returns
// the index of an inner child whose box the ray enters (else -1), its entry in h_entry.
int tlas_child(int node, int c, vec3 o, vec3 d, vec3 inv, inout Hit h, bool opaque_only) {
    vec4 lo = fetch(u_tlas, node * NODE_TEXELS + 2 * c);
    vec4 hi = fetch(u_tlas, node * NODE_TEXELS + 2 * c + 1);
    h_entry = box_entry(lo.xyz, hi.xyz, o, inv, h.t);
    if (h_entry >= INF) return -1;
    if (lo.w >= 0.0) return int(lo.w);
    int first = int(-lo.w) - 1;
    for (int k = first; k < first + int(hi.w); ++k) {
        if (!opaque_only || instance_opacity(k) >= 1.0) hit_instance(k, o, d, h, false);
    }
    return -1;
}

// The nearest hit of o + t d for t in (0, t_max); ``opaque_only`` skips transparent objects
// (the exact channels describe the nearest opaque surface, as the rasterizer's do).
Hit trace_scene(vec3 o, vec3 d, float t_max, bool opaque_only) {
    Hit h = Hit(t_max, -1, -1, vec2(0.0), vec3(0.0), vec2(0.0));
    for (int i = 0; i < u_unbounded; ++i) {
        if (!opaque_only || instance_opacity(i) >= 1.0) hit_instance(i, o, d, h, false);
    }
    if (!u_has_tlas) {  // one placed object: no top level to walk
        if (u_single >= 0 && (!opaque_only || instance_opacity(u_single) >= 1.0))
            hit_instance(u_single, o, d, h, false);
        return h;
    }
    vec3 inv = safe_inverse(d);
    int stack[STACK_SIZE];
    int sp = 0;
    int node = 0;
    while (node >= 0) {
        int inner_l = tlas_child(node, 0, o, d, inv, h, opaque_only);
        float entry_l = h_entry;
        int inner_r = tlas_child(node, 1, o, d, inv, h, opaque_only);
        float entry_r = h_entry;
        if (inner_l >= 0 && inner_r >= 0) {
            bool left_first = entry_l <= entry_r;
            if (sp < STACK_SIZE) stack[sp++] = left_first ? inner_r : inner_l;
            node = left_first ? inner_l : inner_r;
        } else if (inner_l >= 0 || inner_r >= 0) {
            node = max(inner_l, inner_r);
        } else {
            node = sp > 0 ? stack[--sp] : -1;
        }
    }
    return h;
}

// The light that gets through from o along d within t_max: 0 behind an opaque object,
// times (1 - opacity) for each transparent one (as the rasterizer's shadow maps count it).
float trace_shadow(vec3 o, vec3 d, float t_max) {
    float through = 1.0;
    if (!u_has_tlas && u_single >= 0) {
        Hit h = Hit(t_max, -1, -1, vec2(0.0), vec3(0.0), vec2(0.0));
        if (hit_instance(u_single, o, d, h, true)) through *= 1.0 - instance_opacity(u_single);
    }
    for (int i = 0; i < u_unbounded + (u_has_tlas ? 1 : 0); ++i) {
        // Unbounded instances first, then the top level (one more pass of this loop).
        if (i < u_unbounded) {
            Hit h = Hit(t_max, -1, -1, vec2(0.0), vec3(0.0), vec2(0.0));
            if (hit_instance(i, o, d, h, true)) through *= 1.0 - instance_opacity(i);
            continue;
        }
        vec3 inv = safe_inverse(d);
        int stack[STACK_SIZE];
        int sp = 0;
        int node = 0;
        while (node >= 0 && through > 0.0) {
            int inner[2];
            for (int c = 0; c < 2; ++c) {
                vec4 lo = fetch(u_tlas, node * NODE_TEXELS + 2 * c);
                vec4 hi = fetch(u_tlas, node * NODE_TEXELS + 2 * c + 1);
                bool hit_box = box_entry(lo.xyz, hi.xyz, o, inv, t_max) < INF;
                inner[c] = hit_box && lo.w >= 0.0 ? int(lo.w) : -1;
                if (!hit_box || lo.w >= 0.0) continue;
                int first = int(-lo.w) - 1;
                for (int k = 0; k < int(hi.w); ++k) {
                    Hit h = Hit(t_max, -1, -1, vec2(0.0), vec3(0.0), vec2(0.0));
                    if (hit_instance(first + k, o, d, h, true))
                        through *= 1.0 - instance_opacity(first + k);
                }
            }
            if (inner[0] >= 0 && inner[1] >= 0 && sp < STACK_SIZE) stack[sp++] = inner[1];
            node = inner[0] >= 0 ? inner[0] : inner[1] >= 0 ? inner[1]
                 : sp > 0 ? stack[--sp] : -1;
        }
    }
    return through;
}
