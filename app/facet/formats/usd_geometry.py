"""UsdGeom prims -> facet geometry arguments (no GL): Mesh (any faceVertexCounts, fan
triangulated as Hydra does; holes; leftHanded orientation; normals and primvars of every
interpolation), Points, BasisCurves (as lines), and the gprims (Cube, Sphere, Cylinder,
Cone, Capsule, Plane: facet's exact shapes where it has them, turned to the prim's axis).

Primvar interpolation (UsdGeom's): ``constant`` one value, ``uniform`` one per face,
``vertex`` and ``varying`` one per point, ``faceVarying`` one per face corner; indexed
primvars are flattened first. A mesh whose primvars are all per point keeps its points
shared; one with a per-face or per-corner primvar is split into one vertex per corner.
``st`` (or the primvar a material's reader names) are the texture coordinates, (0, 0) the
bottom-left as in OpenGL; ``displayColor`` / ``displayOpacity`` the vertex colours
(linear in USD, sRGB-encoded as facet's vertex colours are).

A mesh's ``subdivisionScheme`` (catmullClark unless authored) is drawn as its control cage,
what usdview draws at its default complexity; with a refinement ``level`` the cage is
refined (facet.formats.subdivide) and drawn with its computed normals, its primvars left
out (said).
"""

from __future__ import annotations

import numpy as np

from ..srgb import linear_to_srgb


class StageSettings:
    """What a file says of its world beyond its objects (a USD stage's upAxis, a URDF's
    z-up): ``up`` ("y" or "z", the framing's and turntables' up axis)."""

    def __init__(self, up: str):
        self.up = up


def matrix(gf) -> np.ndarray:
    """A Gf.Matrix4d (USD's row vectors) as facet's column-vector 4x4."""
    return np.array(gf, dtype=np.float64).reshape(4, 4).T


def _array(value, dtype=np.float64, width: int | None = None) -> np.ndarray | None:
    if value is None:
        return None
    try:
        a = np.asarray(value, dtype=dtype)
        if width is not None:
            a = a.reshape(-1, width)
    except (TypeError, ValueError):  # a primvar of another type (an int for normals)
        return None
    return a


def point_array(prim, time, notes: list | None, where: str) -> np.ndarray | None:
    """A point-based prim's ``points`` (P, 3) float64, or None: when they are not an
    array of three floats (the schema's point3f[]; float3[], color3f[], normal3f[] hold
    the same values), as Hydra too leaves such a prim out, said into ``notes``."""
    from pxr import Vt

    value = prim.GetAttribute("points").Get(time)
    if value is None:
        return None
    if not isinstance(value, Vt.Vec3fArray):  # (the value as authored, whatever its type)
        if notes is not None:
            notes.append(f"{where}: its points are authored as {type(value).__name__} (the "
                         "schema's type is point3f[]); left out")
        return None
    return _array(value, np.float64, 3)


def triangulate(counts: np.ndarray, holes=()) -> tuple[np.ndarray, np.ndarray]:
    """Fan triangles of polygons of ``counts`` corners: ((T, 3) corner numbers into the
    flat faceVertexIndices, (T,) face of each triangle); faces of fewer than 3 corners and
    the hole faces give none."""
    counts = np.asarray(counts, dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]) if len(counts) else counts
    keep = counts >= 3
    if len(holes):
        hole = np.zeros(len(counts), bool)
        h = np.asarray(holes, dtype=np.int64)
        hole[h[(h >= 0) & (h < len(counts))]] = True
        keep &= ~hole
    tris = np.where(keep, counts - 2, 0)
    face = np.repeat(np.arange(len(counts)), tris)
    k = np.arange(int(tris.sum())) - np.repeat(np.cumsum(tris) - tris, tris)  # 0..n-3
    s = starts[face]
    return np.stack([s, s + k + 1, s + k + 2], axis=1), face


