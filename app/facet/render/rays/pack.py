"""The ray tracer's scene as arrays of texels (numpy, no GL), in the layout glsl/trace/ reads.

Per mesh, once (``mesh_data``, cached by facet.render.rays.scene while the mesh lives):
its triangles in hierarchy order as (v0, e1, e2), their vertex indices, the vertices'
normal, uv sets, colour and tangent frame (``VERTEX_TEXELS`` each), and its hierarchy
(facet.geometry.bvh) in object space, with both children's boxes in each node. Moving or
instancing a mesh never rebuilds this; a skinned or morphed pose (facet.scene.animation)
refits its rest mesh's hierarchy (built once) to the moved triangles.

Meshes with the same arrays (``same_geometry``: a glTF's spheres that differ only in
their materials share their accessors, as MetalRoughSpheresNoTextures' 98 do) are uploaded
once and share one hierarchy.

Per scene (``pack_geometry``): every mesh's arrays concatenated, references shifted by
their offsets. Per frame, or per supersample when objects move (``pack_instances``): one
row of ``INSTANCE_TEXELS`` texels per placed object (matrices, kind, material) and a top
level hierarchy over their world boxes; infinite planes go first, outside it.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...geometry.bvh import build_bvh
from ...scene.pbr import COLOR_SLOTS
from ..material_record import RECORD_TEXELS, material_record, record_defines
from ..materials import as_pbr

TEX_SHIFT = 12
TEX_WIDTH = 1 << TEX_SHIFT  # texels per texture row (glsl/trace/data.glsl)
NODE_TEXELS = 4  # the top level's nodes: float boxes (pack_nodes)
MESH_NODE_TEXELS = 2  # a mesh's nodes: boxes quantised to 16 bits (pack_mesh_nodes)
QUANT = 65535  # the quantised coordinates' range
VERTEX_TEXELS = 4  # (normal, u), (v, colour rgb), (tangent xyz, handedness), (uv1, alpha, 0)
MATERIAL_ROW = 8  # the material record's texels (facet.render.material_record)
INSTANCE_TEXELS = MATERIAL_ROW + RECORD_TEXELS
# How an image is stored in the texture array: a colour image decoded to linear, one
# decoded only in the sRGB colour mode (a Phong material's: values "as given"), data as is.
LINEAR, AS_GIVEN, DATA = "linear", "as given", "data"
NEAREST = " nearest"  # a suffix of the modes above
KINDS = {"mesh": 0, "sphere": 1, "plane": 2, "disk": 3, "cylinder": 4, "cone": 5, "box": 6}
# An instance's flags (glsl/trace/scene.glsl): vertex colours, single-sided, and a glass
# volume (KHR_materials_volume) whose mesh bounds none (``open_volume``): traced thin.
FLAG_COLORS, FLAG_ONE_SIDED, FLAG_OPEN_VOLUME = 1, 2, 4


def layout_defines() -> dict:
    """The layout's constants for the GLSL that reads it (glsl/trace/data.glsl)."""
    return {"TEX_SHIFT": TEX_SHIFT, "NODE_TEXELS": NODE_TEXELS,
            "MESH_NODE_TEXELS": MESH_NODE_TEXELS,
            "VERTEX_TEXELS": VERTEX_TEXELS, "INSTANCE_TEXELS": INSTANCE_TEXELS,
            "MATERIAL_ROW": MATERIAL_ROW, **record_defines(),
            "FLAG_COLORS": FLAG_COLORS, "FLAG_ONE_SIDED": FLAG_ONE_SIDED,
            "FLAG_OPEN_VOLUME": FLAG_OPEN_VOLUME,
            **{f"KIND_{name.upper()}": kind for name, kind in KINDS.items()}}
