"""numpy oracles computed from the equations, independent of facet's GL code.

Pixel centres: pixel (row j, column i) of a W x H image (row 0 at the top) sits at NDC
x = 2 (i + 0.5) / W - 1, y = 1 - 2 (j + 0.5) / H. Rays are unprojected through inv(P V).
"""

from __future__ import annotations

import numpy as np


def pixel_rays(view: np.ndarray, proj: np.ndarray, width: int, height: int):
    """World-space ray origins and unit directions through every pixel centre, (H, W, 3)."""
    i, j = np.meshgrid(np.arange(width), np.arange(height))
    x = 2.0 * (i + 0.5) / width - 1.0
    y = 1.0 - 2.0 * (j + 0.5) / height
    inv = np.linalg.inv(proj @ view)

    def unproject(z):
        ndc = np.stack([x, y, np.full_like(x, z, dtype=float), np.ones_like(x, dtype=float)], -1)
        p = ndc @ inv.T
        return p[..., :3] / p[..., 3:]

    near, far = unproject(-1.0), unproject(1.0)
    d = far - near
    return near, d / np.linalg.norm(d, axis=-1, keepdims=True)


def ray_sphere(origins, dirs, center, radius):
    """Nearest hit distance t along each ray (inf where missed), (H, W)."""
    oc = origins - np.asarray(center, dtype=float)
    b = np.sum(oc * dirs, axis=-1)
    c = np.sum(oc * oc, axis=-1) - radius**2
    disc = b * b - c
    t = np.full(disc.shape, np.inf)
    hit = disc >= 0
    t0 = -b[hit] - np.sqrt(disc[hit])
    t[hit] = np.where(t0 > 0, t0, np.inf)
    return t


def linear_depth(view, points):
    """Distance along the camera axis (-z in view space) of world points (..., 3)."""
    return -(points @ view[:3, :3].T + view[:3, 3])[..., 2]


def phong(points, normals, to_eye, color, material, lights, ambient, blinn=False,
          clamp=True):
    """The notes' shading equation at world points (H, W, 3), clamped to [0, 1] (unless
    ``clamp`` is False: the local colour a reflective surface shares with its reflection).

    I = I_a k_a C + sum_i I_i (k_d C max(N.L, 0) + k_s max(R.V, 0)^n), specular only where
    N.L > 0. ``lights``: facet light objects; point/spot attenuation 1 / (c + l d + q d^2).
    """
    C = np.asarray(color, dtype=float)
    out = np.asarray(ambient, dtype=float) * material.ka * C * np.ones_like(points)
    for light in lights:
        kind = type(light).__name__
        intensity = np.asarray(light.color) * light.intensity
        if kind == "DirectionalLight":
            L = np.broadcast_to(-np.asarray(light.direction), points.shape)
            falloff = np.ones(points.shape[:-1])
        else:
            to_light = np.asarray(light.position) - points
            d = np.linalg.norm(to_light, axis=-1)
            L = to_light / d[..., None]
            c, lin, q = light.attenuation
            falloff = 1.0 / (c + lin * d + q * d * d)
            if kind == "SpotLight":
                cos = np.sum(-L * np.asarray(light.direction), axis=-1)
                lo = np.cos(np.radians(light.outer_angle))
                hi = np.cos(np.radians(light.inner_angle))
                s = np.clip((cos - lo) / (hi - lo), 0, 1)
                falloff = falloff * s * s * (3 - 2 * s)
        n_dot_l = np.sum(normals * L, axis=-1)
        lit = n_dot_l > 0
        if blinn:
            H = L + to_eye
            H /= np.linalg.norm(H, axis=-1, keepdims=True)
            spec_base = np.sum(normals * H, axis=-1)
        else:
            R = 2 * n_dot_l[..., None] * normals - L
            spec_base = np.sum(R * to_eye, axis=-1)
        spec = np.maximum(spec_base, 0) ** material.shininess
        term = material.kd * C * np.maximum(n_dot_l, 0)[..., None] + material.ks * spec[..., None]
        out = out + np.where(lit[..., None], intensity * falloff[..., None] * term, 0.0)
    return np.clip(out, 0.0, 1.0) if clamp else out


