// Traversal of the hierarchies (facet.geometry.bvh, packed with both children's boxes in
// each node): the nearer child first, the farther one on a stack; leaves are tested as soon
// as their box is hit, so the nearest hit so far prunes the rest.
#include "trace/data.glsl"
#include "trace/stack.glsl"

// A mesh's primitives are triangles, or (points and lines: facet.render.rays.sprites)
// spheres and capsules, the kind in the first texel's w.
const float PRIM_TRIANGLE = 0.0, PRIM_SPHERE = 1.0, PRIM_CAPSULE = 2.0;

// The nearest root in (0, t) of |o + s d - c|^2 = r^2, the sphere's near side first.
float sphere_root(vec3 c, float r, vec3 o, vec3 d, float t) {
    vec3 oc = o - c;
    float a = dot(d, d), b = dot(oc, d), k = dot(oc, oc) - r * r;
    float disc = b * b - a * k;
    if (disc < 0.0) return INF;
    float s = (-b - sqrt(disc)) / a;
    if (s <= 0.0) s = (-b + sqrt(disc)) / a;
    return s > 0.0 && s < t ? s : INF;
}

// A point (a sphere: centre t0.xyz, radius e1.x) or a line (a capsule from t0.xyz along
// e1 of radius e2.x): its distance in (0, t) and bary = (0, along the line).
bool hit_sprite(vec4 t0, vec3 e1, vec3 e2, vec3 o, vec3 d, inout float t, out vec2 bary) {
    bary = vec2(0.0);
    if (t0.w == PRIM_SPHERE) {
        float s = sphere_root(t0.xyz, e1.x, o, d, t);
        if (s == INF) return false;
        t = s;
        return true;
    }
    // The capsule: the cylinder's side, then the two end caps.
    vec3 a = t0.xyz, ba = e1;
    float r = e2.x, best = INF, along = 0.0;
    float baba = dot(ba, ba);
    vec3 oa = o - a;
    float bard = dot(ba, d), baoa = dot(ba, oa);
    float k2 = baba * dot(d, d) - bard * bard;
    float k1 = baba * dot(oa, d) - baoa * bard;
    float k0 = baba * dot(oa, oa) - baoa * baoa - r * r * baba;
    float h = k1 * k1 - k2 * k0;
    if (k2 != 0.0 && h >= 0.0) {
        float s = (-k1 - sqrt(h)) / k2;
        if (s <= 0.0) s = (-k1 + sqrt(h)) / k2;
        float y = baoa + s * bard;
        if (s > 0.0 && s < t && y > 0.0 && y < baba) { best = s; along = y / baba; }
    }
    float sa = sphere_root(a, r, o, d, min(t, best));
    if (sa < best) { best = sa; along = 0.0; }
    float sb = sphere_root(a + ba, r, o, d, min(t, best));
    if (sb < best) { best = sb; along = 1.0; }
    if (best == INF) return false;
    t = best;
    bary = vec2(0.0, along);
    return true;
}