REGISTER_LIMIT = 32  # the largest stack held in variables (glsl/trace/stack.glsl)
# The top level's stack (top_stack): over more than 15 objects TOP_REGISTERS variables,
# the tree built to fit (the glTF spheres' 125 objects: 12% faster than an array of 48,
# whose pushes llvmpipe stores lane by lane; 32 variables were slower than the array),
# over more than TOP_CAPPED objects an array of TOP_ARRAY.
TOP_REGISTERS = 16
TOP_CAPPED = 1 << 14  # (a balanced tree of 15 levels has that many leaves)
TOP_ARRAY = 48
MAX_REFERENCE = 1 << 24  # node and triangle indices are exact in float32 up to here
EMPTY_CHILD = ((1e30, 1e30, 1e30, -1.0), (-1e30, -1e30, -1e30, 0.0))  # lo > hi: never hit


@dataclass
class MeshData:
    """One mesh for the tracer (module docstring); references local to the mesh."""

    tris: np.ndarray  # (N, 3, 4) float32
    index: np.ndarray  # (N, 4) int32
    vertices: np.ndarray  # (V, VERTEX_TEXELS, 4) float32
    nodes: np.ndarray  # (K + 1, MESH_NODE_TEXELS, 4) uint32: a header, then the nodes
    has_colors: bool
    has_tangents: bool
    bounds: np.ndarray | None = None  # (2, 3) object space: points' and lines' with radii
    depth: int = 1  # the hierarchy's levels (stack_defines)


def pack_nodes(bvh) -> np.ndarray:
    """(K, 4, 4) texels of the inner nodes (module docstring of glsl/trace/data.glsl): per
    child its box, and w = packed child index, or -(first + 1) and the count for a leaf."""
    inner = np.flatnonzero(bvh.left >= 0)
    if inner.size == 0:  # a single leaf: a root with that leaf and an empty child
        leaf = np.array([[*bvh.lo[0], -1.0], [*bvh.hi[0], float(bvh.count[0])]])
        return np.concatenate([leaf, EMPTY_CHILD]).reshape(1, 4, 4).astype(np.float32)
    packed = np.full(len(bvh.left), -1, np.int64)
    packed[inner] = np.arange(inner.size)  # the root (0) stays 0
    out = np.empty((inner.size, 4, 4), np.float32)
    for slot, child in enumerate((bvh.left[inner], bvh.right[inner])):
        is_leaf = bvh.left[child] < 0
        out[:, 2 * slot, :3] = bvh.lo[child]
        out[:, 2 * slot, 3] = np.where(is_leaf, -(bvh.first[child] + 1.0), packed[child])
        out[:, 2 * slot + 1, :3] = bvh.hi[child]
        out[:, 2 * slot + 1, 3] = np.where(is_leaf, bvh.count[child], 0)
    return out


LEAF_BIT = 1 << 31  # a mesh node's child reference: a leaf (LEAF_BIT | count << 24 | first)
MAX_LEAF_COUNT = 127