def sphere_reference(camera, width, height, center, radius, material, lights, ambient,
                     blinn=False):
    """Exact colour (H, W, 3) floats, mask (H, W) and depth (H, W) of a sphere."""
    view, proj = camera.view, camera.projection(width, height)
    origins, dirs = pixel_rays(view, proj, width, height)
    t = ray_sphere(origins, dirs, center, radius)
    mask = np.isfinite(t)
    points = origins + np.where(mask, t, 0)[..., None] * dirs
    normals = (points - np.asarray(center)) / radius
    to_eye = -dirs  # towards the eye along the pixel's ray: right for both projections
    rgb = phong(points, normals, to_eye, material.color, material, lights, ambient, blinn)
    depth = np.where(mask, linear_depth(view, points), 0.0)
    return rgb, mask, depth


def erode(mask: np.ndarray, pixels: int) -> np.ndarray:
    """Binary erosion by a (2 pixels + 1)^2 square: keeps only pixels far from any edge."""
    out = mask.copy()
    for _ in range(pixels):
        m = out.copy()
        m[1:] &= out[:-1]
        m[:-1] &= out[1:]
        m[:, 1:] &= out[:, :-1]
        m[:, :-1] &= out[:, 1:]
        out = m
    return out


def iou(a: np.ndarray, b: np.ndarray) -> float:
    return float((a & b).sum() / max((a | b).sum(), 1))


def object_rays(origins, dirs, transform):
    """World rays in the object space of ``transform`` (object -> world): o', d' with the
    same parameter t (d' not normalised)."""
    inv = np.linalg.inv(np.asarray(transform, dtype=float))
    return origins @ inv[:3, :3].T + inv[:3, 3], dirs @ inv[:3, :3].T


def _first_root(a, b, c, valid):
    """Smallest root s > 0 of a s^2 + 2 b s + c = 0 passing ``valid(s)``, else inf."""
    disc = b * b - a * c
    ok = (disc >= 0) & (a != 0)
    r = np.sqrt(np.where(ok, disc, 0.0))
    safe_a = np.where(a != 0, a, 1.0)
    s = np.sort(np.stack([(-b - r) / safe_a, (-b + r) / safe_a]), axis=0)
    out = np.full(a.shape, np.inf)
    for root in s[::-1]:  # the smaller root wins when both are valid
        good = ok & (root > 0) & valid(root)
        out = np.where(good, root, out)
    return out


def ray_cone(o, d, radius, height):
    """The notes' right circular cone (apex up at y = h/2, base radius r at -h/2) with its
    base disc: nearest t per ray (object space), inf where missed."""
    slope, k0 = radius / height, radius / 2.0
    ky, kd = k0 - slope * o[..., 1], -slope * d[..., 1]
    a = d[..., 0] ** 2 + d[..., 2] ** 2 - kd ** 2
    b = o[..., 0] * d[..., 0] + o[..., 2] * d[..., 2] - ky * kd
    c = o[..., 0] ** 2 + o[..., 2] ** 2 - ky ** 2
    side = _first_root(a, b, c, lambda s: np.abs(o[..., 1] + s * d[..., 1]) <= height / 2)
    return np.minimum(side, ray_disk(o, d, radius, -height / 2))


def ray_cylinder(o, d, radius, height):
    a = d[..., 0] ** 2 + d[..., 2] ** 2
    b = o[..., 0] * d[..., 0] + o[..., 2] * d[..., 2]
    c = o[..., 0] ** 2 + o[..., 2] ** 2 - radius ** 2
    side = _first_root(a, b, c, lambda s: np.abs(o[..., 1] + s * d[..., 1]) <= height / 2)
    caps = np.minimum(ray_disk(o, d, radius, height / 2), ray_disk(o, d, radius, -height / 2))
    return np.minimum(side, caps)


