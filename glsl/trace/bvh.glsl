// Traversal of the hierarchies (facet.geometry.bvh, packed with both children's boxes in
// each node): the nearer child first, the farther one on a stack; leaves are tested as soon
// as their box is hit, so the nearest hit so far prunes the rest.
#include "trace/data.glsl"

const int STACK_SIZE = 48;  // deeper than any hierarchy facet builds (about 30 levels)

// Möller-Trumbore: the triangle's (u, v) and distance when o + s d hits it in (0, t).
bool hit_triangle(int tri, vec3 o, vec3 d, inout float t, out vec2 bary) {
    vec3 v0 = fetch(u_tris, 3 * tri).xyz;
    vec3 e1 = fetch(u_tris, 3 * tri + 1).xyz;
    vec3 e2 = fetch(u_tris, 3 * tri + 2).xyz;
    vec3 p = cross(d, e2);
    float det = dot(e1, p);
    bary = vec2(0.0);
    if (abs(det) < 1e-30) return false;
    float inv = 1.0 / det;
    vec3 s = o - v0;
    float u = dot(s, p) * inv;
    vec3 q = cross(s, e1);
    float v = dot(d, q) * inv;
    float dist = dot(e2, q) * inv;
    if (u < 0.0 || v < 0.0 || u + v > 1.0 || dist <= 0.0 || dist >= t) return false;
    t = dist;
    bary = vec2(u, v);
    return true;
}

// One child of a node: its entry distance (INF when missed); a leaf's triangles are tested
// at once (``found`` and t, tri, bary updated), an inner child's index goes to ``inner``.
void visit_child(vec4 lo, vec4 hi, vec3 o, vec3 d, vec3 inv, inout float t, inout int tri,
                 inout vec2 bary, inout bool found, out float entry, out int inner) {
    entry = box_entry(lo.xyz, hi.xyz, o, inv, t);
    inner = -1;
    if (entry >= INF) return;
    if (lo.w >= 0.0) {
        inner = int(lo.w);
        return;
    }
    int first = int(-lo.w) - 1;
    int last = first + int(hi.w);
    for (int k = first; k < last; ++k) {
        vec2 b;
        if (hit_triangle(k, o, d, t, b)) {
            tri = k;
            bary = b;
            found = true;
        }
    }
}

// The mesh hierarchy at node ``root``: its nearest triangle hit in (0, t) (t, tri, bary
// updated), or with ``any_hit`` the first one found. True when something was hit.
bool trace_mesh(int root, vec3 o, vec3 d, inout float t, inout int tri, inout vec2 bary,
                bool any_hit) {
    vec3 inv = safe_inverse(d);
    int stack[STACK_SIZE];
    int sp = 0;
    int node = root;
    bool found = false;
    while (node >= 0) {
        int base = node * NODE_TEXELS;
        float entry_l, entry_r;
        int inner_l, inner_r;
        visit_child(fetch(u_nodes, base), fetch(u_nodes, base + 1), o, d, inv, t, tri, bary,
                    found, entry_l, inner_l);
        visit_child(fetch(u_nodes, base + 2), fetch(u_nodes, base + 3), o, d, inv, t, tri,
                    bary, found, entry_r, inner_r);
        if (found && any_hit) return true;
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
    return found;
}
