"""Vertex normals split at creases, and tangent frames for normal maps (numpy, no loops over
vertices or faces; object space throughout).

Crease splitting: around each vertex position, the faces whose normals are within the
crease angle of their neighbour across a shared edge form one smooth group; each group gets
its own copy of the vertex, whose normal is the corner-angle-weighted mean of the group's
face normals. A cube's corner thus becomes three vertices with axis-aligned normals, while
a finely tessellated sphere stays one smooth surface. Vertices that already differ (a
texture seam) stay apart; vertices at the same position are welded for adjacency only.
"""

from __future__ import annotations

import numpy as np

from .options import DEFAULT_CREASE  # noqa: F401 - the loaders' default, kept with the options

AREA_EPSILON = 1e-30  # below this |cross| a triangle counts as degenerate


def face_normals(positions: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((F, 3) unit face normals, (F,) twice the areas); degenerate faces get (0, 0, 0)."""
    p = np.asarray(positions, dtype=np.float64)
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=1)
    ok = length > AREA_EPSILON
    n[ok] /= length[ok, None]
    n[~ok] = 0.0
    return n, length


def corner_angles(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F, 3) interior angle of each face at each of its corners, radians."""
    p = np.asarray(positions, dtype=np.float64)[faces]  # (F, 3, 3)
    e1 = np.roll(p, -1, axis=1) - p
    e2 = np.roll(p, 1, axis=1) - p
    cos = (e1 * e2).sum(-1) / np.maximum(np.linalg.norm(e1, axis=-1) *
                                         np.linalg.norm(e2, axis=-1), 1e-300)
    return np.arccos(np.clip(cos, -1.0, 1.0))


def weld(positions: np.ndarray) -> np.ndarray:
    """(N,) index of the first vertex at each vertex's exact position."""
    _, first, inverse = np.unique(np.asarray(positions), axis=0, return_index=True,
                                  return_inverse=True)
    return first[inverse.reshape(-1)]


def crease_normals(positions, faces, crease: float = DEFAULT_CREASE, attributes=None):
    """Split vertices at edges sharper than ``crease`` degrees (module docstring).

    ``attributes``: (N, K) the other per-vertex values (uvs, colours); vertices equal in
    position and attributes are one vertex (files that repeat vertices per face, STL above
    all, get shared ones), vertices that differ stay apart (a texture seam).
    Returns ``(source, faces, normals)``: (M,) the original vertex each new vertex copies
    (take every per-vertex array through it), (F, 3) the new faces, (M, 3) float32 unit
    normals. ``crease`` >= 180 gives fully smooth normals (no splits).
    """
    faces = np.asarray(faces, dtype=np.int64)
    p = np.asarray(positions, dtype=np.float64)
    vertex_id = weld(p if attributes is None else
                np.hstack([p, np.asarray(attributes, dtype=np.float64).reshape(len(p), -1)]))
    n_faces = len(faces)
    fn, _ = face_normals(positions, faces)
    angles = corner_angles(positions, faces)
    welded = weld(positions)[faces]  # (F, 3) position ids
    corner = np.arange(3 * n_faces).reshape(n_faces, 3)
    # Each corner starts in its own group; corners of neighbouring faces at the same
    # position join when their faces meet at less than the crease angle (and neither face
    # is degenerate).
    label = np.arange(3 * n_faces)
    if crease < 180.0 and n_faces > 1:
        edges = np.stack([welded, np.roll(welded, -1, axis=1)], axis=-1).reshape(-1, 2)
        starts = np.stack([corner, np.roll(corner, -1, axis=1)], axis=-1).reshape(-1, 2)
        key = np.sort(edges, axis=1)
        order = np.lexsort((key[:, 1], key[:, 0]))
        key, edges, starts = key[order], edges[order], starts[order]
        same = np.all(key[1:] == key[:-1], axis=1)
        i = np.nonzero(same)[0]  # consecutive half-edges on one edge: neighbours
        fa, fb = starts[i, 0] // 3, starts[i + 1, 0] // 3
        smooth = (fn[fa] * fn[fb]).sum(1) >= np.cos(np.radians(crease)) - 1e-9
        smooth &= np.any(fn[fa] != 0, 1) & np.any(fn[fb] != 0, 1)
        i = i[smooth]
        # Match each endpoint of edge i to the corner of the other face at that position.
        a0, a1 = starts[i, 0], starts[i, 1]
        flipped = edges[i, 0] != edges[i + 1, 0]
        b0 = np.where(flipped, starts[i + 1, 1], starts[i + 1, 0])
        b1 = np.where(flipped, starts[i + 1, 0], starts[i + 1, 1])
        pairs = np.concatenate([np.stack([a0, b0], 1), np.stack([a1, b1], 1)])
        label = _components(pairs, 3 * n_faces)
    else:
        # No creases: one group per position.
        label = _components(np.empty((0, 2), np.int64), 3 * n_faces) if crease < 180 \
            else welded.reshape(-1)
    label = label.reshape(n_faces, 3)
    # One new vertex per (original vertex, group): texture seams stay apart.
    keys = np.stack([vertex_id[faces].reshape(-1), label.reshape(-1)], axis=1)
    uniq, inverse = np.unique(keys, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    # Normals per group (shared by all new vertices of the group), corner-angle weighted.
    weights = (fn[:, None, :] * angles[:, :, None]).reshape(-1, 3)
    sums = np.zeros((3 * n_faces, 3))
    np.add.at(sums, label.reshape(-1), weights)
    normals = sums[uniq[:, 1]]
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.where(length > 0, normals / np.where(length > 0, length, 1), (0.0, 0.0, 1.0))
    return uniq[:, 0], inverse.reshape(n_faces, 3).astype(np.uint32), normals.astype(np.float32)


def _components(pairs: np.ndarray, n: int) -> np.ndarray:
    """Connected components of ``n`` nodes joined by ``pairs`` (E, 2): each node's label is
    the smallest node of its component (min-label propagation with pointer jumping)."""
    label = np.arange(n)
    if len(pairs) == 0:
        return label
    a, b = pairs[:, 0], pairs[:, 1]
    while True:
        low = np.minimum(label[a], label[b])
        new = label.copy()
        np.minimum.at(new, a, low)
        np.minimum.at(new, b, low)
        new = new[new]  # pointer jumping: follow labels to their roots
        while True:
            nxt = new[new]
            if np.array_equal(nxt, new):
                break
            new = nxt
        if np.array_equal(new, label):
            return label
        label = new


def tangents(positions, normals, uvs, faces) -> np.ndarray:
    """(N, 4) float32 tangent frames for normal mapping: xyz the unit tangent (direction of
    increasing u, orthogonal to the normal), w = +-1 the handedness, so that the bitangent
    (increasing v) is w cross(N, T), as glTF defines it. Per-face tangents from the uv
    derivatives are summed over each vertex's corners weighted by corner angle, then
    Gram-Schmidt-orthogonalised (MikkTSpace's result for smooth, well-mapped meshes)."""
    p = np.asarray(positions, dtype=np.float64)
    uv = np.asarray(uvs, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    e1, e2 = p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]]
    d1, d2 = uv[f[:, 1]] - uv[f[:, 0]], uv[f[:, 2]] - uv[f[:, 0]]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    r = np.where(np.abs(det) > 1e-20, 1.0 / np.where(det == 0, 1, det), 0.0)
    t = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * r[:, None]
    b = (e2 * d1[:, 0:1] - e1 * d2[:, 0:1]) * r[:, None]
    w = corner_angles(p, f)
    ts, bs = np.zeros_like(p), np.zeros_like(p)
    for k in range(3):  # the three corners of every face, vectorised over faces
        np.add.at(ts, f[:, k], t * w[:, k:k + 1])
        np.add.at(bs, f[:, k], b * w[:, k:k + 1])
    n = np.asarray(normals, dtype=np.float64)
    ts -= n * (n * ts).sum(1, keepdims=True)
    length = np.linalg.norm(ts, axis=1, keepdims=True)
    # Where uvs give no direction, any tangent orthogonal to the normal will do.
    fallback = np.cross(n, np.where(np.abs(n[:, :1]) < 0.9, (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)))
    ts = np.where(length > 1e-20, ts / np.where(length > 0, length, 1), fallback)
    ts /= np.maximum(np.linalg.norm(ts, axis=1, keepdims=True), 1e-300)
    hand = np.where((np.cross(n, ts) * bs).sum(1) < 0.0, -1.0, 1.0)
    return np.hstack([ts, hand[:, None]]).astype(np.float32)
