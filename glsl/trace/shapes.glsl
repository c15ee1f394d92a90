// Exact ray-shape intersections in object space (facet.scene.shapes: y up, centred). Each
// takes the ray o + t d (d not unit: the object-space image of a world ray, so t is the
// world distance's parameter), the nearest distance so far t, and on a nearer hit in (0, t)
// writes t, the outward object-space normal n and texture coordinates uv (those of the
// rasterizer's tessellation, facet.scene.primitives).
const int SHAPE_SPHERE = 1;
const int SHAPE_PLANE = 2;
const int SHAPE_DISK = 3;
const int SHAPE_CYLINDER = 4;
const int SHAPE_CONE = 5;
const int SHAPE_BOX = 6;
const float PI = 3.14159265358979;

vec2 around(vec3 p) {  // u from +x towards -z, as the tessellations
    return vec2(fract(atan(-p.z, p.x) / (2.0 * PI) + 1.0), 0.0);
}

// The roots s0 <= s1 of a s^2 + 2 b s + c = 0 (the notes' quadratic in s); false without.
bool roots(float a, float b, float c, out float s0, out float s1) {
    float disc = b * b - a * c;
    if (disc < 0.0 || a == 0.0) return false;
    float r = sqrt(disc);
    s0 = (-b - r) / a;
    s1 = (-b + r) / a;
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

bool hit_shape(int kind, vec4 q, vec3 o, vec3 d, inout float t, out vec3 n, out vec2 uv) {
    n = vec3(0.0, 1.0, 0.0);
    uv = vec2(0.0);
    float s0, s1;
    if (kind == SHAPE_SPHERE) {  // |o + s d|^2 = r^2: the nearest positive root
        if (!roots(dot(d, d), dot(o, d), dot(o, o) - q.x * q.x, s0, s1)) return false;
        float s = s0 > 0.0 ? s0 : s1;
        if (s <= 0.0 || s >= t) return false;
        t = s;
        vec3 p = o + s * d;
        n = p / q.x;
        uv = vec2(around(p).x, asin(clamp(n.y, -1.0, 1.0)) / PI + 0.5);
        return true;
    }
    if (kind == SHAPE_PLANE) return hit_flat(0.0, 0.0, 0.5 * q.xy, o, d, t, n, uv, 1.0);
    if (kind == SHAPE_DISK) return hit_flat(0.0, q.x, vec2(0.0), o, d, t, n, uv, 1.0);
    if (kind == SHAPE_BOX) {  // slabs
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
    float r = q.x, h = q.y;
    bool hit = false;
    if (kind == SHAPE_CYLINDER || kind == SHAPE_CONE) {
        // Side: x^2 + z^2 = k(y)^2 with k = r (cylinder) or r (h/2 - y) / h (cone, apex up).
        float slope = kind == SHAPE_CONE ? r / h : 0.0;
        float k0 = kind == SHAPE_CONE ? r * 0.5 : r;  // radius at y = 0
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
        if (kind == SHAPE_CYLINDER &&
            hit_flat(0.5 * h, r, vec2(0.0), o, d, t, cap_n, cap_uv, 1.0)) {
            n = cap_n; uv = cap_uv; hit = true;
        }
    }
    return hit;
}