def pack_mesh_nodes(bvh) -> np.ndarray:
    """(K + 1, MESH_NODE_TEXELS, 4) uint32: a mesh's hierarchy with its boxes quantised to
    16 bits (half the texel fetches of a float node; a node visit's fetches were most of
    its time on llvmpipe). Row 0 is the header: the quantisation frame's origin and scale
    (float32 bits), object -> quantised = (p - origin) * scale, an affine map that keeps a
    ray's parameter t. Then one texel per child: (lo.x | lo.y << 16, lo.z | hi.x << 16,
    hi.y | hi.z << 16, reference): an inner child's node index (the header counts as node
    0 of the mesh's block, so the root is node 1), or LEAF_BIT | count << 24 | first (a
    single-leaf mesh's root has a leaf of nothing beside its leaf).
    Boxes are rounded outwards and widened by what float32 loses where the traversal
    carries a ray into the frame (about 2^-20 of the coordinates' size): never smaller
    than the float boxes."""
    inner = np.flatnonzero(bvh.left >= 0)
    lo_all, hi_all = bvh.lo.astype(np.float64), bvh.hi.astype(np.float64)
    lo_root, hi_root = lo_all.min(axis=0), hi_all.max(axis=0)
    size = np.abs(np.concatenate([lo_root, hi_root])).reshape(2, 3).max(axis=0)
    ext = hi_root - lo_root
    # (the mesh's largest extent sets each axis's least margin: a flat mesh's thin axis
    # keeps a scale of the same order as the others')
    margin = np.maximum(np.maximum(ext.max() * 2.0 ** -10, size * 2.0 ** -18), 1e-30)
    origin = lo_root - margin
    scale = QUANT / (ext + 2.0 * margin)
    slack = 1.0 + np.ceil(size * 2.0 ** -20 * scale)  # float32's error, in quantised units

    def quantised(lo, hi):
        q_lo = np.clip(np.floor((lo - origin) * scale) - slack, 0, QUANT).astype(np.uint32)
        q_hi = np.clip(np.ceil((hi - origin) * scale) + slack, 0, QUANT).astype(np.uint32)
        return q_lo, q_hi

    def texels(q_lo, q_hi, ref):
        sixteen = np.uint32(16)
        return np.stack([q_lo[:, 0] | q_lo[:, 1] << sixteen, q_lo[:, 2] | q_hi[:, 0] << sixteen,
                         q_hi[:, 1] | q_hi[:, 2] << sixteen, ref.astype(np.uint32)],
                        axis=1).astype(np.uint32)

    def leaf_ref(first, count):
        if np.any(count > MAX_LEAF_COUNT):
            raise ValueError(f"a hierarchy leaf holds at most {MAX_LEAF_COUNT} primitives")
        count, first = np.asarray(count, np.uint64), np.asarray(first, np.uint64)
        return (np.uint64(LEAF_BIT) | count << np.uint64(24) | first).astype(np.uint32)

    header = np.zeros((1, MESH_NODE_TEXELS, 4), np.uint32)
    header[0, 0, :3] = origin.astype(np.float32).view(np.uint32)
    header[0, 1, :3] = scale.astype(np.float32).view(np.uint32)
    if inner.size == 0:  # a single leaf: a root with that leaf and an empty child
        q_lo, q_hi = quantised(lo_all[:1], hi_all[:1])
        leaf = texels(q_lo, q_hi, leaf_ref(bvh.first[:1], bvh.count[:1]))
        empty = texels(np.zeros((1, 3), np.uint32), np.zeros((1, 3), np.uint32),
                       leaf_ref(np.zeros(1), np.zeros(1)))  # (a leaf of nothing)
        return np.concatenate([header, np.stack([leaf, empty], axis=1)])
    packed = np.full(len(bvh.left), -1, np.int64)
    packed[inner] = np.arange(inner.size) + 1  # (after the header)
    out = np.empty((inner.size, MESH_NODE_TEXELS, 4), np.uint32)
    for slot, child in enumerate((bvh.left[inner], bvh.right[inner])):
        is_leaf = bvh.left[child] < 0
        q_lo, q_hi = quantised(lo_all[child], hi_all[child])
        ref = np.where(is_leaf, leaf_ref(bvh.first[child], bvh.count[child]), packed[child])
        out[:, slot] = texels(q_lo, q_hi, ref.astype(np.uint32))
    return np.concatenate([header, out])


# A mesh's arrays' digest, kept while it lives (same_geometry).
_DIGESTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _digest(mesh) -> bytes:
    if mesh not in _DIGESTS:
        import hashlib

        h = hashlib.blake2b(digest_size=16)
        for a in (mesh.positions, mesh.faces, mesh.normals, mesh.uvs, mesh.uvs1, mesh.colors,
                  mesh._tangents):
            h.update(b"-" if a is None else str((a.dtype, a.shape)).encode())
            if a is not None:
                h.update(np.ascontiguousarray(a).data)
        _DIGESTS[mesh] = h.digest()
    return _DIGESTS[mesh]


