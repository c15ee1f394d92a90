"""Bounding volume hierarchies over axis-aligned boxes, built with the surface area
heuristic (SAH) in vectorised numpy; numpy only, no GL.

``build_bvh(lo, hi)`` takes the boxes of N primitives (triangles of a mesh in object space,
or placed objects in world space) and splits them top-down, all nodes of one depth at once:
each node's primitives are binned by centroid into ``BINS`` slabs per axis (over the node's
box), the boxes and counts of every bin come from ``np.minimum.at`` / ``np.bincount`` over
all primitives of the level, and the split with the lowest SAH cost

    cost = C_TRAVERSE + (area(L) n_L + area(R) n_R) / area(node)      (in triangle tests)

wins; a node becomes a leaf when it holds at most ``LEAF_SIZE`` primitives, or when no split
is cheaper than testing its ``n`` primitives and ``n <= MAX_LEAF``. Primitives whose
centroids coincide are split by count. No Python loop runs per primitive or per node: the
loop is over depths (about log2 N).

The result is the classic binary layout (``BVH``); tests/reference.py traverses it in numpy for
tests, and facet.render.trace packs it for the GPU.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

BINS = 16
LEAF_SIZE = 4
SAH_LIMIT = 16384  # larger inputs: SAH over clusters of primitives (``_clustered``)
CLUSTER_BITS = 15  # Morton bits of a cluster: cells of a 32^3 grid
BOX_PAD = 2.0 ** -20  # relative widening of node boxes (float32 has 24 bits)
MAX_LEAF = 16
C_TRAVERSE = 1.0  # cost of a node visit, in triangle tests


@dataclass
class BVH:
    """Nodes in depth-first-compatible order (children after their parent).

    lo, hi : (M, 3) float32 node boxes
    left : (M,) int32 index of the left child (right = ``right``), -1 for a leaf
    right : (M,) int32
    first, count : (M,) int32 a leaf's range in ``order`` (count 0 for inner nodes)
    order : (N,) int32 primitive indices, each leaf's primitives contiguous
    """

    lo: np.ndarray
    hi: np.ndarray
    left: np.ndarray
    right: np.ndarray
    first: np.ndarray
    count: np.ndarray
    order: np.ndarray

    @property
    def depth(self) -> int:
        """Longest root-to-leaf path (1 for a single leaf)."""
        depth, frontier = 0, np.array([0])
        while frontier.size:
            depth += 1
            inner = frontier[self.left[frontier] >= 0]
            frontier = np.concatenate([self.left[inner], self.right[inner]])
        return depth


    def refit(self, lo, hi) -> BVH:
        """The same tree over the N boxes ``lo``, ``hi`` (N, 3) of its primitives moved
        (a skinned or morphed mesh's triangles): each leaf's box the union of its
        primitives', each inner node's the union of its children's, bottom-up one depth
        at a time; padded as ``build_bvh`` pads. No split is chosen again."""
        lo = np.asarray(lo, dtype=np.float32).reshape(-1, 3)[self.order]
        hi = np.asarray(hi, dtype=np.float32).reshape(-1, 3)[self.order]
        node_lo, node_hi = self.lo.copy(), self.hi.copy()  # unreachable nodes keep theirs
        levels, leaves, frontier = [], [], np.array([0])
        while frontier.size:  # the nodes reachable from the root, depth by depth
            inner = frontier[self.left[frontier] >= 0]
            leaves.append(frontier[self.left[frontier] < 0])
            if inner.size:
                levels.append(inner)
            frontier = np.concatenate([self.left[inner], self.right[inner]])
        leaves = np.concatenate(leaves)
        leaves = leaves[np.argsort(self.first[leaves], kind="stable")]
        # Reachable leaves' ranges are contiguous and cover ``order``: reduce between
        # their starts.
        node_lo[leaves] = np.minimum.reduceat(lo, self.first[leaves], axis=0)
        node_hi[leaves] = np.maximum.reduceat(hi, self.first[leaves], axis=0)
        for inner in reversed(levels):
            node_lo[inner] = np.minimum(node_lo[self.left[inner]], node_lo[self.right[inner]])
            node_hi[inner] = np.maximum(node_hi[self.left[inner]], node_hi[self.right[inner]])
        pad = (np.abs(node_lo) + np.abs(node_hi) + (node_hi - node_lo)) * BOX_PAD + 1e-30
        return BVH(node_lo - pad, node_hi + pad, self.left, self.right, self.first,
                   self.count, self.order)


def _area(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Half the surface area of boxes (..., 3); 0 for empty ones (lo > hi)."""
    d = np.maximum(hi - lo, 0.0)
    return d[..., 0] * d[..., 1] + d[..., 1] * d[..., 2] + d[..., 2] * d[..., 0]


def build_bvh(lo, hi, method: str = "auto", leaf_items: int = LEAF_SIZE) -> BVH:
    """The hierarchy of N boxes ``lo``, ``hi`` (N, 3); N >= 1 (module docstring).
    ``method``: "sah", "clustered", "balanced" (one box a leaf, ceil(log2 N) + 1 levels:
    a traversal's stack of that many entries holds it), or "auto" (SAH up to
    ``SAH_LIMIT`` boxes);
    ``leaf_items``: 1 splits down to single boxes (the top level over placed objects, whose
    every test is a whole mesh's traversal: each is tested only where its own box is hit)."""
    lo = np.asarray(lo, dtype=np.float32).reshape(-1, 3)
    hi = np.asarray(hi, dtype=np.float32).reshape(-1, 3)
    if len(lo) == 0:
        raise ValueError("a BVH needs at least one primitive")
    if method == "auto":
        method = "sah" if len(lo) <= SAH_LIMIT else "clustered"
    if method == "balanced":
        return _balanced(lo, hi)
    bvh = _sah(lo, hi, leaf_items=leaf_items) if method == "sah" else _clustered(lo, hi)
    # Widen every box by a few float32 steps of its coordinates: a ray grazing a face, or
    # running in a box's face plane with a zero direction component, still enters it
    # (the slab test then sees (lo - o) / d with lo - o < 0 instead of 0 * inf).
    pad = (np.abs(bvh.lo) + np.abs(bvh.hi) + (bvh.hi - bvh.lo)) * BOX_PAD + 1e-30
    bvh.lo, bvh.hi = bvh.lo - pad, bvh.hi + pad
    return bvh


def _sah(lo, hi, weight=None, leaf_items: int = LEAF_SIZE) -> BVH:
    """Binned SAH over all N boxes. ``weight``: primitives each box stands for (the
    clusters of ``_clustered``; their nodes split until one box is left)."""
    n = len(lo)
    centroid = (lo + hi) * np.float32(0.5)
    weight = np.ones(n, np.int64) if weight is None else np.asarray(weight, np.int64)
    capacity = 2 * n
    node_lo = np.empty((capacity, 3), np.float32)
    node_hi = np.empty((capacity, 3), np.float32)
    left = np.full(capacity, -1, np.int32)
    right = np.full(capacity, -1, np.int32)
    first = np.zeros(capacity, np.int32)
    count = np.zeros(capacity, np.int32)
    node_lo[0], node_hi[0] = lo.min(axis=0), hi.max(axis=0)
    count[0] = n
    perm = np.arange(n, dtype=np.int32)  # each node's boxes are a contiguous range
    used = 1
    active = np.array([0], np.int64)  # nodes of this depth that may split
    while active.size:
        active = active[count[active] > leaf_items]
        if not active.size:
            break
        split, goes_left, child_boxes = _choose_splits(
            active, first, count, node_lo, node_hi, perm, centroid, lo, hi, weight,
            leaf_items)
        active = active[split]
        if not active.size:
            break
        starts, counts = first[active], count[active]
        n_left, perm = _partition(perm, starts, counts, goes_left)
        kids = used + 2 * np.arange(active.size)
        used += 2 * active.size
        left[active], right[active] = kids, kids + 1
        first[kids], count[kids] = starts, n_left
        first[kids + 1], count[kids + 1] = starts + n_left, counts - n_left
        count[active] = 0
        (llo, lhi), (rlo, rhi) = child_boxes
        node_lo[kids], node_hi[kids] = llo[split], lhi[split]
        node_lo[kids + 1], node_hi[kids + 1] = rlo[split], rhi[split]
        active = np.concatenate([kids, kids + 1])
    return BVH(node_lo[:used], node_hi[:used], left[:used], right[:used], first[:used],
               count[:used], perm)


def _partition(perm, starts, counts, goes_left):
    """Stable partition of each range of ``perm`` (left ones first): (left counts, perm)."""
    seg = np.repeat(np.arange(starts.size), counts)
    idx = _ranges(starts, counts)
    flag = goes_left[idx]
    n_left = np.bincount(seg, weights=flag, minlength=starts.size).astype(np.int64)
    head = _segment_starts(counts)
    rank_left = np.cumsum(flag) - flag
    rank_left -= np.repeat(rank_left[head], counts)
    rank_right = np.cumsum(~flag) - ~flag
    rank_right -= np.repeat(rank_right[head], counts)
    dest = np.repeat(starts.astype(np.int64), counts) + np.where(
        flag, rank_left, np.repeat(n_left, counts) + rank_right)
    out = perm.copy()
    out[dest] = perm[idx]
    return n_left, out


def _clustered(lo, hi) -> BVH:
    """Large inputs: primitives sorted along a Morton curve and grouped into the cells of a
    coarse grid (clusters, contiguous in that order, their boxes by ``reduceat``); binned
    SAH over the clusters at the top, and inside each cluster splits at the highest
    differing Morton bit (a spatial median), all clusters a depth at a time. The SAH
    decides where it matters most, the top; the bottom is built in O(N) per depth."""
    codes = _centre_codes(lo, hi)
    order = np.argsort(codes, kind="stable").astype(np.int32)
    codes = codes[order]
    s_lo, s_hi = lo[order], hi[order]
    key = codes >> (30 - CLUSTER_BITS)
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    counts = np.diff(np.r_[starts, len(codes)])
    k_lo, k_hi = np.minimum.reduceat(s_lo, starts), np.maximum.reduceat(s_hi, starts)
    top = _sah(k_lo, k_hi, weight=counts, leaf_items=1)
    bottom = _radix(codes, starts, counts, s_lo, s_hi, offset=len(top.left))
    # Each top leaf holds one cluster: it takes the place of that cluster's subtree root.
    leaf = np.flatnonzero(top.left < 0)
    cluster = top.order[top.first[leaf]]
    root = bottom["root"][cluster]
    lo_all = np.concatenate([top.lo, bottom["lo"]])
    hi_all = np.concatenate([top.hi, bottom["hi"]])
    left = np.concatenate([top.left, bottom["left"]])
    right = np.concatenate([top.right, bottom["right"]])
    first = np.concatenate([top.first * 0, bottom["first"]])
    count = np.concatenate([top.count * 0, bottom["count"]])
    for arr in (left, right, first, count):
        arr[leaf] = arr[root]
    return BVH(lo_all, hi_all, left, right, first, count, order)


def _balanced(lo, hi) -> BVH:
    """One box a leaf, the boxes in the Morton order of their centres, each node's range
    split in halves (the larger first): ceil(log2 N) + 1 levels, whatever the layout."""
    n = len(lo)
    order = np.argsort(_centre_codes(lo, hi), kind="stable").astype(np.int32)
    left = np.full(2 * n, -1, np.int32)
    right = np.full(2 * n, -1, np.int32)
    first = np.zeros(2 * n, np.int32)
    count = np.zeros(2 * n, np.int32)
    count[0], used, active = n, 1, np.array([0], np.int64)
    while active.size:  # a depth at a time
        active = active[count[active] > 1]
        kids = used + 2 * np.arange(active.size)
        used += 2 * active.size
        big = (count[active] + 1) // 2
        left[active], right[active] = kids, kids + 1
        first[kids], count[kids] = first[active], big
        first[kids + 1], count[kids + 1] = first[active] + big, count[active] - big
        count[active] = 0
        active = np.concatenate([kids, kids + 1])
    empty = np.zeros((used, 3), np.float32)
    tree = BVH(empty, empty, left[:used], right[:used], first[:used], count[:used], order)
    return tree.refit(lo, hi)  # (its boxes, padded)


def _centre_codes(lo, hi) -> np.ndarray:
    """The Morton codes of the boxes' centres in a 1024^3 grid over their bounds."""
    centroid = (lo + hi) * np.float32(0.5)
    c_lo, c_hi = centroid.min(axis=0), centroid.max(axis=0)
    cells = np.clip(((centroid - c_lo) / np.maximum(c_hi - c_lo, 1e-30) * 1024), 0, 1023)
    return _morton(cells.astype(np.int64))


def _morton(cells: np.ndarray) -> np.ndarray:
    """30-bit Morton codes of (N, 3) integer cells in [0, 1024): x, y, z bits interleaved."""
    code = np.zeros(len(cells), np.int64)
    for bit in range(10):
        for axis in range(3):
            code |= ((cells[:, axis] >> bit) & 1) << (3 * bit + 2 - axis)
    return code


def _radix(codes, starts, counts, lo, hi, offset: int) -> dict:
    """Subtrees of the Morton-sorted ranges (``starts``, ``counts``): a range splits where
    its highest differing code bit turns on (or in halves where all codes are equal) until
    it holds at most LEAF_SIZE primitives. Node indices start at ``offset``; boxes are
    unions, from the leaves (``reduceat`` over their ranges) up."""
    n_nodes = 2 * int(counts.sum())
    first = np.zeros(n_nodes, np.int64)
    count = np.zeros(n_nodes, np.int64)
    left = np.full(n_nodes, -1, np.int32)
    right = np.full(n_nodes, -1, np.int32)
    k = len(starts)
    first[:k], count[:k] = starts, counts
    levels, active, used = [], np.arange(k), k
    while active.size:
        active = active[count[active] > LEAF_SIZE]
        if not active.size:
            break
        s, c = first[active], count[active]
        a, b = codes[s], codes[s + c - 1]
        diff = a ^ b
        high = np.frexp(np.maximum(diff, 1).astype(np.float64))[1] - 1  # highest set bit
        target = (b >> high) << high
        cut = np.searchsorted(codes, target, side="left") - s
        cut = np.where(diff == 0, c // 2, np.clip(cut, 1, c - 1))
        kids = used + 2 * np.arange(active.size)
        used += 2 * active.size
        left[active], right[active] = kids + offset, kids + 1 + offset
        first[kids], count[kids] = s, cut
        first[kids + 1], count[kids + 1] = s + cut, c - cut
        count[active] = 0
        levels.append(active)
        active = np.concatenate([kids, kids + 1])
    first, count, left, right = first[:used], count[:used], left[:used], right[:used]
    node_lo = np.empty((used, 3), np.float32)
    node_hi = np.empty((used, 3), np.float32)
    is_leaf = count > 0
    node_lo[is_leaf] = _range_reduce(np.minimum, lo, first[is_leaf], count[is_leaf])
    node_hi[is_leaf] = _range_reduce(np.maximum, hi, first[is_leaf], count[is_leaf])
    for inner in reversed(levels):  # children are done before their parents
        lk, rk = left[inner] - offset, right[inner] - offset
        node_lo[inner] = np.minimum(node_lo[lk], node_lo[rk])
        node_hi[inner] = np.maximum(node_hi[lk], node_hi[rk])
    return {"lo": node_lo, "hi": node_hi, "left": left, "right": right,
            "first": first.astype(np.int32), "count": count.astype(np.int32),
            "root": np.arange(k) + offset}


def _range_reduce(ufunc, values, starts, counts) -> np.ndarray:
    """``ufunc`` over each range [start, start + count) of ``values`` (rows), for ranges
    that tile the array (the leaves of a tree): one ``reduceat`` in start order."""
    order = np.argsort(starts, kind="stable")
    out = np.empty((len(starts),) + values.shape[1:], values.dtype)
    out[order] = ufunc.reduceat(values, starts[order])
    return out


def _segment_starts(counts: np.ndarray) -> np.ndarray:
    return np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)


def _ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The concatenation of arange(s, s + c) for each (s, c), vectorised."""
    total = int(counts.sum())
    offsets = np.arange(total, dtype=np.int64) - np.repeat(_segment_starts(counts), counts)
    return np.repeat(starts.astype(np.int64), counts) + offsets


def _choose_splits(active, first, count, node_lo, node_hi, perm, centroid, lo, hi, weight,
                   leaf_items):
    """For each active node: whether it splits, which of its boxes go left (indexed by
    position in ``perm``), and the two children's boxes (for every active node)."""
    k = active.size
    counts = count[active].astype(np.int64)
    # Deep levels hold few primitives per node: fewer bins cost less and lose nothing.
    nbins = int(min(BINS, max(4, 2 ** int(np.ceil(np.log2(max(counts.mean(), 1)))))))
    pos = _ranges(first[active], counts)  # positions in perm of the level's primitives
    seg = np.repeat(np.arange(k), counts)
    prim = perm[pos]
    box_lo, box_hi = node_lo[active], node_hi[active]
    extent = box_hi - box_lo
    scale = np.where(extent > 0, nbins / np.where(extent > 0, extent, 1.0), 0.0)
    size = k * nbins
    bin_count = np.empty((3, k, nbins), np.int64)
    bin_lo = np.empty((3, 3, size), np.float32)  # [binning axis, component, node * bin]
    bin_hi = np.empty((3, 3, size), np.float32)
    bins = np.empty((3, len(prim)), np.int64)
    for axis in range(3):
        b = ((centroid[prim, axis] - box_lo[seg, axis]) * scale[seg, axis]).astype(np.int64)
        bins[axis] = np.clip(b, 0, nbins - 1)
        key = seg * nbins + bins[axis]
        bin_count[axis] = np.bincount(key, weights=weight[prim],
                                      minlength=size).reshape(k, nbins)
        for comp in range(3):  # 1-D ufunc.at is far faster than on rows
            bin_lo[axis, comp] = np.inf
            bin_hi[axis, comp] = -np.inf
            np.minimum.at(bin_lo[axis, comp], key, lo[prim, comp])
            np.maximum.at(bin_hi[axis, comp], key, hi[prim, comp])
    # (axis, node, bin, component) boxes; prefix (left of plane b+1) and suffix unions.
    bin_lo = bin_lo.reshape(3, 3, k, nbins).transpose(0, 2, 3, 1)
    bin_hi = bin_hi.reshape(3, 3, k, nbins).transpose(0, 2, 3, 1)
    left_lo = np.minimum.accumulate(bin_lo, axis=2)[:, :, :-1]
    left_hi = np.maximum.accumulate(bin_hi, axis=2)[:, :, :-1]
    right_lo = np.minimum.accumulate(bin_lo[:, :, ::-1], axis=2)[:, :, ::-1][:, :, 1:]
    right_hi = np.maximum.accumulate(bin_hi[:, :, ::-1], axis=2)[:, :, ::-1][:, :, 1:]
    n_left = np.cumsum(bin_count, axis=2)[:, :, :-1]
    items = np.bincount(seg, weights=weight[prim], minlength=k).astype(np.int64)
    n_right = items[None, :, None] - n_left
    parent_area = np.maximum(_area(box_lo, box_hi), 1e-30)
    cost = C_TRAVERSE + (_area(left_lo, left_hi) * n_left + _area(right_lo, right_hi) *
                         n_right) / parent_area[None, :, None]
    cost = np.where((n_left > 0) & (n_right > 0), cost, np.inf)
    flat = cost.transpose(1, 0, 2).reshape(k, -1)  # per node: axis-major planes
    best = np.argmin(flat, axis=1)
    best_cost = flat[np.arange(k), best]
    axis, plane = best // (nbins - 1), best % (nbins - 1)
    binned = np.isfinite(best_cost)
    # A leaf of single boxes (the clusters) never stays with more than leaf_items.
    must = (counts > MAX_LEAF) | (counts > leaf_items) & (leaf_items == 1)
    split = binned & ((best_cost < items) | must)
    stuck = ~binned & must  # centroids coincide: split by count
    split |= stuck
    goes_left = np.zeros(len(perm), bool)
    goes_left[pos] = bins[axis[seg], np.arange(len(pos))] <= plane[seg]
    rank = np.arange(len(pos)) - np.repeat(_segment_starts(counts), counts)
    halves = rank < counts[seg] // 2
    goes_left[pos] = np.where(stuck[seg], halves, goes_left[pos])
    rows = np.arange(k)
    boxes = [(left_lo[axis, rows, plane], left_hi[axis, rows, plane]),
             (right_lo[axis, rows, plane], right_hi[axis, rows, plane])]
    if stuck.any():  # boxes of count splits, from their primitives
        for side, member in ((0, halves), (1, ~halves)):
            sel = stuck[seg] & member
            for comp in range(3):
                b_lo = np.full(k, np.inf, np.float32)
                b_hi = np.full(k, -np.inf, np.float32)
                np.minimum.at(b_lo, seg[sel], lo[prim[sel], comp])
                np.maximum.at(b_hi, seg[sel], hi[prim[sel], comp])
                boxes[side][0][stuck, comp] = b_lo[stuck]
                boxes[side][1][stuck, comp] = b_hi[stuck]
    return split, goes_left, boxes
