"""Gaussian splat files: the reference implementation's PLY (3DGS, nerfstudio's and gsplat's
exports) and the web viewers' ``.splat``, read with numpy (a structured view of the binary
body: no loop over splats).

The PLY: one ``vertex`` element with ``x y z`` (and ``nx ny nz``, unused), ``f_dc_0..2``,
``f_rest_0..`` (0, 9, 24 or 45 of them: SH degree 0-3, channel-major: all of red's
coefficients, then green's, then blue's), ``opacity`` (a logit), ``scale_0..2`` (log
standard deviations) and ``rot_0..3`` (a quaternion w x y z, any length). A file is
recognised by these properties wherever a model is accepted (``is_splat_ply``).
``.splat``: 32 bytes a splat: position (3 float32), scales (3 float32, linear), colour RGBA
(4 uint8: the DC colour and the opacity) and rotation (4 uint8, (q + 1) * 128, w x y z).
Every problem (a header that is not a PLY's, a body shorter than its count, a missing
property, NaN, a zero quaternion, an absurd scale) is one MeshError naming the file.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import InputError, MeshError
from ..scene.splats import Splats

_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2",
              "int16": "i2", "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4",
              "uint": "u4", "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8",
              "float64": "f8"}
NEEDED = ("x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1",
          "scale_2", "rot_0", "rot_1", "rot_2", "rot_3")
SNIFFED = (b"f_dc_0", b"opacity", b"scale_0", b"rot_0")  # the properties that say "splats"
SPLAT_BYTES = 32
MAX_HEADER = 1 << 16


def _header(path, head: bytes) -> tuple[str, list, int]:
    """(format, elements [(name, count, [(property, type)])], body offset) of a PLY whose
    first bytes are ``head``; MeshError naming ``path`` when the header is not a PLY's."""
    end = head.find(b"end_header")
    if not head.startswith(b"ply") or end < 0 or head.find(b"\n", end) < 0:
        raise MeshError(f"{path}: not a PLY file (no 'ply' ... 'end_header' header)")
    stop = head.index(b"\n", end) + 1
    fmt, elements = "", []
    for line in head[:stop].decode("ascii", "replace").splitlines()[1:]:
        words = line.split()
        if not words or words[0] in ("comment", "obj_info", "end_header"):
            continue
        if words[0] == "format" and len(words) >= 2:
            fmt = words[1]
        elif words[0] == "element" and len(words) == 3:
            if not words[2].isdigit():
                raise MeshError(f"{path}: element {words[1]!r} has the count {words[2]!r}; "
                                "a PLY's counts are whole numbers >= 0")
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements:
            if words[1] == "list":
                elements[-1][2].append((words[-1], "list"))
            elif words[1] in _PLY_TYPES and len(words) >= 3:
                elements[-1][2].append((words[2], _PLY_TYPES[words[1]]))
            else:
                raise MeshError(f"{path}: unknown PLY property type {words[1]!r}")
            names = [name for name, _ in elements[-1][2]]
            if names[-1] in names[:-1]:
                raise MeshError(f"{path}: element {elements[-1][0]!r} names the property "
                                f"{names[-1]!r} twice")
    return fmt, elements, stop


def is_splat_file(path) -> bool:
    """Whether ``path`` holds Gaussian splats: a ``.splat`` file, or a PLY of them (its
    header read through facet.guard: a FIFO, a device or a file outside the confinement
    folder is refused, MeshError, before a byte is read)."""
    return Path(path).suffix.lower() == ".splat" or is_splat_ply(path)


def is_splat_ply(path) -> bool:
    """Whether ``path`` is a PLY whose vertices are Gaussian splats (module docstring)."""
    from ..guard import read_head

    p = Path(path)
    if p.suffix.lower() != ".ply":
        return False
    head = read_head(p, MAX_HEADER, "model file", MeshError)
    try:
        _, elements, _ = _header(p, head)
    except MeshError:
        if all(re.search(rb"^property\s+\S+\s+" + name + rb"\s*$", head, re.M)
               for name in SNIFFED):
            raise  # a splat file's header, broken: its own line
        return False  # not a splat PLY's header: the mesh reader says what is wrong
    vertex = next((e for e in elements if e[0] == "vertex"), None)
    names = {name for name, _ in vertex[2]} if vertex else set()
    return {name.decode() for name in SNIFFED} <= names


def read_splats(path: Path) -> Splats:
    """The splats of a 3DGS PLY or a ``.splat`` file; MeshError naming the file."""
    from ..guard import read_bytes

    p = Path(path)
    data = read_bytes(p, "splat file", MeshError, missing="file")
    try:
        if p.suffix.lower() == ".splat":
            return _read_dot_splat(p, data)
        return _read_ply(p, data)
    except InputError as exc:
        if isinstance(exc, MeshError):
            raise
        raise MeshError(f"{p}: {exc}") from None