def same_geometry(meshes: list, framed: set) -> list[int]:
    """For each of ``meshes``, the index of the first one with the same arrays (positions,
    faces, normals, uv sets, colours, tangents; both framed for a normal map or both not):
    its own where none before it has them. Triangle meshes at rest only (a pose's arrays
    are its own; points and lines are sized per draw). Arrays are hashed only where two
    meshes agree in kind and counts and in their first and last vertices."""
    def rough(m):
        if m.kind != "mesh" or getattr(m, "rest", None) is not None:
            return None
        return (len(m.positions), len(m.faces), id(m) in framed,
                m.positions[0].tobytes(), m.positions[-1].tobytes())

    keys = [rough(m) for m in meshes]
    groups: dict = {}
    for key in keys:
        if key is not None:
            groups[key] = groups.get(key, 0) + 1
    first: dict = {}
    out = []
    for i, (m, key) in enumerate(zip(meshes, keys, strict=True)):
        if key is None or groups[key] < 2:
            out.append(i)
            continue
        out.append(first.setdefault((key, _digest(m)), i))
    return out


# Rest meshes' hierarchies, kept while the rest mesh lives (its poses refit them).
_REST_TREES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def mesh_data(mesh, tangents: bool = False, radii=None) -> MeshData:
    """The tracer's arrays for ``mesh`` (module docstring); its tangent frames when it has
    them or ``tangents`` (a normal map needs them: computed from the uvs, once per mesh).
    Points and lines (``radii``: one per point or segment) become spheres and capsules
    (facet.render.rays.sprites)."""
    if mesh.kind != "mesh":
        from .sprites import sprite_data

        tris, index, vertices, bvh = sprite_data(mesh, radii, VERTEX_TEXELS)
        bounds = np.stack([bvh.lo.min(axis=0), bvh.hi.max(axis=0)]).astype(np.float64)
        return MeshData(tris, index, vertices, pack_mesh_nodes(bvh), mesh.colors is not None,
                        False, bounds, bvh.depth)
    faces = mesh.faces.astype(np.int64)
    tri = mesh.positions[faces].astype(np.float32)  # (N, 3, 3) object space
    rest = getattr(mesh, "rest", None)  # a skinned or morphed pose of this mesh
    if rest is not None:  # its rest pose's tree, refitted (built once per rest mesh)
        if rest not in _REST_TREES:
            at_rest = rest.positions[faces].astype(np.float32)
            _REST_TREES[rest] = build_bvh(at_rest.min(axis=1), at_rest.max(axis=1))
        bvh = _REST_TREES[rest].refit(tri.min(axis=1), tri.max(axis=1))
    else:
        bvh = build_bvh(tri.min(axis=1), tri.max(axis=1))
    tri, faces = tri[bvh.order], faces[bvh.order]  # leaves become contiguous ranges
    tris = np.zeros((len(tri), 3, 4), np.float32)
    tris[:, 0, :3] = tri[:, 0]
    tris[:, 1, :3] = tri[:, 1] - tri[:, 0]
    tris[:, 2, :3] = tri[:, 2] - tri[:, 0]
    index = np.zeros((len(faces), 4), np.int32)
    index[:, :3] = faces
    n = len(mesh.positions)
    vertices = np.zeros((n, VERTEX_TEXELS, 4), np.float32)
    vertices[:, 0, :3] = mesh.normals
    uvs = mesh.uvs if mesh.uvs is not None else np.zeros((n, 2), np.float32)
    vertices[:, 0, 3], vertices[:, 1, 0] = uvs[:, 0], uvs[:, 1]
    vertices[:, 1, 1:] = 1.0 if mesh.colors is None else mesh.colors[:, :3]
    frames = mesh.tangents if tangents or mesh._tangents is not None else None
    if frames is not None:
        vertices[:, 2] = frames
    if mesh.uvs1 is not None:
        vertices[:, 3, :2] = mesh.uvs1
    vertices[:, 3, 2] = 1.0 if mesh.colors is None else mesh.colors[:, 3]
    return MeshData(tris, index, vertices, pack_mesh_nodes(bvh), mesh.colors is not None,
                    frames is not None, depth=bvh.depth)


