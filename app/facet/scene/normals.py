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

from .constants import DEFAULT_CREASE  # noqa: F401 - the loaders' default

MAX_COORDINATE = 1e18  # coordinates beyond overflow float32 when squared (distances)
AREA_EPSILON = 1e-36  # below this |cross| (float32) a triangle counts as degenerate


def face_normals(positions: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((F, 3) unit face normals, (F,) twice the areas); degenerate faces get (0, 0, 0).
    The cross product is written out per component (np.cross is several times slower on
    a million rows). float32, as the meshes' positions are."""
    p = np.asarray(positions, dtype=np.float32)
    a = p[faces[:, 0]]
    u = p[faces[:, 1]] - a
    v = p[faces[:, 2]] - a
    n = np.empty_like(u)
    n[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    n[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    n[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    length = np.sqrt(np.einsum("ij,ij->i", n, n))
    ok = length > AREA_EPSILON
    np.divide(n, length[:, None], out=n, where=ok[:, None])
    n[~ok] = 0.0
    return n, length


def corner_angles(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F, 3) float32 interior angle of each face at each of its corners, radians (float32
    is plenty for weights, and halves the work on large meshes)."""
    p = np.asarray(positions, dtype=np.float32)
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    ab, bc, ca = b - a, c - b, a - c
    out = np.empty((len(faces), 3), np.float32)
    for k, (u, v) in enumerate(((ab, -ca), (bc, -ab), (ca, -bc))):
        dot = np.einsum("ij,ij->i", u, v)
        lengths = np.sqrt(np.einsum("ij,ij->i", u, u)) * np.sqrt(np.einsum("ij,ij->i", v, v))
        out[:, k] = np.arccos(np.clip(dot / np.maximum(lengths, 1e-30), -1.0, 1.0))
    return out


def weld(positions: np.ndarray) -> np.ndarray:
    """(N,) one representative vertex index per distinct row of ``positions`` (exact
    equality; rows sorted with lexsort, numeric and fast, rather than np.unique on rows)."""
    p = np.asarray(positions)
    if p.ndim == 1:
        p = p[:, None]
    order = np.lexsort(p.T[::-1])
    s = p[order]
    new = np.ones(len(p), bool)
    new[1:] = np.any(s[1:] != s[:-1], axis=1)
    starts = np.maximum.accumulate(np.where(new, np.arange(len(p)), 0))
    out = np.empty(len(p), np.int64)
    out[order] = order[starts]
    return out


def crease_normals(positions, faces, crease: float = DEFAULT_CREASE, attributes=None,
                   face_n: np.ndarray | None = None, found: dict | None = None):
    """Split vertices at edges sharper than ``crease`` degrees (module docstring).

    ``attributes``: (N, K) the other per-vertex values (uvs, colours); vertices equal in
    position and attributes are one vertex (files that repeat vertices per face, STL above
    all, get shared ones), vertices that differ stay apart (a texture seam).
    Returns ``(source, faces, normals)``: (M,) the original vertex each new vertex copies
    (take every per-vertex array through it), (F, 3) the new faces, (M, 3) float32 unit
    normals. ``crease`` >= 180 gives fully smooth normals (no splits). ``face_n``: the
    unit face normals when the caller has them; ``found["closed"]`` receives whether the
    surface is closed and consistently wound (Mesh.closed), a by-product of the edge sort
    (left unset when it was not sorted). Corners are numbered 3 f + k; the
    half-edge of corner c runs from it to the next corner of its face. Index arrays are
    int32 where they fit (a 1.3M-triangle mesh stays within a few hundred MB).
    """
    faces = np.asarray(faces, dtype=np.int64)
    n_faces, n = len(faces), len(positions)
    p = np.asarray(positions)
    position_id = weld(p)
    vertex_id = position_id if attributes is None else weld(
        np.hstack([p, np.asarray(attributes, dtype=p.dtype).reshape(n, -1)]))
    fn = face_normals(positions, faces)[0] if face_n is None else face_n
    fn = fn.astype(np.float32)
    angles = corner_angles(positions, faces)
    shared = bool(np.array_equal(vertex_id, np.arange(n)))  # nothing to weld
    index = np.int32 if 3 * n_faces < 2**31 else np.int64
    corner_pos = position_id[faces].astype(index).reshape(-1)  # (3F,) position of a corner
    if crease < 180.0 and n_faces > 1:
        nxt = np.arange(3 * n_faces, dtype=index).reshape(n_faces, 3)
        nxt = np.roll(nxt, -1, axis=1).reshape(-1)  # the next corner of the same face
        a_, b_ = corner_pos, corner_pos[nxt]
        key = np.minimum(a_, b_).astype(np.int64) * n + np.maximum(a_, b_)
        order = np.argsort(key).astype(index)  # the two half-edges of an edge, in any order
        sorted_key = key[order]
        del key
        i = np.nonzero(sorted_key[1:] == sorted_key[:-1])[0]
        if found is not None:  # closed: every edge twice, run once each way
            paired = 2 * len(i) == 3 * n_faces and not np.any(
                sorted_key[2:] == sorted_key[:-2])
            found["closed"] = bool(paired and np.all(
                corner_pos[order[i]] == corner_pos[nxt[order[i + 1]]]))
        del sorted_key
        h1, h2 = order[i], order[i + 1]  # two half-edges on one edge: neighbours
        del order, i
        fa, fb = h1 // 3, h2 // 3
        smooth = np.einsum("ij,ij->i", fn[fa], fn[fb]) >= np.cos(np.radians(crease)) - 1e-6
        smooth &= np.any(fn[fa] != 0, 1) & np.any(fn[fb] != 0, 1)
        if shared and smooth.all() and 2 * len(h1) == 3 * n_faces:
            # Every edge smooth and shared by two faces, every vertex already shared: one
            # group per vertex, the mesh as it is (the common case, done directly).
            return np.arange(n), faces.astype(np.uint32), _group_normals(
                faces.reshape(-1), fn, angles, n)
        h1, h2 = h1[smooth], h2[smooth]
        # Join the corners at each end: h1's start with the corner of h2 at that position.
        flipped = corner_pos[h1] != corner_pos[h2]
        b0 = np.where(flipped, nxt[h2], h2)
        b1 = np.where(flipped, h2, nxt[h2])
        pairs = np.concatenate([np.stack([h1, b0], 1), np.stack([nxt[h1], b1], 1)])
        del h1, h2, b0, b1, flipped, nxt
        label = _components(pairs, 3 * n_faces)
        del pairs
    elif crease < 180.0:
        label = np.arange(3 * n_faces)
    else:
        label = corner_pos.astype(np.int64)  # no creases: one group per position
    # One new vertex per (original vertex, group): texture seams stay apart. Both are
    # below 3F (or N), so one int64 key holds the pair.
    groups = max(3 * n_faces, n)
    keys = vertex_id[faces].reshape(-1).astype(np.int64) * groups + label
    uniq, inverse = np.unique(keys, return_inverse=True)
    del keys
    normals = _group_normals(label, fn, angles, groups)[uniq % groups]
    return uniq // groups, inverse.reshape(n_faces, 3).astype(np.uint32), normals


def _group_normals(group: np.ndarray, fn: np.ndarray, angles: np.ndarray, count: int):
    """(count, 3) float32 unit normals: per group, the corner-angle-weighted sum of the
    corners' face normals (``group``: (3F,) each corner's group)."""
    sums = np.stack([np.bincount(group, (fn[:, k, None] * angles).reshape(-1),
                                 minlength=count) for k in range(3)], axis=1)
    return _unit(sums)


def _unit(normals: np.ndarray) -> np.ndarray:
    """(N, 3) float32 unit vectors; zero ones become +z."""
    length = np.sqrt((normals * normals).sum(axis=1, keepdims=True))
    ok = length > 0
    return np.where(ok, normals / np.where(ok, length, 1), (0.0, 0.0, 1.0)).astype(np.float32)


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


def smooth_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals, (N, 3) float32.

    Each face adds its unnormalised cross product (|cross| = 2 x area) to its three vertices,
    summed with ``np.bincount`` (no Python loop over vertices; the sums run in float64).
    Vertices used by no face, or whose normals cancel, get +z.
    """
    p = np.asarray(positions, dtype=np.float32)
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    face_n = np.cross(b - a, c - a)
    n = np.zeros((len(p), 3))
    for corner in range(3):
        for k in range(3):
            n[:, k] += np.bincount(faces[:, corner], face_n[:, k], minlength=len(p))
    length = np.linalg.norm(n, axis=1)
    ok = length > 0
    n[ok] /= length[ok, None]
    n[~ok] = (0.0, 0.0, 1.0)
    return n.astype(np.float32)


def weld_key(positions: np.ndarray) -> np.ndarray:
    """(N,) one index per position, positions within ~1e-6 of the extent counting as one
    (a seam's copies may differ in the last bits: cos(2 pi) is not cos(0))."""
    p = positions.astype(np.float64)
    lo, extent = p.min(axis=0), max(float(np.ptp(p, axis=0).max()), 1e-30)
    # 20 bits per axis; the cells start off-centre, so a symmetric shape's zeros (which
    # land on a cell's middle, not its edge) stay together however they round.
    q = np.floor((p - lo) / extent * ((1 << 20) - 2) + 0.37).astype(np.int64)
    _, first, inverse = np.unique((q[:, 0] << 42) | (q[:, 1] << 21) | q[:, 2],
                                  return_index=True, return_inverse=True)
    return first[inverse.reshape(-1)]


def closed_surface(faces: np.ndarray, n: int) -> bool:
    """Every directed edge occurs once and its reverse occurs too (see Mesh.closed)."""
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & \
        (faces[:, 0] != faces[:, 2])
    f = faces[keep]
    if len(f) == 0:
        return False
    a = f.reshape(-1)
    b = np.roll(f, -1, axis=1).reshape(-1)
    # Each undirected edge must come exactly twice, once each way: sorted by the edge,
    # pairs of equal keys whose directions are opposite.
    key = np.sort(np.minimum(a, b) * n + np.maximum(a, b) << 1 | (a < b))
    if len(key) % 2:
        return False
    edge, forward = key[0::2] >> 1, key[0::2] & 1
    edge2, forward2 = key[1::2] >> 1, key[1::2] & 1
    return bool(np.array_equal(edge, edge2) and not np.any(forward == forward2) and
                not np.any(edge[1:] == edge[:-1]))
