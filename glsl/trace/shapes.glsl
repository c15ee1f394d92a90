// Exact ray-shape intersections in object space (facet.scene.shapes: y up, centred). Each
// takes the ray o + t d (d not unit: the object-space image of a world ray, so t is the
// world distance's parameter), the nearest distance so far t, and on a nearer hit in (0, t)
// writes t, the outward object-space normal n and texture coordinates uv (those of the
// rasterizer's tessellation, facet.scene.primitives).
#include "lib/constants.glsl"

vec2 around(vec3 p) {  // u from +x towards -z, as the tessellations
    return vec2(fract(atan(-p.z, p.x) / (2.0 * PI) + 1.0), 0.0);
}

// The roots s0 <= s1 of a s^2 + 2 b s + c = 0 (the notes' quadratic in s); false without.
// In the cancellation-free form: q = -(b + sign(b) sqrt(b^2 - a c)), roots q / a and c / q.
// The textbook (-b -+ sqrt) / a loses the small root to cancellation where |a c| << b^2
// (a ray leaving a surface, or grazing a cone's side), and a lost root is a false hit:
// shadow acne.
bool roots(float a, float b, float c, out float s0, out float s1) {
    float disc = b * b - a * c;
    if (disc < 0.0) return false;
    float q = -(b + (b < 0.0 ? -sqrt(disc) : sqrt(disc)));
    if (q == 0.0) {  // b = 0 and a c = 0
        if (a == 0.0) return false;
        s0 = s1 = 0.0;
        return true;
    }
    s0 = a != 0.0 ? q / a : c / q;  // a = 0: one root (a line along a cone's generator)
    s1 = c / q;
    if (s0 > s1) { float tmp = s0; s0 = s1; s1 = tmp; }
    return true;
}

// A disk or rectangle in the plane y = h facing +y or -y (caps, planes): radius > 0 is a
// disk, else half sizes (w, d) (INF for the infinite plane).
bool hit_flat(float h, float radius, vec2 half_size, vec3 o, vec3 d, inout float t,
              out vec3 n, out vec2 uv, float facing) {
    if (d.y == 0.0) return false;
    float s = (h - o.y) / d.y;
    if (s <= 0.0 || s >= t) return false;
    vec3 p = o + s * d;
    if (radius > 0.0 ? dot(p.xz, p.xz) > radius * radius
                     : any(greaterThan(abs(p.xz), half_size))) return false;
    t = s;
    n = vec3(0.0, facing, 0.0);
    uv = radius > 0.0 ? vec2(around(p).x, 0.5)  // the tessellated cap's lathe coordinates
                      : vec2(p.x / (2.0 * half_size.x) + 0.5, 0.5 - p.z / (2.0 * half_size.y));
    return true;
}

// The texture coordinates of point p (normal n) of a sphere centred at the origin.
vec2 sphere_uv(vec3 p, vec3 n) {
    return vec2(around(p).x, asin(clamp(n.y, -1.0, 1.0)) / PI + 0.5);
}

bool hit_shape(int kind, vec4 q, vec3 o, vec3 d, inout float t, out vec3 n, out vec2 uv) {
    n = vec3(0.0, 1.0, 0.0);
    uv = vec2(0.0);
    float s0, s1;
    // (NO_KIND_*: a kind no object of the scene has, its test left out: scene_defines)
#ifndef NO_KIND_SPHERE
    if (kind == KIND_SPHERE) {  // |o + s d|^2 = r^2: the nearest positive root
        if (!roots(dot(d, d), dot(o, d), dot(o, o) - q.x * q.x, s0, s1)) return false;
        float s = s0 > 0.0 ? s0 : s1;
        if (s <= 0.0 || s >= t) return false;
        t = s;
        vec3 p = o + s * d;
        n = p / q.x;
        uv = sphere_uv(p, n);
        return true;
    }
#endif
#ifndef NO_KIND_PLANE
    if (kind == KIND_PLANE) return hit_flat(0.0, 0.0, 0.5 * q.xy, o, d, t, n, uv, 1.0);
#endif
#ifndef NO_KIND_DISK
    if (kind == KIND_DISK) return hit_flat(0.0, q.x, vec2(0.0), o, d, t, n, uv, 1.0);
#endif
#ifndef NO_KIND_BOX
    if (kind == KIND_BOX) {  // slabs
        vec3 half_size = 0.5 * q.xyz;
        vec3 inv = safe_inverse(d);
        vec3 t0 = (-half_size - o) * inv, t1 = (half_size - o) * inv;
        vec3 near3 = min(t0, t1), far3 = max(t0, t1);
        float near = max(max(near3.x, near3.y), near3.z);
        float far = min(min(far3.x, far3.y), far3.z);
        if (near > far || far <= 0.0) return false;
        float s = near > 0.0 ? near : far;  // from inside: the exit
        if (s >= t) return false;
        vec3 axis = near > 0.0 ? step(vec3(near), near3) : step(far3, vec3(far));
        axis = axis.x > 0.0 ? vec3(1, 0, 0) : axis.y > 0.0 ? vec3(0, 1, 0) : vec3(0, 0, 1);
        vec3 p = o + s * d;
        t = s;
        n = axis * sign(p);
        // Each face spans [0, 1]^2 along its two other axes (facet.scene.primitives.cube).
        vec3 f = p / (2.0 * half_size) + 0.5;
        uv = axis.x > 0.0 ? f.yz : axis.y > 0.0 ? f.zx : f.xy;
        return true;
    }
#endif
    float r = q.x, h = q.y;
    bool hit = false;
#if !defined(NO_KIND_CYLINDER) || !defined(NO_KIND_CONE)
    if (kind == KIND_CYLINDER || kind == KIND_CONE) {
        // Side: x^2 + z^2 = k(y)^2 with k = r (cylinder) or r (h/2 - y) / h (cone, apex up).
        float slope = kind == KIND_CONE ? r / h : 0.0;
        float k0 = kind == KIND_CONE ? r * 0.5 : r;  // radius at y = 0
        float ky = k0 - slope * o.y, kd = -slope * d.y;
        float a = d.x * d.x + d.z * d.z - kd * kd;
        float b = o.x * d.x + o.z * d.z - ky * kd;
        float c = o.x * o.x + o.z * o.z - ky * ky;
        if (roots(a, b, c, s0, s1)) {  // the nearer root on the finite side wins
            vec3 p0 = o + s0 * d, p1 = o + s1 * d;
            bool ok0 = s0 > 0.0 && s0 < t && abs(p0.y) <= 0.5 * h;
            bool ok1 = s1 > 0.0 && s1 < t && abs(p1.y) <= 0.5 * h;
            if (ok0 || ok1) {
                float s = ok0 ? s0 : s1;
                vec3 p = ok0 ? p0 : p1;
                t = s;
                n = normalize(vec3(p.x, slope * length(p.xz), p.z));
                uv = vec2(around(p).x, p.y / h + 0.5);
                hit = true;
            }
        }
        vec3 cap_n;
        vec2 cap_uv;
        if (hit_flat(-0.5 * h, r, vec2(0.0), o, d, t, cap_n, cap_uv, -1.0)) {
            n = cap_n; uv = cap_uv; hit = true;
        }
        if (kind == KIND_CYLINDER &&
            hit_flat(0.5 * h, r, vec2(0.0), o, d, t, cap_n, cap_uv, 1.0)) {
            n = cap_n; uv = cap_uv; hit = true;
        }
    }
#endif
    return hit;
}

