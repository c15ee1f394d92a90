"""Subdivision surfaces refined to a level (no GL): Catmull-Clark over polygons of any size
and Loop over triangles (trimesh's), what a USD mesh's ``subdivisionScheme`` asks for when
a refinement level is requested (``subdivide``; usdview draws the control cage at its
default complexity, as facet does without one).

Catmull-Clark (one level, all numpy): a face point at each face's centroid; an edge point
at the mean of its two ends and the two face points beside it (the edge's midpoint on a
boundary); each vertex moved to (Q + 2R + (n - 3) P) / n (Q the mean of its faces' points,
R of its edges' midpoints, n its valence), on a boundary to (e1 + 6 P + e2) / 8 along the
boundary; every face of k corners becomes k quads. Positions only: texture coordinates and
other primvars are not carried through (said by the caller), normals are computed on the
refined surface. Creases and corners are not honoured (the caller says so).
"""

from __future__ import annotations

import numpy as np

MAX_LEVEL = 4  # each level multiplies the faces by about 4


def catmull_clark(points: np.ndarray, counts: np.ndarray,
                  indices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One level: ((N', 3) points, (F', 4) quads) of polygons (``counts``, flat
    ``indices`` into ``points``)."""
    points = np.asarray(points, np.float64)
    counts = np.asarray(counts, np.int64)
    indices = np.asarray(indices, np.int64)
    n, nf = len(points), len(counts)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    face_of = np.repeat(np.arange(nf), counts)
    position = np.arange(len(indices)) - starts[face_of]  # corner number within its face
    nxt = starts[face_of] + (position + 1) % counts[face_of]
    prv = starts[face_of] + (position - 1) % counts[face_of]
    face_pts = np.zeros((nf, 3))
    np.add.at(face_pts, face_of, points[indices])
    face_pts /= counts[:, None]
    # undirected edges of every corner (v, next v)
    a, b = indices, indices[nxt]
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    edges, edge_of = np.unique(np.stack([lo, hi], 1), axis=0, return_inverse=True)
    edge_of = edge_of.reshape(-1)
    ne = len(edges)
    faces_per_edge = np.bincount(edge_of, minlength=ne)
    face_sum = np.zeros((ne, 3))
    np.add.at(face_sum, edge_of, face_pts[face_of])
    mid = points[edges].mean(axis=1)
    boundary = faces_per_edge == 1
    edge_pts = np.where(boundary[:, None], mid,
                        (points[edges].sum(axis=1) + face_sum) /
                        (2 + faces_per_edge)[:, None])
    # vertex points
    valence = np.bincount(edges.reshape(-1), minlength=n).astype(np.float64)
    r = np.zeros((n, 3))
    np.add.at(r, edges[:, 0], mid)
    np.add.at(r, edges[:, 1], mid)
    q = np.zeros((n, 3))
    np.add.at(q, indices, face_pts[face_of])
    faces_at = np.bincount(indices, minlength=n).astype(np.float64)
    safe = np.maximum(valence, 1)[:, None]
    moved = (q / np.maximum(faces_at, 1)[:, None] + 2 * r / safe +
             (valence - 3)[:, None] * points) / safe
    on_boundary = np.zeros(n, bool)
    on_boundary[edges[boundary].reshape(-1)] = True
    bsum = np.zeros((n, 3))
    np.add.at(bsum, edges[boundary][:, 0], points[edges[boundary][:, 1]])
    np.add.at(bsum, edges[boundary][:, 1], points[edges[boundary][:, 0]])
    moved = np.where(on_boundary[:, None], (bsum + 6 * points) / 8, moved)
    used = faces_at > 0
    moved = np.where(used[:, None], moved, points)
    # quads: (vertex, edge after it, face, edge before it)
    out_points = np.concatenate([moved, edge_pts, face_pts])
    quads = np.stack([indices, n + edge_of, n + ne + face_of, n + edge_of[prv]], axis=1)
    return out_points, quads


def refine(points: np.ndarray, counts: np.ndarray, indices: np.ndarray, scheme: str,
           level: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(points, counts, indices) after ``level`` levels of ``scheme`` ("catmullClark",
    "loop"; "bilinear" and "none" are returned as they are)."""
    level = min(int(level), MAX_LEVEL)
    if level <= 0 or scheme not in ("catmullClark", "loop"):
        return points, counts, indices
    if scheme == "loop" and np.all(np.asarray(counts) == 3):
        from trimesh.remesh import subdivide_loop

        v, f = subdivide_loop(np.asarray(points, np.float64),
                              np.asarray(indices, np.int64).reshape(-1, 3), level)
        return v, np.full(len(f), 3), f.reshape(-1)
    for _ in range(level):  # (Loop on polygons: Catmull-Clark, as OpenSubdiv falls back)
        points, quads = catmull_clark(points, counts, indices)
        counts, indices = np.full(len(quads), 4), quads.reshape(-1)
    return points, counts, indices