def ray_disk(o, d, radius, y=0.0, half=None):
    """The plane y = const within a disc of ``radius`` (or a rectangle of half sizes)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (y - o[..., 1]) / d[..., 1]
    p = o + s[..., None] * d
    inside = (p[..., 0] ** 2 + p[..., 2] ** 2 <= radius ** 2) if half is None else \
        (np.abs(p[..., 0]) <= half[0]) & (np.abs(p[..., 2]) <= half[1])
    return np.where(np.isfinite(s) & (s > 0) & inside, s, np.inf)


def ray_box(o, d, size):
    half = np.asarray(size, dtype=float) / 2
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (-half - o) / d, (half - o) / d
    near = np.nanmax(np.minimum(t0, t1), axis=-1)
    far = np.nanmin(np.maximum(t0, t1), axis=-1)
    return np.where((near <= far) & (near > 0), near, np.inf)


def ray_sphere_object(o, d, radius):
    """|o + s d| = r for rays with any direction length (object space)."""
    a = np.sum(d * d, axis=-1)
    return _first_root(a, np.sum(o * d, axis=-1), np.sum(o * o, axis=-1) - radius ** 2,
                       lambda s: np.ones(s.shape, bool))


# -- glTF 2.0 metallic-roughness (the specification's Appendix B) ---------------------------
def _pbr_brdf_cos(N, V, L, base, metallic, roughness):
    """pi f(L, V) (N.L) per element: what a light of intensity 1 adds (facet.scene.pbr's
    convention: intensity I gives irradiance pi I). Arrays broadcast over (..., 3)."""
    base = np.asarray(base, dtype=float)
    nl = np.sum(N * L, -1)
    nv = np.maximum(np.sum(N * V, -1), 1e-4)
    H = L + V
    H = H / np.maximum(np.linalg.norm(H, axis=-1, keepdims=True), 1e-300)
    nh = np.maximum(np.sum(N * H, -1), 0.0)
    vh = np.maximum(np.sum(V * H, -1), 0.0)
    a = max(roughness * roughness, 1e-3)
    a2 = a * a
    d = a2 / (np.pi * (nh * nh * (a2 - 1) + 1) ** 2)
    g = nl * np.sqrt(nv * nv * (1 - a2) + a2) + nv * np.sqrt(nl * nl * (1 - a2) + a2)
    vis = np.where(g > 0, 0.5 / np.where(g > 0, g, 1), 0.0)
    spec = (d * vis)[..., None]
    fc = ((1 - vh) ** 5)[..., None]
    f_dielectric = 0.04 + 0.96 * fc
    f_metal = base + (1 - base) * fc
    # The lobe's multiple-scattering scale 1 + F0 (1 - E) / E (lib/pbr.glsl), E the lobe's
    # albedo with F = 1 at this N.V, integrated here (facet tabulates it).
    f0 = 0.04 * (1 - metallic) + base * metallic
    spec = spec * (1 + f0 * (1 / ggx_albedo(nv, roughness)[..., None] - 1))
    dielectric = f_dielectric * spec + (1 - f_dielectric) * base / np.pi
    metal = f_metal * spec
    f = (1 - metallic) * dielectric + metallic * metal
    return np.where((nl > 0)[..., None], np.pi * f * np.maximum(nl, 0)[..., None], 0.0)


def ggx_albedo(n_dot_v, roughness, steps=200):
    """E = int D Vis cos dw (F = 1) of the GGX lobe, per element of ``n_dot_v``: by midpoint
    quadrature in (cos theta, phi) at 48 angles, interpolated linearly in N.V."""
    key = (float(roughness), steps)
    if key not in _ALBEDO:
        a2 = max(roughness * roughness, 1e-3) ** 2
        ct = (np.arange(steps) + 0.5) / steps
        ph = (np.arange(2 * steps) + 0.5) / (2 * steps) * 2 * np.pi
        ct, ph = np.meshgrid(ct, ph, indexing="ij")
        st = np.sqrt(1 - ct * ct)
        grid = np.linspace(1e-4, 1.0, 48)
        values = []
        for nv in grid:
            v = np.array([np.sqrt(1 - nv * nv), 0.0, nv])
            h = np.stack([st * np.cos(ph) + v[0], st * np.sin(ph), ct + v[2]], -1)
            nh = h[..., 2] / np.linalg.norm(h, axis=-1)
            d = a2 / (np.pi * (nh * nh * (a2 - 1) + 1) ** 2)
            g = ct * np.sqrt(nv * nv * (1 - a2) + a2) + nv * np.sqrt(ct * ct * (1 - a2) + a2)
            values.append((d * 0.5 / g * ct).sum() / steps * (2 * np.pi / (2 * steps)))
        _ALBEDO[key] = (grid, np.array(values))
    grid, values = _ALBEDO[key]
    return np.interp(np.asarray(n_dot_v, dtype=float), grid, values)


_ALBEDO: dict = {}


def pbr_directional(N, V, direction, intensity, base, metallic, roughness):
    """Linear radiance (..., 3) of surfaces with normals N seen from V under one directional
    light travelling along ``direction`` with intensity (3,)."""
    L = -np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    L = np.broadcast_to(L, N.shape)
    return _pbr_brdf_cos(N, V, L, base, metallic, roughness) * np.asarray(intensity)


def pbr_uniform_environment(n_dot_v, base, metallic, roughness, radiance=1.0, steps=400):
    """Linear radiance (len(n_dot_v), 3) reflected towards V at angle acos(n_dot_v) from the
    normal under radiance L from every direction: L int f cos dw over the hemisphere, by
    midpoint quadrature in (cos theta, phi) (exact integral of the BRDF; no split sum)."""
    ct = (np.arange(steps) + 0.5) / steps  # cos theta of L, uniform: dw = d(cos t) d(phi)
    ph = (np.arange(2 * steps) + 0.5) / (2 * steps) * 2 * np.pi
    ct, ph = np.meshgrid(ct, ph, indexing="ij")
    st = np.sqrt(1 - ct * ct)
    L = np.stack([st * np.cos(ph), st * np.sin(ph), ct], -1)
    N = np.array([0.0, 0.0, 1.0])
    dw = (1.0 / steps) * (2 * np.pi / (2 * steps))
    out = []
    for nv in np.atleast_1d(n_dot_v):
        V = np.array([np.sqrt(max(1 - nv * nv, 0)), 0.0, nv])
        f_cos = _pbr_brdf_cos(np.broadcast_to(N, L.shape), np.broadcast_to(V, L.shape), L,
                              base, metallic, roughness) / np.pi  # f cos
        out.append(f_cos.sum(axis=(0, 1)) * dw * radiance)
    return np.array(out)


def srgb_encode(c):
    c = np.clip(np.asarray(c, dtype=float), 0, 1)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1 / 2.4) - 0.055)


def traverse(bvh, tri, origin, direction, t_max=np.inf):
    """Nearest hit of one ray through the hierarchy of triangles ``tri`` (N, 3, 3):
    (t, triangle index) or (inf, -1) (facet.geometry.bvh's layout; slow: a loop)."""
    o, d = np.asarray(origin, float), np.asarray(direction, float)
    inv = 1.0 / np.where(np.abs(d) < 1e-30, np.copysign(1e-30, d), d)
    best, hit = t_max, -1
    stack = [0]
    while stack:
        i = stack.pop()
        t0 = (bvh.lo[i] - o) * inv
        t1 = (bvh.hi[i] - o) * inv
        near, far = np.minimum(t0, t1).max(), np.maximum(t0, t1).min()
        if near > min(far, best) or far < 0:
            continue
        if bvh.left[i] >= 0:
            stack += [bvh.left[i], bvh.right[i]]
            continue
        prims = bvh.order[bvh.first[i]: bvh.first[i] + bvh.count[i]]
        t = ray_triangles(tri[prims], o, d)
        j = int(np.argmin(t))
        if t[j] < best:
            best, hit = t[j], int(prims[j])
    return best, hit


def ray_triangles(tri, origin, direction) -> np.ndarray:
    """Möller-Trumbore distance along the ray to each triangle (K, 3, 3); inf for misses."""
    tri = np.asarray(tri, float)
    v0, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    inv = 1.0 / np.where(ok, det, 1.0)
    s = origin - v0
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ direction) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    return np.where(hit, t, np.inf)
