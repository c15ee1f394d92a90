"""The path tracer's emitters as a table for light sampling (numpy, no GL).

Every triangle of a mesh whose material emits (emissive factor x strength, as
facet.render.rays.pack lays it out) is a light, and so is every emitting analytic shape
(facet.scene.shapes) of finite area. glsl/trace/path.frag picks one by its share of the
emitted power, area x luminance of the factor (a binary search in the cumulative shares),
then a point uniformly on it by area; the density of that point per unit area is then
luminance / total power, the same for every point of an instance: the ``emit_pdf`` the
instance row carries, which also weights the emitters that BSDF sampling finds (multiple
importance sampling). An emissive texture varies what is emitted, not the density (still
unbiased). A shape is sampled in its object space, which is uniform in the world where its
transform is a similarity (rotation, uniform scale, translation); a shape stretched
unevenly, or an infinite plane, is found by BSDF sampling alone (its ``emit_pdf`` is 0):
exact, only noisier.
"""

from __future__ import annotations

import numpy as np

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def emitted_luminance(material) -> float:
    """The luminance of ``material``'s emitted radiance factor (a PbrMaterial)."""
    return float(LUMINANCE @ (material.emissive * material.emissive_strength))


def shape_area(obj) -> float:
    """The world area of ``obj``'s analytic shape; 0 for one that cannot be sampled
    uniformly by area in its object space (an infinite plane; a curved shape or a box under
    an uneven scale). A flat shape (a finite plane, a disk) stays uniform under any affine
    map: its area scales by one factor, |M x_axis x M z_axis| (the plane is y = 0), so a
    plane light written as a 2 x 2 plane scaled 0.23 x 0.19 is sampled as one of that size."""
    m = np.asarray(obj.transform, dtype=np.float64)[:3, :3]
    kind, q = obj.shape.kind, [float(v) for v in obj.shape.params]
    if not np.all(np.isfinite(q)) or not np.isfinite(m).all():
        return 0.0
    if kind in ("plane", "disk"):
        stretch = float(np.linalg.norm(np.cross(m[:, 0], m[:, 2])))
        return float((q[0] * q[1] if kind == "plane" else np.pi * q[0] ** 2) * stretch)
    scale = np.linalg.svd(m, compute_uv=False)
    if scale[0] <= 0 or scale[0] - scale[-1] > 1e-6 * scale[0]:
        return 0.0
    if kind == "sphere":
        area = 4 * np.pi * q[0] ** 2
    elif kind == "box":
        area = 2 * (q[0] * q[1] + q[1] * q[2] + q[0] * q[2])
    elif kind == "cylinder":
        area = 2 * np.pi * q[0] * (q[1] + q[0])
    elif kind == "cone":
        area = np.pi * q[0] * (np.hypot(q[0], q[1]) + q[0])
    else:
        return 0.0
    return float(area * scale[0] ** 2)


def pack_emitters(objects, pbr_of, mesh_tris: dict, tri_offset: dict):
    """(table (n, 4) float32 of (instance, triangle, cumulative power share, 0), emit_pdf
    (len(objects),) float32) for the placed ``objects`` in instance order. ``pbr_of``:
    object -> its PbrMaterial; ``mesh_tris``: id(mesh) -> (N, 3, 4) triangles (v0, e1, e2)
    in object space, hierarchy order; ``tri_offset``: id(mesh) -> its first triangle."""
    pdf = np.zeros(len(objects), np.float32)
    parts, powers = [], []
    for i, obj in enumerate(objects):
        lum = emitted_luminance(pbr_of(obj))
        if lum <= 0.0:
            continue
        if obj.shape is not None:
            area = shape_area(obj)
            if area > 0:
                parts.append(np.array([[i, -1, 0, 0]], np.float64))
                powers.append(np.array([area * lum]))
                pdf[i] = lum
            continue
        if obj.mesh.kind != "mesh":  # emitting points and lines: met by paths only
            continue
        tris = mesh_tris[id(obj.mesh)]
        m = np.asarray(obj.transform, dtype=np.float64)[:3, :3]
        e1, e2 = tris[:, 1, :3] @ m.T, tris[:, 2, :3] @ m.T
        area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
        keep = np.flatnonzero(area > 0)
        if keep.size == 0:
            continue
        part = np.zeros((keep.size, 4), np.float64)
        part[:, 0] = i
        part[:, 1] = tri_offset[id(obj.mesh)] + keep
        parts.append(part)
        powers.append(area[keep] * lum)
        pdf[i] = lum  # divided by the total power below
    if not parts:
        return np.zeros((1, 4), np.float32), pdf
    table = np.concatenate(parts)
    power = np.concatenate(powers)
    total = power.sum()
    table[:, 2] = np.cumsum(power) / total
    table[-1, 2] = 1.0 + 1e-6  # the last share catches every u < 1
    return table.astype(np.float32), (pdf / total).astype(np.float32)
