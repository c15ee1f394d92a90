"""Bounding volume hierarchies (numpy, no GL): every primitive in exactly one reachable
leaf, boxes that contain their contents, and nearest hits equal to brute force on random
rays, for both builders (SAH, and clustered SAH for large inputs)."""

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

from facet.geometry import bvh as B

from reference import ray_triangles, traverse


def _triangles(kind: str, n_sub: int = 3) -> np.ndarray:
    rng = np.random.default_rng(7)
    if kind == "sphere":
        ico = trimesh.creation.icosphere(subdivisions=n_sub)
        return np.asarray(ico.vertices)[np.asarray(ico.faces)].astype(np.float32)
    if kind == "soup":  # random triangles of very different sizes, overlapping
        centres = rng.uniform(-1, 1, (3000, 1, 3))
        return (centres + rng.normal(0, 1, (3000, 3, 3)) * rng.uniform(0.001, 0.3, (3000, 1, 1))
                ).astype(np.float32)
    if kind == "duplicates":  # many identical triangles: centroids coincide
        one = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
        return np.concatenate([np.repeat(one[None], 500, 0),
                               rng.uniform(-1, 1, (100, 3, 3)).astype(np.float32)])
    raise ValueError(kind)


def _check_structure(b: B.BVH, tri: np.ndarray) -> None:
    covered = np.zeros(len(tri), int)
    frontier = np.array([0])
    while frontier.size:
        for f in frontier[b.left[frontier] < 0]:
            prims = b.order[b.first[f]: b.first[f] + b.count[f]]
            covered[prims] += 1
            assert b.count[f] >= 1
            assert np.all(tri[prims].min(axis=1) >= b.lo[f] - 1e-6)
            assert np.all(tri[prims].max(axis=1) <= b.hi[f] + 1e-6)
        inner = frontier[b.left[frontier] >= 0]
        for child in (b.left[inner], b.right[inner]):
            assert np.all(b.lo[child] >= b.lo[inner] - 1e-6)
            assert np.all(b.hi[child] <= b.hi[inner] + 1e-6)
        frontier = np.concatenate([b.left[inner], b.right[inner]])
    assert np.all(covered == 1)


@pytest.mark.parametrize("builder", ["sah", "clustered"])
@pytest.mark.parametrize("kind", ["sphere", "soup", "duplicates"])
def test_every_primitive_in_one_leaf_inside_its_boxes(builder, kind):
    tri = _triangles(kind)
    b = B.build_bvh(tri.min(axis=1), tri.max(axis=1), builder)
    _check_structure(b, tri)
    leaves = b.count[b.left < 0]
    assert leaves.max() <= B.MAX_LEAF


def test_large_inputs_take_the_clustered_builder_and_stay_close_to_full_sah():
    """The clustered build's SAH cost stays within 15% of the full binned SAH's."""
    tri = _triangles("sphere", 6)  # 81920 triangles > SAH_LIMIT
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    full, fast = B._sah(lo, hi), B.build_bvh(lo, hi)

    def cost(b):
        area = B._area(b.lo, b.hi) / B._area(b.lo[0], b.hi[0])
        total, frontier = 0.0, np.array([0])
        while frontier.size:
            leaf = b.left[frontier] < 0
            total += area[frontier[~leaf]].sum() * B.C_TRAVERSE
            total += (area[frontier[leaf]] * b.count[frontier[leaf]]).sum()
            inner = frontier[~leaf]
            frontier = np.concatenate([b.left[inner], b.right[inner]])
        return total

    _check_structure(fast, tri)
    assert len(fast.left) != len(full.left)  # really the other builder
    assert cost(fast) < 1.15 * cost(full)


TRIS = {kind: _triangles(kind) for kind in ("sphere", "soup", "duplicates")}
TREES = {(kind, name): B.build_bvh(t.min(axis=1), t.max(axis=1), name)
         for kind, t in TRIS.items() for name in ("sah", "clustered")}


@settings(max_examples=150, deadline=None)
@given(kind=st.sampled_from(sorted(TRIS)), builder=st.sampled_from(["sah", "clustered"]),
       origin=st.tuples(*[st.floats(-3, 3)] * 3), target=st.tuples(*[st.floats(-1, 1)] * 3))