def _per_corner(values: np.ndarray, interpolation: str, indices: np.ndarray,
                corners: np.ndarray, faces: np.ndarray) -> np.ndarray | None:
    """Values for each triangle corner (``corners``: (T, 3) positions in the flat
    faceVertexIndices ``indices``; ``faces``: (T,) face of each triangle)."""
    n = len(values)
    if interpolation == "constant":
        return np.broadcast_to(values[:1], (corners.size, values.shape[1]))
    if interpolation == "uniform":
        return None if faces.max(initial=-1) >= n else np.repeat(values[faces], 3, axis=0)
    if interpolation in ("vertex", "varying"):
        at = indices[corners.reshape(-1)]
        return None if at.max(initial=-1) >= n else values[at]
    if interpolation == "faceVarying":
        at = corners.reshape(-1)
        return None if at.max(initial=-1) >= n else values[at]
    return None


def mesh_arguments(prim, time, uv_name: str, notes: list, where: str,
                   level: int = 0) -> dict | None:
    """A UsdGeom.Mesh's facet Mesh arguments (positions, faces, normals, uvs, colors),
    or None when it has no faces; problems said into ``notes``."""
    from pxr import UsdGeom

    mesh = UsdGeom.Mesh(prim)
    points = point_array(prim, time, notes, where)
    counts = _array(mesh.GetFaceVertexCountsAttr().Get(time), np.int64)
    indices = _array(mesh.GetFaceVertexIndicesAttr().Get(time), np.int64)
    if points is None or counts is None or indices is None or not len(counts):
        return None
    if counts.sum() != len(indices) or (len(indices) and (indices.min() < 0 or
                                                        indices.max() >= len(points))):
        notes.append(f"{where}: faceVertexCounts and faceVertexIndices do not agree with "
                     f"its {len(points):,} points; left out")
        return None
    holes = _array(mesh.GetHoleIndicesAttr().Get(time), np.int64)
    scheme = mesh.GetSubdivisionSchemeAttr().Get(time)
    if level > 0 and scheme in ("catmullClark", "loop"):
        return _refined(points, counts, indices, holes, scheme, level, prim, time, notes,
                        where, mesh.GetOrientationAttr().Get(time) == "leftHanded")
    corners, faces = triangulate(counts, () if holes is None else holes)
    if not len(corners):
        return None
    if mesh.GetOrientationAttr().Get(time) == "leftHanded":
        corners = corners[:, [0, 2, 1]]
    api = UsdGeom.PrimvarsAPI(prim)
    per_corner: dict[str, tuple] = {}  # name -> (values, interpolation)
    normals_pv = api.GetPrimvar("normals")
    if normals_pv and normals_pv.HasAuthoredValue():
        per_corner["normals"] = (_array(normals_pv.ComputeFlattened(time), np.float64, 3),
                                 normals_pv.GetInterpolation())
    elif mesh.GetNormalsAttr().HasAuthoredValue():
        per_corner["normals"] = (_array(mesh.GetNormalsAttr().Get(time), np.float64, 3),
                                 mesh.GetNormalsInterpolation())
    for name in dict.fromkeys([uv_name, "st"]):
        pv = api.GetPrimvar(name)
        if pv and pv.HasAuthoredValue():
            per_corner["uvs"] = (_array(pv.ComputeFlattened(time), np.float64, 2),
                                 pv.GetInterpolation())
            break
    colour = api.GetPrimvar("displayColor")
    if colour and colour.HasAuthoredValue():
        per_corner["color"] = (_array(colour.ComputeFlattened(time), np.float64, 3),
                               colour.GetInterpolation())
    opacity = api.GetPrimvar("displayOpacity")
    if opacity and opacity.HasAuthoredValue():
        per_corner["opacity"] = (_array(opacity.ComputeFlattened(time), np.float64, 1),
                                 opacity.GetInterpolation())
    # (a polygonal mesh without normals is flat, as Storm draws it: a vertex a corner)
    flat = (scheme or "catmullClark") in ("none", "bilinear") and "normals" not in per_corner
    shared = not flat and all(interp in ("vertex", "varying", "constant")
                              for _, interp in per_corner.values())
    if shared:  # one vertex per point
        used, remap = np.unique(indices[corners.reshape(-1)], return_inverse=True)
        args = {"positions": points[used].astype(np.float32),
                "faces": remap.reshape(-1, 3).astype(np.uint32), "point_index": used}
        pick = used

        def take(values, interp):
            if interp == "constant":
                return np.broadcast_to(values[:1], (len(used), values.shape[1]))
            return values[pick] if pick.max(initial=-1) < len(values) else None
    else:  # one vertex per triangle corner
        args = {"positions": points[indices[corners.reshape(-1)]].astype(np.float32),
                "faces": np.arange(corners.size, dtype=np.uint32).reshape(-1, 3),
                "point_index": indices[corners.reshape(-1)]}

        def take(values, interp):
            return _per_corner(values, interp, indices, corners, faces)
    for key, (values, interp) in per_corner.items():
        if values is None or not len(values):
            continue
        got = take(values, interp)
        if got is None:
            notes.append(f"{where}: primvar {key} ({interp}, {len(values):,} values) does "
                         "not match the mesh; left out")
            continue
        if key == "normals":
            args["normals"] = np.asarray(got, np.float32)
        elif key == "uvs":
            args["uvs"] = np.asarray(got, np.float32)
        elif key == "color":
            args["colors_rgb"] = np.asarray(got, np.float64)
        else:
            args["colors_alpha"] = np.asarray(got, np.float64)
    scheme = scheme or "catmullClark"
    if "normals" not in args:  # Hydra's (Storm's): a subdivision surface's cage smooth,
        if scheme in ("none", "bilinear"):  # a polygonal mesh flat
            if shared:  # (its normals given but unreadable: split where faces meet)
                args["crease"] = 0.0
            else:
                args["normals"] = _flat_normals(args["positions"])
        else:
            args["normals"] = _smooth_normals(
                points, counts, indices, holes,
                mesh.GetOrientationAttr().Get(time) == "leftHanded", args["point_index"])
    _vertex_colours(args)
    args["subdivision"] = scheme
    return args