def top_stack(objects: int) -> int:
    """The top level's stack entries over ``objects`` placed objects: one more than their
    count up to TOP_REGISTERS (a tree of n leaves has at most n levels, and the walk holds a
    waiting child per level and the two new ones of the last), rounded up to a multiple of
    8; then TOP_REGISTERS, or above TOP_CAPPED objects TOP_ARRAY. The tree has at most
    ``top_levels``: binned SAH where its tree is that shallow, else a balanced one (its
    ceil(log2 n) + 1 levels fit: 15 for TOP_CAPPED objects, 47 for 2^46)."""
    if objects + 1 <= TOP_REGISTERS:
        return 8 * -(-(objects + 1) // 8)
    return TOP_REGISTERS if objects <= TOP_CAPPED else TOP_ARRAY


def top_levels(objects: int) -> int:
    """The most levels of the top level over ``objects`` (its stack's entries less one)."""
    return top_stack(objects) - 1


def stack_defines(deepest: int, objects: int) -> dict:
    """The traversals' stack depths of glsl/trace/stack.glsl for meshes whose deepest
    hierarchy has ``deepest`` levels and ``objects`` placed objects. MESH_STACK: entries
    enough for the deepest hierarchy, ``deepest`` - 2 (glsl/trace/bvh.glsl trace_mesh
    pushes only at a node both of whose children are inner nodes, so at most once a level
    from the root to the last level but two, each entry from a level above the node being
    visited), rounded up to a multiple of 8 so that scenes of similar meshes share their
    programs. TOP_STACK: ``top_stack``. REGISTER_STACK: the variables that the stacks of at
    most REGISTER_LIMIT entries need (each one a vector select more on every push and pop:
    a dataset's 20k-triangle model of 17 levels, 16 entries rather than 24: 6% faster)."""
    mesh = 8 * -(-max(deepest - 2, 1) // 8)
    top = top_stack(objects)
    held = [n for n in (mesh, top) if n <= REGISTER_LIMIT]
    return {"MESH_STACK": mesh, "TOP_STACK": top, "REGISTER_STACK": max(held, default=8)}


def pack_geometry(meshes: list[MeshData], max_texels: int) -> dict:
    """Every mesh's arrays in one set (references shifted); ``root``: each mesh's root node.
    InputError when a texture would exceed ``max_texels`` (the GL's size limit)."""
    node_off = np.cumsum([0] + [len(m.nodes) for m in meshes])
    tri_off = np.cumsum([0] + [len(m.tris) for m in meshes])
    vert_off = np.cumsum([0] + [len(m.vertices) for m in meshes])
    nodes = np.concatenate([m.nodes for m in meshes]).copy()
    refs = nodes[:, :, 3].astype(np.int64)  # the children's references (headers': 0)
    own = np.repeat(np.arange(len(meshes)), [len(m.nodes) for m in meshes])[:, None]
    header = np.zeros(len(nodes), bool)
    header[node_off[:-1]] = True
    leaf = (refs & LEAF_BIT) != 0
    shifted = np.where(leaf, refs + tri_off[own], refs + node_off[own])
    nodes[:, :, 3] = np.where(header[:, None], refs, shifted).astype(np.uint32)
    index = np.concatenate([m.index + np.array([1, 1, 1, 0]) * vert_off[i]
                            for i, m in enumerate(meshes)])
    out = {"tris": np.concatenate([m.tris for m in meshes]).reshape(-1, 4),
           "index": index.astype(np.int32),
           "vertices": np.concatenate([m.vertices for m in meshes]).reshape(-1, 4),
           "nodes": nodes.reshape(-1, 4), "root": node_off[:-1], "first_tri": tri_off[:-1]}
    if tri_off[-1] > MAX_REFERENCE or node_off[-1] > MAX_REFERENCE:
        raise InputError(f"the scene has {int(tri_off[-1]):,} triangles; the ray tracer "
                         f"holds at most {MAX_REFERENCE:,} (its references are float32); "
                         "use the rasterizer (engine='raster') or simplify the meshes")
    for name in ("tris", "vertices", "nodes"):
        if len(out[name]) > max_texels:
            raise InputError(f"the scene has {int(tri_off[-1]):,} triangles, more than the "
                             f"ray tracer can hold on this GL ({name} would need "
                             f"{len(out[name]):,} texels of {max_texels:,}); use the "
                             "rasterizer (engine='raster') or simplify the meshes")
    return out


def pack_instances(objects, mesh_root: dict, material_color, layers: dict,
                   boxes: dict | None = None, levels: int | None = None):
    """(instances (n, INSTANCE_TEXELS, 4) float32, top-level nodes or None, unbounded count,
    the objects in instance order) for the scene's ``objects``: infinite planes first, then
    the rest in top-level order
    (one bounded object needs no top level: the tracer tests it directly).
    ``mesh_root``: id(mesh) -> its root node; ``layers``: id(texture) -> texture layer;
    ``boxes``: id(mesh) -> its (2, 3) object-space box where not its mesh's bounds (the
    spheres and capsules of points and lines)."""
    unbounded = [o for o in objects if o.infinite]
    bounded = [o for o in objects if not o.infinite]
    tlas = None
    if len(bounded) > 1:
        boxes = _world_boxes(bounded, boxes or {})
        order, tlas = _top_level(boxes, top_levels(len(objects)) if levels is None
                                 else levels)
        bounded = [bounded[i] for i in order]
        tlas = tlas.copy()
        tlas[:, [0, 2], 3] = np.where(tlas[:, [0, 2], 3] >= 0, tlas[:, [0, 2], 3],
                                      tlas[:, [0, 2], 3] - len(unbounded))
    ordered = unbounded + bounded
    rows = np.zeros((len(ordered), INSTANCE_TEXELS, 4), np.float32)
    if not ordered:
        return rows, tlas, len(unbounded), ordered
    m = np.array([o.transform for o in ordered], dtype=np.float64)
    rows[:, 0:3] = np.linalg.inv(m)[:, :3]  # (all at once: a scene of many objects)
    rows[:, 3:6] = m[:, :3]
    for i, o in enumerate(ordered):  # one row per placed object, not per triangle
        _instance(rows[i], o, mesh_root, material_color, layers)
    return rows, tlas, len(unbounded), ordered


_TOP_LEVELS: dict = {}  # the world boxes' bytes -> (order, packed nodes): the last few


def _top_level(boxes: np.ndarray, levels: int):
    """The top level over placed objects' world ``boxes`` (n, 2, 3), of at most ``levels``
    levels (top_levels): (their order, its packed nodes), built again only when a box
    changed (a series of renders of one scene builds it once)."""
    key = (boxes.tobytes(), levels)
    made = _TOP_LEVELS.pop(key, None)
    if made is None:
        bvh = build_bvh(boxes[:, 0], boxes[:, 1], leaf_items=1)
        if bvh.depth > levels:  # (a layout SAH splits unevenly: the program's stack holds
            bvh = build_bvh(boxes[:, 0], boxes[:, 1], "balanced")  # this one)
        made = (bvh.order, pack_nodes(bvh))
    _TOP_LEVELS[key] = made
    while len(_TOP_LEVELS) > 4:
        del _TOP_LEVELS[next(iter(_TOP_LEVELS))]
    return made


def _instance(row, obj, mesh_root, material_color, layers) -> None:
    """The rest of ``obj``'s row (its matrices are there): kind, flags and material."""
    mat = obj.material
    if obj.shape is not None:
        kind, root = KINDS[obj.shape.kind], 0
        params = np.array(obj.shape.params, dtype=np.float64)
        row[7, :len(params)] = np.where(np.isinf(params), 1e30, params)
    else:
        kind, root = KINDS["mesh"], mesh_root[id(obj.mesh)]
    # A single-sided material's back faces are not there, but for a transmitting volume's
    # (its inside is seen through them).
    pbr = as_pbr(mat)
    one_sided = not pbr.double_sided and not (pbr.transmission > 0 and pbr.thickness > 0)
    flags = (FLAG_COLORS if obj.mesh.colors is not None and obj.shape is None else 0) | \
        (FLAG_ONE_SIDED if one_sided else 0) | (FLAG_OPEN_VOLUME if open_volume(obj) else 0)
    row[6] = (kind, root, obj.id, flags)
    phong_image = layers.get((id(mat.texture), AS_GIVEN), -1) if mat.texture is not None \
        else -1
    row[MATERIAL_ROW:] = material_record(
        mat, material_color(mat),
        lambda name, slot: layers.get((id(slot.texture), slot_mode(name, slot)), -1),
        phong_image)


def open_volume(obj) -> bool:
    """Whether ``obj`` is glass with a volume (KHR_materials_volume: transmission and a
    thickness) on a surface that bounds none: a mesh that is not closed and consistently
    wound (facet.scene.mesh.Mesh.closed), a plane or a disk. Tracing refraction into and
    out of such a "volume" would bend light as a solid block does; the tracers trace it as
    thin-walled glass instead, absorbing over the thickness the file gives (what the
    thickness is for: the rasterizer's refraction, glsl/mesh/pbr.frag)."""
    m = as_pbr(obj.material)
    if m.transmission <= 0 or m.thickness <= 0 or obj.mesh.kind != "mesh":
        return False
    if obj.shape is not None:
        return obj.shape.kind in ("plane", "disk")
    return not obj.mesh.closed


def open_volume_lines(scene, noun: str) -> list[str]:
    """The warning line for glass volumes on open surfaces (``open_volume``)."""
    n = sum(open_volume(o) for o in scene.objects)
    if not n:
        return []
    return [f"{noun} traces KHR_materials_volume on surfaces that bound no volume (open or "
            f"inconsistently wound meshes) as thin-walled glass that absorbs over the "
            f"material's thickness ({n} of {len(scene.objects)} objects)"]


def slot_mode(name: str, slot) -> str:
    """How the image of texture slot ``name`` (a TextureSlot) is stored: colour images
    decoded to linear, data as is; NEAREST added for nearest filtering (resized by
    repeating texels, so that a texel's centre reads its own value)."""
    mode = LINEAR if name in COLOR_SLOTS else DATA
    return mode + NEAREST if slot.filter[1] == "nearest" else mode


_CORNERS = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)])