def test_nearest_hit_equals_brute_force(kind, builder, origin, target):
    tri = TRIS[kind]
    # An irrational nudge of both ends keeps rays off exact vertices and edges, where a
    # hit or a miss depends on the last bit of the barycentric sums (brute force and the
    # tree test the same triangle in batches of different sizes): a ray aimed at (0, -1, 0),
    # the sphere's pole vertex, once found the tree's triangle there and not brute force's.
    o = np.array(origin) + np.array([np.pi, np.e, np.sqrt(2)]) * 1e-4
    d = np.array(target) + np.array([np.sqrt(3), np.pi / 2, np.e / 2]) * 1e-4 - o
    if np.linalg.norm(d) < 1e-3:
        return
    d /= np.linalg.norm(d)
    brute = ray_triangles(tri, o, d)
    t, hit = traverse(TREES[kind, builder], tri, o, d)
    assert t == pytest.approx(brute.min()) if np.isfinite(brute.min()) else hit == -1
    if hit >= 0:
        assert ray_triangles(tri[[hit]], o, d)[0] == pytest.approx(brute.min())


def test_a_single_primitive_is_a_one_leaf_tree():
    tri = _triangles("sphere")[:1]
    b = B.build_bvh(tri.min(axis=1), tri.max(axis=1))
    assert len(b.left) == 1 and b.count[0] == 1 and b.depth == 1
    with pytest.raises(ValueError):
        B.build_bvh(np.zeros((0, 3)), np.zeros((0, 3)))


@pytest.mark.parametrize("builder", ["sah", "clustered"])
@pytest.mark.parametrize("kind", ["sphere", "soup", "duplicates"])
def test_a_refitted_tree_bounds_the_moved_primitives(builder, kind):
    """Refit (skinned and morphed poses): the rest pose's tree over triangles bent and
    stretched keeps every primitive inside its leaf and every child inside its parent,
    finds the nearest hits brute force finds, and refitting unmoved triangles gives the
    built boxes back (SAH's; the clustered builder's boxes of clusters may be looser)."""
    tri = _triangles(kind)
    rest = B.build_bvh(tri.min(axis=1), tri.max(axis=1), builder)
    same = rest.refit(tri.min(axis=1), tri.max(axis=1))
    if builder == "sah":
        np.testing.assert_array_equal(same.lo, rest.lo)
        np.testing.assert_array_equal(same.hi, rest.hi)
    # (within the padding: the clustered builder pads its boxes before uniting them)
    assert np.all(same.lo >= rest.lo - 1e-5) and np.all(same.hi <= rest.hi + 1e-5)
    angle = tri[..., 0:1] * 1.3  # a bend about z growing along x, and a stretch in y
    moved = np.concatenate([tri[..., 0:1] * np.cos(angle) - tri[..., 1:2] * np.sin(angle),
                            (tri[..., 0:1] * np.sin(angle) + tri[..., 1:2] * np.cos(angle))
                            * 1.5, tri[..., 2:3]], axis=-1).astype(np.float32)
    fit = rest.refit(moved.min(axis=1), moved.max(axis=1))
    _check_structure(fit, moved)
    rng = np.random.default_rng(3)
    for _ in range(20):
        o = rng.uniform(-3, 3, 3)
        d = rng.uniform(-1, 1, 3) - o
        d /= np.linalg.norm(d)
        brute = ray_triangles(moved, o, d)
        t, hit = traverse(fit, moved, o, d)
        assert t == pytest.approx(brute.min()) if np.isfinite(brute.min()) else hit == -1


def test_the_top_level_has_one_placed_object_a_leaf():
    """Each test of a placed object is a whole mesh traversal: the top level splits down to
    single objects, so an object is tested only where its own box is hit (four to a leaf,
    a ray through a leaf's box traversed all four: the glTF spheres scene of
    benchmarks/pathtrace.py, 123 objects, 25% slower a path)."""
    import facet
    from facet.render.rays.pack import pack_instances

    scene = facet.Scene()
    rng = np.random.default_rng(3)
    mesh = facet.primitives.sphere(0.1, segments=8, rings=4)
    for p in rng.uniform(-2, 2, (40, 3)):
        scene.add(mesh, transform=facet.transforms.translate(tuple(p)))
    rows, tlas, unbounded, ordered = pack_instances(
        scene.objects, {id(mesh): 0}, lambda m: (1.0, 1.0, 1.0), {})
    children = tlas.reshape(-1, 4, 4)[:, [0, 2]]  # (left lo, ref), (right lo, ref)
    counts = tlas.reshape(-1, 4, 4)[:, [1, 3], 3]
    leaves = children[..., 3] < 0
    assert leaves.sum() == 40 and (counts[leaves] == 1).all()


