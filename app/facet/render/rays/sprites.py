"""Points and lines for the tracers (numpy, no GL): a point cloud is a mesh of spheres and a
line set a mesh of capsules (cylinders with round ends), packed like a mesh's triangles
(facet.render.rays.pack) with the primitive's kind in the first texel's w, and traversed
by the same hierarchy (glsl/trace/bvh.glsl: hit_primitive).

Per primitive, three texels: a sphere (centre, KIND_SPHERE), (radius, 0, 0, 0), 0; a capsule
(end a, KIND_CAPSULE), (b - a, 0), (radius, 0, 0, 0). Its vertex indices (i, i, i) or
(a, a, b), so vertex colours interpolate along a line. Sizes in pixels become radii in scene
units at each point's distance from the camera (``sprite_radii``): as wide as the
rasterizer draws them, at that distance.
"""

from __future__ import annotations

import numpy as np

from ...geometry.bvh import build_bvh

PRIM_SPHERE, PRIM_CAPSULE = 1.0, 2.0  # (0: a triangle) glsl/trace/bvh.glsl's PRIM_*


def sprite_lines(scene, engine: str) -> list[str]:
    """The warning line for points shown unlit (or with eye-dome lighting) and lines,
    which ``engine`` draws as lit spheres and capsules."""
    unlit = [o for o in scene.objects if o.mesh.kind == "lines" or
             (o.mesh.kind == "points" and o.mesh.normals is None)]
    if not unlit:
        return []
    return [f"{engine} draws points as lit spheres and lines as lit capsules (the "
            "rasterizer shows unlit points and lines in their colour, clouds with eye-dome "
            "lighting)"]


def sprite_radii(obj, camera, width: int, height: int) -> np.ndarray:
    """(N,) object-space radii of ``obj``'s points (or (M,) of its segments): its world
    radius, or its size in pixels at each one's distance along the camera's axis."""
    sprites = obj.mesh
    scale = abs(float(np.linalg.det(obj.transform[:3, :3]))) ** (1.0 / 3.0) or 1.0
    count = len(sprites.segments) if sprites.kind == "lines" else len(sprites.positions)
    radius = getattr(sprites, "radius", None)
    if radius:
        return np.full(count, radius, np.float32)
    pixels = sprites.width if sprites.kind == "lines" else sprites.size
    if camera.is_orthographic:
        footprint = np.full(len(sprites.positions), camera.ortho_height / height)
    else:
        world = sprites.positions @ obj.transform[:3, :3].T + obj.transform[:3, 3]
        depth = np.maximum(-(world @ camera.view[2, :3] + camera.view[2, 3]), 0.0)
        if camera.intrinsics is not None:
            per_pixel = 1.0 / camera.intrinsics.fy
        else:
            per_pixel = 2.0 * np.tan(np.radians(camera.fov_y) / 2.0) / height
        footprint = depth * per_pixel
    r = 0.5 * pixels * footprint / scale
    if sprites.kind == "lines":
        r = np.maximum(r[sprites.segments[:, 0]], r[sprites.segments[:, 1]])
    return np.maximum(r, 1e-9).astype(np.float32)


def sprite_data(sprites, radii: np.ndarray, vertex_texels: int):
    """(tris (N, 3, 4), index (N, 4), vertices (V, vertex_texels, 4), bvh) of ``sprites``
    with ``radii`` (N,) (module docstring), primitives in hierarchy order."""
    p = sprites.positions.astype(np.float32)
    r = radii.astype(np.float32)[:, None]
    if sprites.kind == "points":
        lo, hi = p - r, p + r
        ends = np.arange(len(p))[:, None].repeat(3, axis=1)
    else:
        a, b = p[sprites.segments[:, 0]], p[sprites.segments[:, 1]]
        lo, hi = np.minimum(a, b) - r, np.maximum(a, b) + r
        ends = np.stack([sprites.segments[:, 0], sprites.segments[:, 0],
                         sprites.segments[:, 1]], axis=1)
    bvh = build_bvh(lo, hi)
    order = bvh.order
    tris = np.zeros((len(order), 3, 4), np.float32)
    if sprites.kind == "points":
        tris[:, 0, :3], tris[:, 0, 3] = p[order], PRIM_SPHERE
        tris[:, 1, 0] = r[order, 0]
    else:
        tris[:, 0, :3], tris[:, 0, 3] = a[order], PRIM_CAPSULE
        tris[:, 1, :3] = (b - a)[order]
        tris[:, 2, 0] = r[order, 0]
    index = np.zeros((len(order), 4), np.int32)
    index[:, :3] = ends[order]
    n = len(p)
    vertices = np.zeros((n, vertex_texels, 4), np.float32)
    vertices[:, 1, 1:] = 1.0 if sprites.colors is None else sprites.colors[:, :3]
    vertices[:, 3, 2] = 1.0 if sprites.colors is None else sprites.colors[:, 3]
    return tris, index, vertices, bvh
