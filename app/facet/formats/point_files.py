"""Point clouds and lines from files (no GL), as facet.formats.loading's part arguments
(``kind`` "points" or "lines"; facet.scene.points makes them):

* PLY vertex-only files (what scanners write): positions, red/green/blue(/alpha) colours,
  nx/ny/nz normals; without colours, a scalar field (intensity, scalar_*) as grey levels
  spread over its range, as CloudCompare shows one.
* XYZ and PTS text: ``x y z`` per line, then optionally ``r g b`` (0-255) or ``nx ny nz``,
  PTS's ``x y z intensity [r g b]`` (its first line may be the point count).
* PCD (the Point Cloud Library's): ASCII and binary data with fields x y z, rgb / rgba
  (packed), normal_x/y/z, intensity. binary_compressed (LZF) is refused with one line.
* OBJ ``l`` polylines become segments.

Every failure is one MeshError naming the file and what to do.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..budgets import budget
from ..errors import MeshError
from ..guard import read_bytes

SCALAR_FIELDS = ("intensity", "scalar_intensity", "scalar", "reflectance", "confidence")
# PLY vertex properties that are not scalars of their own (position, normal, colour, uv).
PLY_FIXED = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha", "s", "t",
             "u", "v", "texture_u", "texture_v"}


def ply_scalars(tm, count: int) -> dict[str, np.ndarray]:
    """{name: (N,) float32} of a PLY's per-vertex scalar properties (quality, intensity,
    curvature, ...), for colormaps (facet.scene.colormap)."""
    raw = ((getattr(tm, "metadata", None) or {}).get("_ply_raw") or {}).get("vertex") or {}
    data = raw.get("data")
    fields = data if isinstance(data, dict) else (
        {n: data[n] for n in data.dtype.names} if getattr(data, "dtype", None) is not None
        and data.dtype.names else {})
    out = {}
    for name, values in fields.items():
        v = np.asarray(values)
        if name.lower() in PLY_FIXED or v.dtype.kind not in "fiu":
            continue
        v = v.reshape(len(v), -1)
        if v.shape == (count, 1):
            out[name] = v[:, 0].astype(np.float32)
    return out


def grey(values: np.ndarray) -> np.ndarray:
    """(N, 3) float32 grey levels of a scalar field spread over its 1st-99th percentile."""
    v = np.asarray(values, dtype=np.float64)
    lo, hi = np.percentile(v, [1, 99]) if len(v) else (0.0, 1.0)
    g = np.clip((v - lo) / (hi - lo), 0, 1) if hi > lo else np.full(len(v), 0.8)
    return np.repeat(g[:, None], 3, axis=1).astype(np.float32)


def ply_points(tm, p: Path) -> dict:
    """Points arguments of a trimesh PointCloud read from a PLY (module docstring)."""
    raw = ((getattr(tm, "metadata", None) or {}).get("_ply_raw") or {}).get("vertex") or {}
    data = raw.get("data")
    fields = data if isinstance(data, dict) else (
        {n: data[n] for n in data.dtype.names} if getattr(data, "dtype", None) is not None
        and data.dtype.names else {})
    positions = np.asarray(tm.vertices, dtype=np.float64)
    colors = getattr(tm, "colors", None)
    colors = None if colors is None or len(colors) != len(positions) else \
        np.asarray(colors, dtype=np.uint8)
    normals = None
    if all(k in fields for k in ("nx", "ny", "nz")):
        normals = np.stack([np.asarray(fields[k], np.float64).reshape(-1)
                            for k in ("nx", "ny", "nz")], axis=1)
    if colors is None:
        scalar = next((k for k in fields if k.lower() in SCALAR_FIELDS), None)
        if scalar is not None:
            colors = grey(np.asarray(fields[scalar]).reshape(-1))
    return {"kind": "points", "positions": positions, "colors": colors, "normals": normals,
            "name": p.name, "scalars": ply_scalars(tm, len(positions)) or None}


def read_text_points(p: Path) -> dict:
    """Points arguments of an XYZ or PTS file (module docstring)."""
    try:
        text = read_bytes(p, "point file", MeshError).decode("utf-8", errors="strict")
    except UnicodeDecodeError:
        raise MeshError(f"{p}: not a text point cloud (XYZ / PTS files are text: x y z per "
                        "line)") from None
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if lines and len(lines[0].split()) == 1:  # PTS: the point count first
        lines = lines[1:]
    if not lines:
        raise MeshError(f"{p}: holds no points; nothing to render")
    widths = {len(ln.replace(",", " ").split()) for ln in lines}
    if len(widths) != 1 or min(widths) < 3:
        raise MeshError(f"{p}: every line must hold the same number of values, at least x y "
                        f"z (found {sorted(widths)[:4]} values per line)")
    try:
        values = np.array(" ".join(lines).replace(",", " ").split(), dtype=np.float64)
    except ValueError as exc:
        raise MeshError(f"{p}: not numbers ({exc}); XYZ / PTS lines hold x y z and "
                        "optionally colours or normals") from None
    values = values.reshape(len(lines), -1)
    positions, rest = values[:, :3], values[:, 3:]
    colors = normals = None
    width = rest.shape[1]
    if width in (3, 4) and p.suffix.lower() == ".pts" and width == 4:
        colors = rest[:, 1:4]  # intensity r g b
    elif width >= 3 and _is_rgb(rest[:, :3]):
        colors = rest[:, :3]
    elif width >= 3 and np.all(np.abs(rest[:, :3]) <= 1.0 + 1e-6):
        normals = rest[:, :3]
        if width >= 6 and _is_rgb(rest[:, 3:6]):
            colors = rest[:, 3:6]
    elif width in (1, 4):
        colors = grey(rest[:, 0]) * 255.0
    if colors is not None:
        colors = np.clip(colors, 0, 255).astype(np.uint8)
    return {"kind": "points", "positions": positions, "colors": colors, "normals": normals,
            "name": p.name}


def _is_rgb(v: np.ndarray) -> bool:
    return bool(np.all((v >= 0) & (v <= 255) & (v == np.round(v))) and v.max() > 1)


PCD_TYPES = {("F", 4): "<f4", ("F", 8): "<f8", ("U", 1): "u1", ("U", 2): "<u2",
             ("U", 4): "<u4", ("I", 1): "i1", ("I", 2): "<i2", ("I", 4): "<i4"}


def read_pcd(p: Path) -> dict:
    """Points arguments of a PCD file (module docstring)."""
    raw = read_bytes(p, "point file", MeshError)
    header, offset = {}, 0
    for _ in range(64):
        end = raw.find(b"\n", offset)
        if end < 0:
            break
        line = raw[offset:end].decode("ascii", errors="replace").strip()
        offset = end + 1
        if not line or line.startswith("#"):
            continue
        key, _, value = line.partition(" ")
        header[key.upper()] = value.split()
        if key.upper() == "DATA":
            break
    need = ("FIELDS", "SIZE", "TYPE", "DATA")
    missing = [k for k in need if k not in header]
    if missing:
        raise MeshError(f"{p}: not a PCD file (its header lacks {', '.join(missing)})")
    fields, count, types, n = _pcd_layout(p, header)
    mode = header["DATA"][0].lower()
    columns: dict[str, np.ndarray] = {}
    if mode == "ascii":
        text = raw[offset:].decode("ascii", errors="replace").split()
        width = sum(count)
        if len(text) < n * width:
            raise MeshError(f"{p}: {n:,} points promised, the data holds {len(text) // width:,}"
                            "; is it truncated?")
        try:
            values = np.array(text[:n * width], dtype=np.float64).reshape(n, width)
        except ValueError:
            raise MeshError(f"{p}: its ascii data holds something that is not a number "
                            f"(a PCD's ascii rows are {width} numbers each)") from None
        k = 0
        for name, c, t in zip(fields, count, types, strict=True):
            col = values[:, k:k + c]
            if name in ("rgb", "rgba"):  # packed 0x00RRGGBB as a float's bits
                col = col.astype(np.float32).view(np.uint32) if t == "<f4" else \
                    col.astype(np.uint32)
            columns[name] = col[:, 0] if c == 1 else col
            k += c
    elif mode == "binary":
        dtype = np.dtype([(f"{name}", t, (c,)) if c > 1 else (f"{name}", t)
                          for name, c, t in zip(fields, count, types, strict=True)])
        if len(raw) - offset < n * dtype.itemsize:
            raise MeshError(f"{p}: {n:,} points promised, the data holds "
                            f"{(len(raw) - offset) // dtype.itemsize:,}; is it truncated?")
        rec = np.frombuffer(raw, dtype, count=n, offset=offset)
        for name in fields:
            col = rec[name]
            columns[name] = col.view(np.uint32) if name in ("rgb", "rgba") and \
                col.dtype == np.float32 else col
    else:
        raise MeshError(f"{p}: PCD data '{mode}' is LZF-compressed, which facet does not "
                        "read; convert it with pcl_convert_pcd_ascii_binary FILE OUT 1 "
                        "(binary) or 0 (ascii)")
    if not all(k in columns for k in "xyz"):
        raise MeshError(f"{p}: a PCD without x y z fields (fields: {' '.join(fields)})")
    return _pcd_points(p, columns)


def _whole(p: Path, key: str, text: str) -> int:
    """A PCD header's count: a whole number >= 0, else one line naming the key."""
    if not text.isdigit():
        raise MeshError(f"{p}: PCD header {key}: expected a whole number >= 0, got "
                        f"{text[:20]!r}")
    return int(text)