def _read_ply(p: Path, raw: bytes) -> Splats:
    fmt, elements, offset = _header(p, raw[:MAX_HEADER])
    if not elements or elements[0][0] != "vertex":
        raise MeshError(f"{p}: the splats' 'vertex' element must come first")
    _, count, props = elements[0]
    if any(kind == "list" for _, kind in props):
        raise MeshError(f"{p}: a splat PLY's vertices have no list properties")
    names = [name for name, _ in props]
    missing = [n for n in NEEDED if n not in names]
    if missing:
        raise MeshError(f"{p}: not a Gaussian splat PLY: its vertices lack "
                        f"{', '.join(missing)} (the 3DGS layout: x y z, f_dc_0..2, "
                        "f_rest_*, opacity, scale_0..2, rot_0..3)")
    if fmt == "ascii":
        body = raw[offset:].decode("ascii", "replace")
        try:
            table = np.loadtxt(body.splitlines()[:count], dtype=np.float64, ndmin=2)
        except ValueError as exc:
            raise MeshError(f"{p}: its ASCII body does not parse ({exc})") from None
        if table.shape != (count, len(props)):
            raise MeshError(f"{p}: the header says {count} splats of {len(props)} "
                            f"properties; the body has {table.shape[0]} rows")
        column = {name: table[:, k] for k, name in enumerate(names)}
    elif fmt in ("binary_little_endian", "binary_big_endian"):
        order = "<" if fmt == "binary_little_endian" else ">"
        dtype = np.dtype([(name, order + kind) for name, kind in props])
        size = len(raw) - offset
        if size < count * dtype.itemsize:
            raise MeshError(f"{p}: the header says {count} splats ({count * dtype.itemsize} "
                            f"bytes) but the body has {size} bytes: a truncated file")
        data = np.frombuffer(raw, dtype=dtype, count=count, offset=offset)
        column = {name: data[name].astype(np.float64) for name in names}
    else:
        raise MeshError(f"{p}: unknown PLY format {fmt!r}")
    rest = sorted((n for n in names if re.fullmatch(r"f_rest_\d+", n)),
                  key=lambda n: int(n[7:]))
    if len(rest) not in (0, 9, 24, 45) or rest != [f"f_rest_{k}" for k in range(len(rest))]:
        raise MeshError(f"{p}: {len(rest)} f_rest properties: expected 0, 9, 24 or 45 "
                        "(f_rest_0 ...: SH degree 0-3)")
    k = len(rest) // 3  # coefficients beyond the DC one, per channel
    sh = np.empty((count, k + 1, 3))
    for c in range(3):
        sh[:, 0, c] = column[f"f_dc_{c}"]
        for j in range(k):  # (channel-major: red's k, then green's, then blue's)
            sh[:, j + 1, c] = column[f"f_rest_{c * k + j}"]
    means = np.stack([column["x"], column["y"], column["z"]], axis=1)
    log_scales = np.stack([column[f"scale_{i}"] for i in range(3)], axis=1)
    with np.errstate(over="ignore", invalid="ignore"):
        scales = np.exp(log_scales)
        opacity = 1.0 / (1.0 + np.exp(-column["opacity"]))
    rotations = np.stack([column[f"rot_{i}"] for i in range(4)], axis=1)
    return Splats(means, scales, rotations, opacity, sh, name=p.stem)


def _read_dot_splat(p: Path, raw: bytes) -> Splats:
    size = len(raw)
    if size == 0 or size % SPLAT_BYTES:
        raise MeshError(f"{p}: a .splat file is 32 bytes a splat; this one has {size} bytes")
    data = np.frombuffer(raw, dtype=np.dtype([("position", "<f4", 3), ("scale", "<f4", 3),
                                             ("rgba", "u1", 4), ("rot", "u1", 4)]))
    rgba = data["rgba"].astype(np.float64) / 255.0
    rotations = (data["rot"].astype(np.float64) - 128.0) / 128.0
    return Splats.from_colors(data["position"], data["scale"], rotations, rgba[:, 3],
                              rgba[:, :3], name=p.stem)


def write_ply(splats: Splats, path: Path) -> Path:
    """``splats`` as a binary 3DGS PLY (module docstring) at ``path``."""
    n, k = splats.count, splats.sh.shape[1] - 1
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2",
             *[f"f_rest_{i}" for i in range(3 * k)], "opacity", "scale_0", "scale_1",
             "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    data = np.zeros(n, dtype=np.dtype([(name, "<f4") for name in names]))
    for i, axis in enumerate("xyz"):
        data[axis] = splats.means[:, i]
        data[f"scale_{i}"] = np.log(splats.scales[:, i])
    for c in range(3):
        data[f"f_dc_{c}"] = splats.sh[:, 0, c]
        for j in range(k):
            data[f"f_rest_{c * k + j}"] = splats.sh[:, j + 1, c]
    a = np.clip(splats.opacities.astype(np.float64), 1e-7, 1 - 1e-7)
    data["opacity"] = np.log(a / (1.0 - a))
    for i in range(4):
        data[f"rot_{i}"] = splats.rotations[:, i]
    header = "ply\nformat binary_little_endian 1.0\n" + f"element vertex {n}\n" + \
        "".join(f"property float {name}\n" for name in names) + "end_header\n"
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        data.tofile(f)
    return path

