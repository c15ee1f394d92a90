// The emitters of the path tracer: a point on the emitting triangles and shapes, one
// chosen by power (facet.render.path.emitters), then a point uniformly on it by area; a
// sphere seen from outside by a direction uniformly in the cone it subtends (its visible
// cap: no sample is spent on its hidden half).
#include "trace/shade.glsl"
#include "trace/random.glsl"
#include "lib/sampling.glsl"

uniform sampler2D u_emitters;  // per emitting triangle: (instance, triangle, cumulative
uniform int u_emitter_count;   // share of the emitted power, -), facet.render.path.emitters

// A point uniformly by area on an analytic shape (facet.scene.shapes, object space; y up,
// centred): a sphere, a disk, a finite plane, a box's faces, a cylinder's or a cone's side
// and caps, each part chosen by its share of the area.
vec3 shape_point(int kind, vec4 q, vec2 r) {
    float phi = 2.0 * PI * r.y, pick = random01();
    vec2 ring = vec2(cos(phi), sin(phi));
    if (kind == KIND_SPHERE) {
        float y = 1.0 - 2.0 * r.x, s = sqrt(max(1.0 - y * y, 0.0));
        return q.x * vec3(s * ring.x, y, s * ring.y);
    }
    if (kind == KIND_DISK) return vec3(q.x * sqrt(r.x) * ring.x, 0.0, q.x * sqrt(r.x) * ring.y);
    if (kind == KIND_PLANE) return vec3((r.x - 0.5) * q.x, 0.0, (r.y - 0.5) * q.y);
    float side = random01() < 0.5 ? -0.5 : 0.5;  // which of two opposite faces or caps
    if (kind == KIND_BOX) {
        vec3 a = vec3(q.y * q.z, q.x * q.z, q.x * q.y);  // the faces facing x, y, z
        pick *= a.x + a.y + a.z;
        if (pick < a.x) return vec3(side * q.x, (r.x - 0.5) * q.y, (r.y - 0.5) * q.z);
        if (pick < a.x + a.y) return vec3((r.x - 0.5) * q.x, side * q.y, (r.y - 0.5) * q.z);
        return vec3((r.x - 0.5) * q.x, (r.y - 0.5) * q.y, side * q.z);
    }
    float radius = q.x, h = q.y;
    if (kind == KIND_CYLINDER) {  // side 2 pi r h, caps 2 pi r^2
        if (pick * (h + radius) < h) return vec3(radius * ring.x, (r.x - 0.5) * h, radius * ring.y);
        return vec3(radius * sqrt(r.x) * ring.x, side * h, radius * sqrt(r.x) * ring.y);
    }
    // the cone: side pi r l (density along it grows with the distance from the apex), base
    float l = length(vec2(radius, h));
    if (pick * (l + radius) < l) {
        float t = sqrt(r.x);
        return vec3(radius * t * ring.x, 0.5 * h - h * t, radius * t * ring.y);
    }
    return vec3(radius * sqrt(r.x) * ring.x, -0.5 * h, radius * sqrt(r.x) * ring.y);
}

// The point p_obj of the emitting shape of instance inst as seen from p: the hit where the
// ray from p towards it meets the shape, when that is the point itself (else the shape
// hides it from p: false).
bool shape_hit_at(int inst, vec3 p_obj, vec3 p, out Hit h, out vec3 L, out float dist) {
    int base = inst * INSTANCE_TEXELS;
    vec3 to = apply_rows(base + 3, p_obj, 1.0) - p;
    dist = length(to);
    L = to / max(dist, 1e-20);
    vec3 oo = apply_rows(base, p, 1.0), od = apply_rows(base, L, 0.0);
    float t = dist * 1.001 + 1e-4;
    vec3 n;
    vec2 uv;
    if (!hit_shape(int(instance_texel(base + 6).x), instance_texel(base + 7), oo, od,
                   t, n, uv) || t < dist * 0.999 - 1e-4) return false;
    h = Hit(t, inst, -1, vec2(0.0), n, uv);
    dist = t;
    return true;
}

// A sphere emitter (a shape of instance inst, under a similarity: its emit_pdf > 0) seen
// from p outside it: its world radius r, the axis w from p to its centre, and 1 - cos of
// the half angle of the cone it subtends (false: not a sphere, or p on or inside it,
// where it is sampled by area).
bool sphere_cone(int inst, vec3 p, out float r, out vec3 w, out float one_minus_cos) {
#ifdef NO_SHAPES
    return false;
#endif
    int base = inst * INSTANCE_TEXELS;
    if (int(instance_texel(base + 6).x) != KIND_SPHERE) return false;
    r = instance_texel(base + 7).x
      * length(apply_rows(base + 3, vec3(1.0, 0.0, 0.0), 0.0));
    vec3 to = apply_rows(base + 3, vec3(0.0), 1.0) - p;
    float d2 = dot(to, to), s2 = r * r / d2;  // sin^2 of the half angle
    if (!(s2 < 0.99)) return false;
    w = to * inversesqrt(d2);
    one_minus_cos = s2 / (1.0 + sqrt(1.0 - s2));  // (exact for a far, small sphere)
    return true;
}