def _pcd_layout(p: Path, header: dict) -> tuple[list, list, list, int]:
    """(fields, counts, numpy types, points) of a PCD header, every count checked before
    numpy sees the data: one count and type per field, no field twice, x y z single
    numbers, a number of points within the elements budget."""
    fields = header["FIELDS"]
    if not fields or not header["DATA"]:
        raise MeshError(f"{p}: a PCD header with no FIELDS or no DATA kind (ascii or "
                        "binary)")
    count = [_whole(p, "COUNT", c) for c in header.get("COUNT", ["1"] * len(fields))]
    if len(set(fields)) != len(fields):
        raise MeshError(f"{p}: PCD header FIELDS names a field twice ({' '.join(fields)})")
    for key, values in (("COUNT", count), ("SIZE", header["SIZE"]),
                        ("TYPE", header["TYPE"])):
        if len(values) != len(fields):
            raise MeshError(f"{p}: PCD header {key} has {len(values)} entries for "
                            f"{len(fields)} FIELDS")
    if any(c < 1 for c in count) or any(c != 1 for f, c in zip(fields, count, strict=True)
                                        if f in ("x", "y", "z")):
        raise MeshError(f"{p}: PCD header COUNT {' '.join(map(str, count))}: each field "
                        "holds at least one number, and x, y and z one each")
    try:
        types = [PCD_TYPES[(t, int(s))] for t, s in zip(header["TYPE"], header["SIZE"],
                                                         strict=True)]
    except (KeyError, ValueError):
        raise MeshError(f"{p}: a PCD header with sizes and types facet does not know "
                        f"(SIZE {' '.join(header['SIZE'])}, TYPE {' '.join(header['TYPE'])})"
                        ) from None
    if "POINTS" in header:
        n = _whole(p, "POINTS", (header["POINTS"] or [""])[0])
    else:
        n = _whole(p, "WIDTH", (header.get("WIDTH") or [""])[0]) * \
            _whole(p, "HEIGHT", (header.get("HEIGHT") or [""])[0])
    if n * sum(count) > budget("elements"):
        raise MeshError(f"{p}: {n:,} points of {sum(count)} numbers each are more than "
                        f"facet's budget of {budget('elements'):,} numbers (--budget "
                        "elements=N)")
    if n == 0:
        raise MeshError(f"{p}: the PCD holds no points (POINTS 0)")
    return fields, count, types, n