def _flat_normals(corners: np.ndarray) -> np.ndarray:
    """(3T, 3) float32: each triangle's unit normal at its three corners (``corners``
    (3T, 3), a vertex a corner); +z where a triangle has no area (nothing of it is drawn)."""
    p = np.asarray(corners, np.float64).reshape(-1, 3, 3)
    a, b = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    n = a[:, [1, 2, 0]] * b[:, [2, 0, 1]] - a[:, [2, 0, 1]] * b[:, [1, 2, 0]]  # a x b
    length = np.sqrt((n * n).sum(axis=1))[:, None]
    n = np.where(length > 0, n / np.where(length > 0, length, 1.0), [0.0, 0.0, 1.0])
    return np.repeat(n, 3, axis=0).astype(np.float32)


def _smooth_normals(points: np.ndarray, counts: np.ndarray, indices: np.ndarray, holes,
                    left: bool, point_index: np.ndarray) -> np.ndarray:
    """(V, 3) float32: each vertex's point's smooth normal as Hydra computes it (the sum
    over the polygons around the point of the cross product of its two edges there: each
    polygon counts once, however it is triangulated), holes and faces of fewer than 3
    corners left out."""
    keep = counts >= 3
    if holes is not None and len(holes):
        h = np.asarray(holes, np.int64)
        keep[h[(h >= 0) & (h < len(counts))]] = False
    starts = np.repeat(np.cumsum(counts) - counts, counts)
    sizes = np.repeat(counts, counts)
    k = np.arange(len(indices)) - starts  # each corner's place in its polygon
    used = np.repeat(keep, counts)
    here = indices[used]
    after = indices[(starts + (k + 1) % np.maximum(sizes, 1))[used]]
    before = indices[(starts + (k - 1) % np.maximum(sizes, 1))[used]]
    turn = np.cross(points[after] - points[here], points[before] - points[here])
    total = np.zeros_like(points)
    np.add.at(total, here, -turn if left else turn)
    norm = np.linalg.norm(total, axis=1, keepdims=True)
    return (total / np.where(norm > 0, norm, 1.0))[point_index].astype(np.float32)