// Möller-Trumbore: the triangle's (u, v) and distance when o + s d hits it in (0, t);
// ``front_only``: not when the ray meets its back (det < 0: the ray runs along the normal
// cross(e1, e2), which object space keeps whatever the transform's determinant).
bool hit_triangle(int tri, vec3 o, vec3 d, inout float t, out vec2 bary, bool front_only) {
    vec4 t0 = TEXEL(u_tris, 3 * tri);
    vec3 v0 = t0.xyz;
    vec3 e1 = TEXEL(u_tris, 3 * tri + 1).xyz;
    vec3 e2 = TEXEL(u_tris, 3 * tri + 2).xyz;
#ifndef NO_SPRITES
    if (t0.w != PRIM_TRIANGLE) return hit_sprite(t0, e1, e2, o, d, t, bary);
#endif
    vec3 p = cross(d, e2);
    float det = dot(e1, p);
    bary = vec2(0.0);
    if (abs(det) < 1e-30 || (front_only && det < 0.0)) return false;
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

// The mesh hierarchy at node ``root``: its nearest triangle hit in (0, t) (t, tri, bary
// updated), or with ``any_hit`` the first one found; ``front_only``: front faces only (a
// single-sided material). True when something was hit.
// Two inner loops ("while-while", Aila and Laine 2009): inner nodes until each lane holds
// a leaf to test, then those leaves' triangles. llvmpipe runs every line of a loop's body
// for all 8 lanes of a SIMD group whichever branch a lane takes, so one loop with both a
// node step and a triangle test ("if-if") paid for both on every turn; here a turn pays
// for one (the glass and glTF-spheres scenes of benchmarks/pathtrace.py: 10-25% faster).
// The nearer of two inner children is opened next and the farther one waits on the stack.
// Boxes are quantised to 16 bits in the mesh's frame (its header: origin and scale), where
// the ray is carried once: o_q = (o - origin) scale, d_q = d scale keep its parameter t.
// A child's texel: (lo.x | lo.y << 16, lo.z | hi.x << 16, hi.y | hi.z << 16, reference).
const uint LEAF_BIT = 0x80000000u;

void child_box(uvec4 c, out vec3 lo, out vec3 hi) {
    lo = vec3(float(c.x & 0xFFFFu), float(c.x >> 16), float(c.y & 0xFFFFu));
    hi = vec3(float(c.y >> 16), float(c.z & 0xFFFFu), float(c.z >> 16));
}

bool trace_mesh(int root, vec3 o, vec3 d, inout float t, inout int tri, inout vec2 bary,
                bool any_hit, bool front_only) {
    int head = root * MESH_NODE_TEXELS;
    vec3 origin = uintBitsToFloat(TEXEL(u_nodes, head).xyz);
    vec3 scale = uintBitsToFloat(TEXEL(u_nodes, head + 1).xyz);
    vec3 o_q = (o - origin) * scale;
    vec3 inv = safe_inverse(d * scale);
    MESH_STACK_DECLARE
    int node = root + 1;
    int k = 0, end = 0;    // the triangles being tested
    int k2 = 0, end2 = 0;  // a second leaf of the same node, tested next
    bool found = false;
    do {
        // Inner nodes until this lane has a leaf to test (or nothing left).
        while (node >= 0 && k >= end) {
            int base = node * MESH_NODE_TEXELS;
            uvec4 c0 = TEXEL(u_nodes, base), c1 = TEXEL(u_nodes, base + 1);
            vec3 lo0, hi0, lo1, hi1;
            child_box(c0, lo0, hi0);
            child_box(c1, lo1, hi1);
            float e0 = box_entry(lo0, hi0, o_q, inv, t);
            float e1 = box_entry(lo1, hi1, o_q, inv, t);
            int inner0 = -1, inner1 = -1;
            // A leaf: its first primitive and count (LEAF_BIT | count << 24 | first).
            int first0 = int(c0.w & 0xFFFFFFu), n0 = int((c0.w >> 24) & 0x7Fu);
            int first1 = int(c1.w & 0xFFFFFFu), n1 = int((c1.w >> 24) & 0x7Fu);
            if (e0 < INF) {
                if ((c0.w & LEAF_BIT) == 0u) inner0 = int(c0.w);
                else { k = first0; end = first0 + n0; }
            }
            if (e1 < INF) {
                if ((c1.w & LEAF_BIT) == 0u) inner1 = int(c1.w);
                else if (k >= end) { k = first1; end = first1 + n1; }
                else { k2 = first1; end2 = first1 + n1; }
            }
            if (inner0 >= 0 && inner1 >= 0) {
                bool near0 = e0 <= e1;
                MESH_STACK_PUSH(near0 ? inner1 : inner0)
                node = near0 ? inner0 : inner1;
            } else if (inner0 >= 0 || inner1 >= 0) {
                node = max(inner0, inner1);
            } else {
                MESH_STACK_POP(node)
            }
        }
        // Then its leaves' triangles.
        while (k < end) {
            vec2 b;
            if (hit_triangle(k, o, d, t, b, front_only)) {
                tri = k;
                bary = b;
                found = true;
                if (any_hit) return true;
            }
            ++k;
            if (k >= end && k2 < end2) { k = k2; end = end2; end2 = 0; }
        }
    } while (node >= 0);
    return found;
}