def _pcd_points(p: Path, columns: dict) -> dict:
    """Points arguments of a PCD file's columns: positions, packed or scalar colours and
    normals, NaN holes dropped."""
    positions = np.stack([columns[k] for k in "xyz"], axis=1).astype(np.float64)
    colors = normals = None
    packed = columns.get("rgb", columns.get("rgba"))
    if packed is not None:
        packed = np.asarray(packed, dtype=np.uint32)
        colors = np.stack([(packed >> 16) & 255, (packed >> 8) & 255, packed & 255],
                          axis=1).astype(np.uint8)
    elif any(k in columns for k in SCALAR_FIELDS):
        colors = grey(columns[next(k for k in SCALAR_FIELDS if k in columns)])
    if all(f"normal_{a}" in columns for a in "xyz"):
        normals = np.stack([columns[f"normal_{a}"] for a in "xyz"], axis=1).astype(np.float64)
    keep = np.isfinite(positions).all(axis=1)  # organised clouds mark holes with NaN
    if not keep.any():
        raise MeshError(f"{p}: every point is NaN; nothing to render")
    return {"kind": "points", "positions": positions[keep],
            "colors": None if colors is None else colors[keep],
            "normals": None if normals is None else normals[keep], "name": p.name}


_OBJ_LINE = re.compile(rb"^[ \t]*l[ \t]+([^\n#]*)", re.M)
_OBJ_VERTEX = re.compile(rb"^[ \t]*v[ \t]+([^\n#]*)", re.M)


def obj_lines(p: Path) -> dict | None:
    """Lines arguments of an OBJ's ``l`` polylines (indices from 1, or back from -1; a
    ``v/vt`` pair keeps its vertex), or None when it has none."""
    data = read_bytes(p, "mesh file", MeshError)
    polylines = _OBJ_LINE.findall(data)
    if not polylines:
        return None
    import io

    try:
        positions = np.loadtxt(io.BytesIO(b"\n".join(_OBJ_VERTEX.findall(data))),
                               usecols=(0, 1, 2), ndmin=2, dtype=np.float64)
    except ValueError:
        raise MeshError(f"{p}: a vertex line holds something other than numbers") from None
    n = len(positions)
    segments = []
    for line in polylines:
        try:
            idx = np.array([int(tok.split(b"/")[0]) for tok in line.split()], dtype=np.int64)
        except (ValueError, OverflowError):  # not a number, or beyond any vertex count
            raise MeshError(f"{p}: an 'l' line holds something other than vertex "
                            "indices") from None
        idx = np.where(idx < 0, n + idx, idx - 1)
        if (idx < 0).any() or (idx >= n).any() or len(idx) < 2:
            raise MeshError(f"{p}: an 'l' line refers to vertices that do not exist (the "
                            f"file has {n}; OBJ counts from 1)")
        segments.append(np.stack([idx[:-1], idx[1:]], axis=1))
    return {"kind": "lines", "positions": positions, "segments": np.concatenate(segments),
            "name": p.name}