def test_the_top_level_is_built_again_when_an_object_moves():
    """The top level is kept for a series of renders of one scene (its build was a third of
    a render's Python time with 123 objects), and made anew when a box changes."""
    import facet
    from facet.render.rays import pack

    scene = facet.Scene()
    mesh = facet.primitives.sphere(0.1, segments=8, rings=4)
    for x in range(6):
        scene.add(mesh, transform=facet.transforms.translate((float(x), 0.0, 0.0)))

    def packed():
        return pack.pack_instances(scene.objects, {id(mesh): 0}, lambda m: (1.0,) * 3, {})

    first = packed()
    np.testing.assert_array_equal(packed()[1], first[1])
    scene.objects[0].transform = facet.transforms.translate((2.5, 3.0, 0.0))
    moved = packed()
    pack._TOP_LEVELS.clear()
    fresh = packed()
    assert not np.array_equal(moved[1], first[1])
    np.testing.assert_array_equal(moved[1], fresh[1])
    np.testing.assert_array_equal(moved[0], fresh[0])


def _dequantised_leaves(nodes):
    """Each leaf of a packed mesh hierarchy (facet.render.rays.pack pack_mesh_nodes):
    (first, count, lo, hi) with its box back in object space (float64)."""
    from facet.render.rays.pack import LEAF_BIT

    origin = nodes[0, 0, :3].view(np.float32).astype(np.float64)
    scale = nodes[0, 1, :3].view(np.float32).astype(np.float64)
    out = []
    for child in nodes[1:].reshape(-1, 4):
        if not child[3] & LEAF_BIT or not (child[3] >> 24) & 0x7F:
            continue  # (an inner child, or a single-leaf root's leaf of nothing)
        lo = np.array([child[0] & 0xFFFF, child[0] >> 16, child[1] & 0xFFFF], np.float64)
        hi = np.array([child[1] >> 16, child[2] & 0xFFFF, child[2] >> 16], np.float64)
        out.append((int(child[3] & 0xFFFFFF), int((child[3] >> 24) & 0x7F),
                    lo / scale + origin, hi / scale + origin))
    return out


@pytest.mark.parametrize("case", ["sphere", "flat", "far and small", "one triangle", "line"])
def test_quantised_boxes_hold_their_triangles(case):
    """A mesh's hierarchy is packed with 16-bit boxes in its own frame (half the texel
    fetches of float boxes): every triangle lies in its leaf's box, with room for what
    float32 loses carrying a ray into that frame, for a flat mesh, a small mesh far from
    the origin and a single triangle as for a sphere; every triangle is in one leaf."""
    import facet
    from facet.render.rays.pack import mesh_data

    sphere = trimesh.creation.icosphere(subdivisions=3)
    v, f = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    if case == "flat":
        v = v * [3.0, 0.0, 2.0]
    if case == "far and small":
        v = v * 1e-3 + [5e4, -2e4, 1e3]
    if case == "one triangle":
        v, f = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]])
    if case == "line":
        v = v * [0.0, 0.0, 1.0] + [1.0, 2.0, 0.0]
    data = mesh_data(facet.Mesh(v, f))
    tri = data.tris[:, 0, :3][:, None, :] + np.concatenate(
        [np.zeros((len(data.tris), 1, 3)), data.tris[:, 1:, :3]], axis=1)
    tri = np.stack([tri[:, 0], tri[:, 0] + tri[:, 1] - tri[:, 0], tri[:, 0] + tri[:, 2]
                    - tri[:, 0]], axis=1)  # (N, 3, 3) object-space corners
    seen = np.zeros(len(tri), int)
    for first, count, lo, hi in _dequantised_leaves(data.nodes):
        corners = tri[first:first + count].reshape(-1, 3).astype(np.float64)
        room = 2.0 ** -21 * np.abs(corners).max() + 1e-30
        assert (corners >= lo - room).all() and (corners <= hi + room).all(), case
        seen[first:first + count] += 1
    assert (seen == 1).all()