// Point p, near the surface of a shape whose outward normal there is n (what hit_shape
// gave), moved onto that surface. A hit point o + t d carries the error of its root, and
// where a ray passes near a cone's apex (its two nappes give nearly equal roots) that
// error is far more than the offset a spawned ray starts with: the ray would start inside
// and shadow its own surface. On the surface, a point's error is a few ulps (offset_ray's).
vec3 onto_shape(int kind, vec4 q, vec3 p, vec3 n) {
    if (kind == KIND_SPHERE) return p * (q.x / max(length(p), 1e-30));
    if (kind == KIND_PLANE || kind == KIND_DISK) return vec3(p.x, 0.0, p.z);
    if (kind == KIND_BOX) {  // the face the normal names
        vec3 half_size = 0.5 * q.xyz;
        return mix(p, sign(n) * half_size, abs(n));
    }
    float r = q.x, h = q.y;
    if (abs(n.y) == 1.0) return vec3(p.x, 0.5 * h * n.y, p.z);  // a cap
    float rho = length(p.xz);
    if (rho == 0.0) return p;
    if (kind == KIND_CYLINDER) return vec3(p.x * r / rho, p.y, p.z * r / rho);
    // The cone's side in the (rho, y) half-plane: the line rho = r (h/2 - y) / h, through
    // (r/2, 0) with direction (-r, h) / |(-r, h)|; p goes to its nearest point on it.
    vec2 u = vec2(-r, h) / length(vec2(r, h));
    vec2 on = vec2(0.5 * r, 0.0) + dot(vec2(rho - 0.5 * r, p.y), u) * u;
    return vec3(p.x * on.x / rho, on.y, p.z * on.x / rho);
}

// The tangent frame of a shape at its surface point p with outward normal n, as the
// rasterizer's tessellation has it (tangents from its uvs): T = dp/du, with the handedness
// w that turns cross(n, T) w along dp/dv; 0 where the uvs give no frame (the caps and
// disks, whose v is constant, and a sphere's poles).
vec4 shape_tangent(int kind, vec3 p, vec3 n) {
    vec3 T, B;
    if (kind == KIND_PLANE) {  // u along +x, v along -z
        T = vec3(1.0, 0.0, 0.0);
        B = vec3(0.0, 0.0, -1.0);
    } else if (kind == KIND_BOX) {  // each face: its two other axes (hit_shape's uv)
        vec3 a = abs(n);
        if (a.x > 0.5) { T = vec3(0.0, 1.0, 0.0); B = vec3(0.0, 0.0, 1.0); }
        else if (a.y > 0.5) { T = vec3(0.0, 0.0, 1.0); B = vec3(1.0, 0.0, 0.0); }
        else { T = vec3(1.0, 0.0, 0.0); B = vec3(0.0, 1.0, 0.0); }
    } else if (kind == KIND_DISK || abs(n.y) == 1.0) {
        return vec4(0.0);
    } else {  // a sphere's, cylinder's or cone's side: u around from +x towards -z, v up
        T = vec3(p.z, 0.0, -p.x);
        B = vec3(0.0, 1.0, 0.0) - n * n.y;
    }
    T -= n * dot(n, T);
    if (dot(T, T) < 1e-12 || dot(B, B) < 1e-12) return vec4(0.0);
    T = normalize(T);
    return vec4(T, dot(cross(n, T), B) < 0.0 ? -1.0 : 1.0);
}