def bounded_box(objects, tlas, unbounded: int, boxes: dict | None = None):
    """The (2, 3) world box every ray that hits one of ``objects`` passes through (the top
    level's root, ``tlas`` from pack_instances, or the one bounded object's box; lo > hi
    when there is none); None when one of them is unbounded (an infinite plane)."""
    if unbounded:
        return None
    if tlas is not None:
        root = np.asarray(tlas[0], np.float64)  # (left lo, left hi, right lo, right hi)
        return np.stack([np.minimum(root[0, :3], root[2, :3]),
                         np.maximum(root[1, :3], root[3, :3])])
    bounded = [o for o in objects if not o.infinite]
    if not bounded:
        return np.array([[np.inf] * 3, [-np.inf] * 3])
    return _world_boxes(bounded, boxes or {})[0]


def _world_boxes(objects, boxes: dict) -> np.ndarray:
    """(n, 2, 3) world boxes of ``objects``: each one's object-space box (its shape's, its
    mesh's, or ``boxes``' for id(mesh)) through its transform, corner by corner."""
    b = np.array([o.shape.bounds if o.shape is not None else boxes.get(id(o.mesh),
                                                                       o.mesh.bounds)
                  for o in objects], dtype=np.float64)  # (n, 2, 3)
    corners = np.where(_CORNERS[None].astype(bool), b[:, None, 1], b[:, None, 0])  # (n, 8, 3)
    m = np.array([o.transform for o in objects], dtype=np.float64)
    w = np.einsum("nij,nkj->nki", m[:, :3, :3], corners) + m[:, None, :3, 3]
    return np.stack([w.min(axis=1), w.max(axis=1)], axis=1)


def to_texels(rows: np.ndarray) -> np.ndarray:
    """(n, 4) rows as a (ceil(n / TEX_WIDTH), TEX_WIDTH, 4) image, zero-padded."""
    n = max(len(rows), 1)
    height = -(-n // TEX_WIDTH)
    out = np.zeros((height * TEX_WIDTH, 4), rows.dtype)
    out[:len(rows)] = rows
    return out.reshape(height, TEX_WIDTH, 4)