def test_a_one_leaf_mesh_beside_others_is_traced_exactly():
    """A floor of two triangles (one leaf: its root's other child is a leaf of nothing)
    beside a box: each pixel sees the nearer of the two as each alone shows it (the empty
    child was once an inner reference to the mesh's header: rays by the box saw nothing)."""
    import facet
    from facet.scene.pbr import PbrMaterial

    cam = facet.Camera.look_at((0, 1.4, 3.2), (0, 0.4, 0), fov_y=35, near=0.5, far=20)
    grey = PbrMaterial(base_color=(0.6,) * 3, metallic=0.0)

    def depth(*parts):
        scene = facet.Scene(ambient=0.3)
        for part, matrix in parts:
            scene.add(part, grey, matrix)
        with facet.Renderer(64, 64) as r:
            return r.render(scene, cam, engine="trace", outputs=("color", "depth")).depth

    floor = (facet.primitives.plane(6.0), np.eye(4))
    box = (facet.primitives.cube(0.5), facet.transforms.translate((-0.2, 0.25, -1.0)))
    def seen(d):  # (0 where nothing is hit)
        return np.where(d > 0, d, np.inf)

    both, alone = seen(depth(floor, box)), np.minimum(seen(depth(floor)), seen(depth(box)))
    np.testing.assert_allclose(both, alone, rtol=1e-5)
    assert np.isfinite(both).sum() > 2000


def _chain(n: int, base: float) -> tuple[np.ndarray, np.ndarray]:
    """n triangles across the x axis at x = base^-k (the hierarchy grows deep where they
    crowd towards 0); two of every three moved off the axis so that their boxes hold it and
    they do not: a ray along it opens boxes it finds nothing in, and waits on the stack."""
    x = float(base) ** -np.arange(n)
    s = np.full(n, 0.01)
    off = np.where(np.arange(n) % 3 == 0, 0.0, -0.2) * s
    corners = [np.stack([x, -s + off, -s + off], 1), np.stack([x, s + off, -s + off], 1),
               np.stack([x, -s + off, s + off], 1)]
    return np.stack(corners, 1).reshape(-1, 3), np.arange(3 * n).reshape(-1, 3)


def test_the_stacks_are_as_deep_as_the_scene_needs():
    """A mesh's stack holds a waiting child per level of the deepest hierarchy but the last
    two (test_a_mesh_stack_of_depth_less_two_holds_every_waiting_child), the top
    level's one more than the objects up to 16, then 16 (its tree built to fit) up to
    16,384 objects, an array of 48 above; in variables up to 32, in an array above."""
    from facet.render.rays.pack import stack_defines, top_levels

    assert stack_defines(1, 1) == {"MESH_STACK": 8, "TOP_STACK": 8, "REGISTER_STACK": 8}
    assert stack_defines(21, 8) == {"MESH_STACK": 24, "TOP_STACK": 16, "REGISTER_STACK": 24}
    assert stack_defines(43, 31) == {"MESH_STACK": 48, "TOP_STACK": 16, "REGISTER_STACK": 16}
    assert stack_defines(9, 500) == {"MESH_STACK": 8, "TOP_STACK": 16, "REGISTER_STACK": 16}
    assert stack_defines(11, 500) == {"MESH_STACK": 16, "TOP_STACK": 16, "REGISTER_STACK": 16}
    assert stack_defines(10, 20000) == {"MESH_STACK": 8, "TOP_STACK": 48,
                                        "REGISTER_STACK": 8}
    assert top_levels(500) == top_levels(1 << 14) == 15 and top_levels(20000) == 47


@pytest.mark.parametrize("n", [1, 2, 3, 7, 125, 1000, 16384])
def test_a_balanced_hierarchy_has_log2_levels_and_holds_every_box(n):
    """The top level's fallback where SAH's tree is deeper than its stack holds."""
    import math

    rng = np.random.default_rng(n)
    lo = rng.uniform(-10, 10, (n, 3)) * rng.uniform(0, 1, (n, 1)) ** 3  # (clustered)
    hi = lo + rng.uniform(0.01, 2, (n, 3))
    bvh = B.build_bvh(lo, hi, "balanced")
    assert bvh.depth == math.ceil(math.log2(n)) + 1
    reach = _reachable(bvh)
    leaf = np.flatnonzero(bvh.left < 0)
    leaf = leaf[np.isin(leaf, reach)]
    assert (bvh.count[leaf] == 1).all() and sorted(bvh.order[bvh.first[leaf]]) == list(range(n))
    boxes = bvh.order[bvh.first[leaf]]
    assert (bvh.lo[leaf] <= lo[boxes]).all() and (bvh.hi[leaf] >= hi[boxes]).all()
    inner = np.flatnonzero(bvh.left >= 0)
    for child in (bvh.left[inner], bvh.right[inner]):
        assert (bvh.lo[inner] <= bvh.lo[child]).all() and (bvh.hi[inner] >= bvh.hi[child]).all()