def _refined(points, counts, indices, holes, scheme, level, prim, time, notes, where,
             left) -> dict:
    """A subdivision mesh refined ``level`` times: positions and faces (normals computed),
    its constant display colour kept, other primvars said to be left out."""
    from .subdivide import refine

    if holes is not None and len(holes):
        notes.append(f"{where}: holes are filled when the surface is subdivided")
    keep = counts >= 3
    if not keep.all():  # (faces of fewer corners: no surface)
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        flat = np.concatenate([np.arange(s, s + c) for s, c in zip(starts[keep],
                                                                    counts[keep],
                                                                    strict=True)])
        counts, indices = counts[keep], indices[flat]
    pts, counts, indices = refine(points, counts, indices, scheme, level)
    corners, _ = triangulate(counts)
    if left:
        corners = corners[:, [0, 2, 1]]
    from pxr import UsdGeom

    api = UsdGeom.PrimvarsAPI(prim)
    if any(api.GetPrimvar(n) and api.GetPrimvar(n).HasAuthoredValue() and
           api.GetPrimvar(n).GetInterpolation() != "constant"
           for n in ("st", "displayColor", "displayOpacity", "normals")):
        notes.append(f"{where}: texture coordinates, normals and colours that vary over the "
                     "surface are left out of its subdivided surface")
    rgb, alpha = display_color(prim, time)
    args = {"positions": np.asarray(pts, np.float32),
            "faces": indices[corners.reshape(-1)].reshape(-1, 3).astype(np.uint32),
            "subdivision": "none"}
    if rgb is not None or alpha < 1:
        args["constant_color"] = (rgb, alpha)
    return args


def _vertex_colours(args: dict) -> None:
    """displayColor (linear) and displayOpacity -> sRGB-encoded RGBA vertex colours, left
    out when they are constant (the material's colour carries those)."""
    rgb, alpha = args.pop("colors_rgb", None), args.pop("colors_alpha", None)
    if rgb is None and alpha is None:
        return
    n = len(args["positions"])
    rgb = np.ones((n, 3)) if rgb is None else np.broadcast_to(rgb, (n, 3))
    alpha = np.ones((n, 1)) if alpha is None else np.broadcast_to(alpha, (n, 1))
    if np.ptp(rgb, axis=0).max(initial=0) == 0 and np.ptp(alpha).max(initial=0) == 0:
        args["constant_color"] = (rgb[0], float(alpha[0, 0]))
        return
    args["colors"] = np.concatenate([linear_to_srgb(np.clip(rgb, 0, 1)),
                                     np.clip(alpha, 0, 1)], axis=1).astype(np.float32)


def display_color(prim, time) -> tuple[np.ndarray | None, float]:
    """A gprim's constant displayColor (linear) and displayOpacity (first values)."""
    from pxr import UsdGeom

    api = UsdGeom.PrimvarsAPI(prim)
    colour, opacity = api.GetPrimvar("displayColor"), api.GetPrimvar("displayOpacity")
    rgb = None
    if colour and colour.HasAuthoredValue():
        v = _array(colour.ComputeFlattened(time), np.float64, 3)
        rgb = v[0] if v is not None and len(v) else None
    alpha = 1.0
    if opacity and opacity.HasAuthoredValue():
        v = _array(opacity.ComputeFlattened(time), np.float64)
        alpha = float(v[0]) if v is not None and len(v) else 1.0
    return rgb, alpha


def axis_turn(axis: str) -> np.ndarray:
    """The 4x4 rotation that turns facet's y-axis shapes to USD's ``axis``."""
    m = np.eye(4)
    if axis == "X":  # y -> x: a quarter turn about z (clockwise)
        m[:3, :3] = [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]
    elif axis == "Z":  # y -> z: a quarter turn about x
        m[:3, :3] = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]
    return m