// The density in solid angle of sample_emitter's drawing direction d from p to the point
// of emitter instance inst at distance t with geometric normal ng (its area density
// emit_pdf): the emitter's share of the power over its cone for a sphere seen from
// outside (share = emit_pdf x area), else emit_pdf t^2 / |cos|.
float emitter_pdf(int inst, float emit_pdf, vec3 p, vec3 d, float t, vec3 ng) {
    float r, omc;
    vec3 w;
    if (sphere_cone(inst, p, r, w, omc)) return emit_pdf * 2.0 * r * r / omc;  // 4pi r^2 / 2pi
    return emit_pdf * t * t / max(abs(dot(ng, d)), 1e-12);
}

// A point on the emitters for the surface point p: an emitting triangle or shape chosen by
// power (binary search in the cumulative shares), then a point uniformly on it by area.
// Returns the radiance it sends towards p (0 from the back of a one-sided emitter, or
// where the shape hides the point), the direction L and distance to it, the density of L
// in solid angle, and the instance of the shape it chose (-1: a triangle), which the
// shadow ray towards it passes.
// One 2D sample picks the emitter (its x) and the point on it (x rescaled within the
// emitter's share, and y), so a pixel's stratified samples stay stratified over the lamp.
vec3 sample_emitter(vec3 p, out vec3 L, out float dist, out float pdf, out int convex) {
    vec2 xi = sample2(QMC_EMITTER);
    float u = xi.x;
    int lo = 0, hi = u_emitter_count - 1;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (fetch(u_emitters, mid).z > u) hi = mid; else lo = mid + 1;
    }
    vec4 e = fetch(u_emitters, lo);
    float below = lo > 0 ? fetch(u_emitters, lo - 1).z : 0.0;
    // (u is a multiple of 2^-24: a random offset within that step keeps the rescaled
    // number uniform however small the share)
    xi.x = clamp((u - below + random01() * (1.0 / 16777216.0)) / max(e.z - below, 1e-30),
                 0.0, 0.99999994);
    int inst = int(e.x), tri = int(e.y);
    Hit h;
    pdf = 0.0;
    convex = -1;
#ifndef NO_SHAPES
    if (tri < 0) {  // an analytic shape
        int base = inst * INSTANCE_TEXELS;
        float r, omc;
        vec3 w, p_obj;
        if (sphere_cone(inst, p, r, w, omc)) {
            // A direction in its cone and where it meets the sphere: the near side, seen
            // from p by construction (a hit test there fails for rays that graze it: a
            // sample in a few hundred was lost).
            float one_minus = xi.x * omc, sin_t = sqrt(max(one_minus * (2.0 - one_minus), 0.0));
            L = around(vec3(sin_t * cos(TWO_PI * xi.y), sin_t * sin(TWO_PI * xi.y),
                            1.0 - one_minus), w);
            vec3 to = apply_rows(base + 3, vec3(0.0), 1.0) - p;
            float b = dot(L, to);
            dist = b - sqrt(max(b * b - dot(to, to) + r * r, 0.0));
            p_obj = apply_rows(base, p + dist * L, 1.0);
            vec3 n = normalize(p_obj);
            h = Hit(dist, inst, -1, vec2(0.0), n, sphere_uv(p_obj, n));
        } else {
            p_obj = shape_point(int(instance_texel(base + 6).x), instance_texel(base + 7), xi);
            if (!shape_hit_at(inst, p_obj, p, h, L, dist)) return vec3(0.0);
        }
        convex = inst;  // (every shape is convex: nothing of it lies before its first hit)
    } else
#endif
    {
        vec2 b = xi;
        if (b.x + b.y > 1.0) b = 1.0 - b;
        vec3 p_obj = TEXEL(u_tris, 3 * tri).xyz + b.x * TEXEL(u_tris, 3 * tri + 1).xyz
                   + b.y * TEXEL(u_tris, 3 * tri + 2).xyz;
        vec3 to = apply_rows(inst * INSTANCE_TEXELS + 3, p_obj, 1.0) - p;
        dist = length(to);
        L = to / max(dist, 1e-20);
        h = Hit(dist, inst, tri, b, vec3(0.0), vec2(0.0));
    }
    Surface s = surface_at(h, p, L);
    float emit_pdf;
    vec3 emission = emission_at(s.inst, point_of(s), emit_pdf);
    pdf = abs(dot(s.ng, L)) > 0.0 ? emitter_pdf(inst, emit_pdf, p, L, dist, s.ng) : 0.0;
    bool one_sided = (int(instance_texel(inst * INSTANCE_TEXELS + 6).w)
                      & FLAG_ONE_SIDED) != 0;
    return s.front || !one_sided ? emission : vec3(0.0);
}