def _reachable(bvh) -> np.ndarray:
    out, frontier = [], np.array([0])
    while frontier.size:
        out.append(frontier)
        inner = frontier[bvh.left[frontier] >= 0]
        frontier = np.concatenate([bvh.left[inner], bvh.right[inner]])
    return np.concatenate(out)


def test_a_top_level_too_deep_for_its_stack_is_built_balanced(renderer, monkeypatch):
    """A top level whose SAH tree is deeper than the program's stack (here one of 8
    entries over 40 objects in a line of growing gaps) is built balanced: the objects
    each ray finds are those the default program finds."""
    import facet
    from facet.geometry.camera import Camera
    from facet.render.rays import pack

    scene = facet.Scene()
    for i in range(40):
        scene.add(facet.primitives.cube(0.8),
                  transform=facet.transforms.translate((1.1 ** i - 20.0, 0.0, 0.0)))
    camera = Camera.look_at((0.0, 0.0, 60.0), (0.0, 0.0, 0.0), fov_y=10)
    outputs = ("depth", "ids")
    with facet.Renderer(160, 40) as r:
        want = r.render(scene, camera, engine="trace", outputs=outputs)
    built = []
    real = pack.build_bvh
    monkeypatch.setattr(pack, "build_bvh",
                        lambda *a, **k: built.append(a[2] if len(a) > 2 else "sah") or
                        real(*a, **k))
    monkeypatch.setattr(pack, "TOP_REGISTERS", 8)
    pack._TOP_LEVELS.clear()
    with facet.Renderer(160, 40) as r:
        got = r.render(scene, camera, engine="trace", outputs=outputs)
        assert r._engines["trace"].rays._stacks["TOP_STACK"] == 8
    pack._TOP_LEVELS.clear()
    assert "balanced" in built
    np.testing.assert_array_equal(got.object_ids, want.object_ids)
    np.testing.assert_array_equal(got.depth, want.depth)
    assert len(np.unique(want.object_ids[want.object_ids >= 0])) > 30


def _comb(m: int, side: int):
    """A hierarchy of m + 2 levels that a ray along +x from x = -1 fills: root R0, each
    R_i's children R_(i+1) (nearer) and a side node S_i of two one-triangle leaves (farther),
    R_m two leaves. Every triangle stands across the x axis, its box holding the axis, and
    all but S_side's first miss it (corners moved off, as _chain's), so the ray descends to
    R_m with S_(m-1) ... S_0 waiting, m = depth - 2 entries, and finds its hit in S_side's.
    (vertices, faces, the BVH, the hit's x)."""
    s = 0.01
    xs = [1.0 + 0.1 * (m - i) + d for i in range(m) for d in (0.0, 0.05)] + [0.5, 0.55]
    tris = []
    for k, x in enumerate(xs):
        if k == 2 * side:  # (wide, the axis well inside it)
            tris.append([(x, -s, -s), (x, 3 * s, -s), (x, -s, 3 * s)])
        else:
            o = -0.2 * s
            tris.append([(x, -s + o, -s + o), (x, s + o, -s + o), (x, -s + o, s + o)])
    v = np.array(tris, np.float32).reshape(-1, 3)
    t = v.reshape(-1, 3, 3)
    t_lo, t_hi = t.min(axis=1) - 1e-4, t.max(axis=1) + 1e-4
    lo, hi, left, right, first, count = [], [], [], [], [], []

    def node(prims, kids=None):
        lo.append(t_lo[prims].min(axis=0))
        hi.append(t_hi[prims].max(axis=0))
        left.append(-1), right.append(-1), first.append(prims[0] if kids is None else 0)
        count.append(len(prims) if kids is None else 0)
        return len(lo) - 1

    def inner(a, b):
        k = node(list(range(len(xs))))  # (its box set below, from its children's)
        left[k], right[k] = a(), b()
        lo[k], hi[k] = np.minimum(lo[left[k]], lo[right[k]]), \
            np.maximum(hi[left[k]], hi[right[k]])
        first[k] = count[k] = 0
        return k

    def r(i):
        if i == m:
            return inner(lambda: node([2 * m]), lambda: node([2 * m + 1]))
        return inner(lambda: inner(lambda: node([2 * i]), lambda: node([2 * i + 1])),
                     lambda: r(i + 1))

    r(0)
    tree = B.BVH(np.array(lo, np.float32), np.array(hi, np.float32), np.array(left, np.int32),
                 np.array(right, np.int32), np.array(first, np.int32),
                 np.array(count, np.int32), np.arange(len(xs), dtype=np.int32))
    return v, np.arange(len(v)).reshape(-1, 3), tree, xs[2 * side]