def gprim(prim, time) -> tuple[str, tuple, np.ndarray] | None:
    """(facet shape kind, its parameters, 4x4 shape -> prim) of a UsdGeom gprim; kind
    "capsule" is a mesh facet tessellates (no exact capsule)."""
    from pxr import UsdGeom

    kind = prim.GetTypeName()
    if kind == "Cube":
        s = float(UsdGeom.Cube(prim).GetSizeAttr().Get(time))
        return "box", (s, s, s), np.eye(4)
    if kind == "Sphere":
        return "sphere", (float(UsdGeom.Sphere(prim).GetRadiusAttr().Get(time)),), np.eye(4)
    if kind in ("Cylinder", "Cone", "Capsule"):
        schema = getattr(UsdGeom, kind)(prim)
        r = float(schema.GetRadiusAttr().Get(time))
        h = float(schema.GetHeightAttr().Get(time))
        axis = schema.GetAxisAttr().Get(time) or "Z"
        return kind.lower(), (r, h), axis_turn(axis)
    if kind == "Plane":
        schema = UsdGeom.Plane(prim)
        w = float(schema.GetWidthAttr().Get(time))
        length = float(schema.GetLengthAttr().Get(time))
        axis = schema.GetAxisAttr().Get(time) or "Z"
        # facet's plane faces +y with (width, depth) along (x, z); USD's faces +axis with
        # width along the first other axis and length along the second.
        turn = {"Z": np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1.0]]),
                "Y": np.eye(4),
                "X": np.array([[0, 1, 0, 0], [1, 0, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1.0]])}
        # (axis Z: width along x, length along y; Y: x and z; X: z and y)
        size = (length, w) if axis == "X" else (w, length)
        return "plane", size, turn[axis]
    return None


def points_arguments(prim, time, notes: list | None = None) -> dict | None:
    """UsdGeom.Points: positions, per-point colours, widths (the first as the size; said
    into ``notes`` when they vary)."""
    from pxr import UsdGeom

    pts = UsdGeom.Points(prim)
    points = point_array(prim, time, notes, str(prim.GetPath()))
    if points is None or not len(points):
        return None
    args: dict = {"kind": "points", "positions": points.astype(np.float32)}
    rgb, _ = display_color(prim, time)
    colour = UsdGeom.PrimvarsAPI(prim).GetPrimvar("displayColor")
    if colour and colour.HasAuthoredValue():
        v = _array(colour.ComputeFlattened(time), np.float64, 3)
        if v is not None and len(v) == len(points):
            args["colors"] = np.concatenate([linear_to_srgb(np.clip(v, 0, 1)),
                                             np.ones((len(v), 1))], 1).astype(np.float32)
    widths = _array(pts.GetWidthsAttr().Get(time), np.float64)
    args["width"] = float(widths[0]) if widths is not None and len(widths) else None
    if notes is not None and widths is not None and len(widths) > 1 and np.ptp(widths) > 0:
        notes.append(f"{prim.GetPath()}: its points' widths vary; all are drawn at the "
                     f"first, {widths[0]:g}")
    args["rgb"] = rgb
    return args


def curve_arguments(prim, time, notes: list | None = None) -> dict | None:
    """UsdGeom.BasisCurves as polylines through their points (each curve's vertices in
    order; a cubic curve's control points, said into ``notes``, a linear one's points)."""
    from pxr import UsdGeom

    curves = UsdGeom.BasisCurves(prim)
    points = point_array(prim, time, notes, str(prim.GetPath()))
    counts = _array(curves.GetCurveVertexCountsAttr().Get(time), np.int64)
    if points is None or counts is None or not len(points) or counts.sum() != len(points):
        return None
    if notes is not None and curves.GetTypeAttr().Get(time) == "cubic":
        notes.append(f"{prim.GetPath()}: cubic curves are drawn as lines through their "
                     "control points")
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    seg_counts = np.maximum(counts - 1, 0)
    first = np.repeat(starts, seg_counts) + (np.arange(int(seg_counts.sum())) -
                                             np.repeat(np.cumsum(seg_counts) - seg_counts,
                                                       seg_counts))
    if curves.GetWrapAttr().Get(time) == "periodic":
        closing = np.stack([starts + counts - 1, starts], axis=1)[counts > 2]
        segments = np.concatenate([np.stack([first, first + 1], 1), closing])
    else:
        segments = np.stack([first, first + 1], axis=1)
    if not len(segments):
        return None
    rgb, _ = display_color(prim, time)
    return {"kind": "lines", "positions": points.astype(np.float32),
            "segments": segments.astype(np.uint32), "rgb": rgb}
