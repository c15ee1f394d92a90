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


def phong(points, normals, to_eye, color, material, lights, ambient, blinn=False):
    """The notes' shading equation at world points (H, W, 3), clamped to [0, 1].

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
    return np.clip(out, 0.0, 1.0)


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