@pytest.mark.parametrize("m", [8, 16, 32, 40])
def test_a_mesh_stack_of_depth_less_two_holds_every_waiting_child(renderer, monkeypatch, m):
    """pack.stack_defines gives a mesh hierarchy of D levels D - 2 entries (rounded up to
    8): in a comb that fills them exactly (_comb: 8, 16, 32 in variables, 40 in an array)
    the ray along its axis finds the triangle in the entry pushed first (variables: those
    drop the bottom entry when full) or last (an array: it drops the entry pushed onto a
    full one); with 8 variables fewer, or an array of one entry fewer, that entry is lost
    and the ray finds nothing (so the scene does fill the stack)."""
    import facet
    from facet.render.rays import pack

    in_array = m > pack.REGISTER_LIMIT
    v, f, tree, hit_x = _comb(m, m - 1 if in_array else 0)
    assert tree.depth == m + 2
    monkeypatch.setattr(pack, "build_bvh", lambda lo, hi: tree)
    stacks = pack.stack_defines
    assert stacks(m + 2, 1)["MESH_STACK"] == m
    cam = facet.Camera.look_at((-1.0, 0, 0), (1.0, 0, 0), ortho_height=0.004, near=0.01,
                               far=10)

    def depth(mesh_stack=None):
        if mesh_stack is not None:
            monkeypatch.setattr(pack, "stack_defines", lambda d, n: {
                **stacks(d, n), "MESH_STACK": mesh_stack,
                "REGISTER_STACK": mesh_stack if mesh_stack <= pack.REGISTER_LIMIT else 8})
        scene = facet.Scene()
        scene.add(facet.Mesh(v, f))  # (a new mesh: its hierarchy is built again)
        return renderer(8, 8).render(scene, cam, outputs=("depth",), engine="trace",
                                     aa="none").depth

    np.testing.assert_allclose(depth(), hit_x + 1.0, atol=1e-5)  # (from the eye at -1)
    if m > 8:  # (8 variables are the least a program holds)
        assert (depth(m - 1 if in_array else m - 8) == 0).all()


@pytest.mark.parametrize("n, base, stack", [(300, 1.2, 24), (4000, 1.02, 48)])
def test_the_traversal_stack_holds_the_deepest_hierarchy(renderer, n, base, stack):
    """A mesh traversal's stack is as deep as the scene's deepest hierarchy
    (pack.stack_defines): held in shifting variables up to 32 entries, in an array above
    (glsl/trace/stack.glsl). Through both, every pixel of a deep chain of triangles, seen
    along it from either end, finds the nearest triangle that the equations find."""
    import facet
    from facet.render.rays.pack import mesh_data, stack_defines

    from reference import ray_triangles

    v, f = _chain(n, base)
    assert stack_defines(mesh_data(facet.Mesh(v, f)).depth, 1)["MESH_STACK"] == stack
    scene = facet.Scene()
    scene.add(facet.Mesh(v, f))
    size, tri = 24, v[f]
    for eye, target in (((-1.0, 0, 0), (1.0, 0, 0)), ((3.0, 0, 0), (0.0, 0, 0))):
        cam = facet.Camera.look_at(eye, target, ortho_height=0.03, near=0.01, far=10)
        depth = renderer(size, size).render(scene, cam, outputs=("depth",), engine="trace",
                                            aa="none").depth
        inv = np.linalg.inv(cam.projection(size, size) @ cam.view)
        expected = np.zeros((size, size))
        for row in range(size):
            for col in range(size):
                ndc = np.array([2 * (col + 0.5) / size - 1, 1 - 2 * (row + 0.5) / size])
                near, far = (inv @ [*ndc, z, 1.0] for z in (-1.0, 1.0))
                o, d = near[:3] / near[3], far[:3] / far[3] - near[:3] / near[3]
                t = ray_triangles(tri, o, d / np.linalg.norm(d)).min()
                expected[row, col] = t + 0.01 if np.isfinite(t) else 0.0  # from the eye
        assert (expected > 0).sum() > 150  # (a third of the view)
        np.testing.assert_allclose(depth, expected, rtol=0, atol=1e-5)
