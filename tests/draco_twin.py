"""A Draco-compressed twin of a glTF file, made with DracoPy's encoder (for differential
tests: a file and its twin must draw alike, skins and morph targets included).

Each triangle primitive's POSITION, NORMAL, TEXCOORD_0, JOINTS_0 and WEIGHTS_0 and its
indices go into one Draco stream (vertex order kept: the extension asks encoders to keep it
when a primitive has morph targets, whose accessors stay outside the stream); their
accessors lose their bufferView, as KHR_draco_mesh_compression has them. Positions are
quantized to 16 bits, the rest kept as floats or integers."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np

COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32,
          5126: np.float32}


def _glb(path: Path) -> tuple[dict, bytes]:
    data = path.read_bytes()
    length = struct.unpack("<I", data[12:16])[0]
    document = json.loads(data[20:20 + length])
    rest = data[20 + length:]
    blob = rest[8:8 + struct.unpack("<I", rest[:4])[0]] if rest else b""
    return document, blob


def _accessor(document: dict, blob: bytes, index: int) -> np.ndarray:
    acc = document["accessors"][index]
    view = document["bufferViews"][acc["bufferView"]]
    dtype = np.dtype(DTYPES[acc["componentType"]])
    n = COMPONENTS[acc["type"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride", n * dtype.itemsize)
    rows = np.frombuffer(blob, np.uint8, count=stride * (acc["count"] - 1) + n * dtype.itemsize,
                         offset=start)
    out = np.lib.stride_tricks.as_strided(rows, (acc["count"], n * dtype.itemsize),
                                          (stride, 1)).copy().view(dtype)
    return out.reshape(acc["count"], n)


def _floats(a):
    return None if a is None else np.ascontiguousarray(a, dtype=np.float64)


def draco_twin(source: Path, target: Path) -> Path:
    """Write ``source`` (a .glb) Draco-compressed as ``target`` (a .gltf with its .bin)."""
    import DracoPy

    document, blob = _glb(source)
    out = bytearray(blob)
    views = document["bufferViews"]
    for mesh in document.get("meshes", []):
        for prim in mesh["primitives"]:
            if prim.get("mode", 4) != 4 or "indices" not in prim:
                continue
            attrs = prim["attributes"]
            get = {name: _accessor(document, blob, attrs[name]) for name in
                   ("POSITION", "NORMAL", "TEXCOORD_0", "JOINTS_0", "WEIGHTS_0")
                   if name in attrs}
            faces = _accessor(document, blob, prim["indices"]).reshape(-1, 3).astype(np.uint32)
            generic = {}
            if "JOINTS_0" in get:
                generic[10] = get["JOINTS_0"].astype(np.uint16)
            if "WEIGHTS_0" in get:
                generic[11] = get["WEIGHTS_0"].astype(np.float32)
            stream = DracoPy.encode(get["POSITION"].astype(np.float32), faces,
                                    quantization_bits=16, preserve_order=True,
                                    normals=_floats(get.get("NORMAL")),
                                    tex_coord=_floats(get.get("TEXCOORD_0")),
                                    generic_attributes=generic or None)
            decoded = DracoPy.decode(stream)
            kinds = {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 3}
            ids = {}
            for attribute in decoded.attributes:
                uid = attribute["unique_id"]
                if uid == 10:
                    ids["JOINTS_0"] = uid
                elif uid == 11:
                    ids["WEIGHTS_0"] = uid
                else:
                    name = next((n for n, k in kinds.items()
                                 if attribute.get("attribute_type") == k and n in get), None)
                    ids[name or "POSITION"] = uid
            while len(out) % 4:
                out.append(0)
            views.append({"buffer": 0, "byteOffset": len(out), "byteLength": len(stream)})
            out += stream
            prim.setdefault("extensions", {})["KHR_draco_mesh_compression"] = {
                "bufferView": len(views) - 1, "attributes": ids}
            for index in [*(attrs[n] for n in ids), prim["indices"]]:
                accessor = document["accessors"][index]
                accessor.pop("bufferView", None)
                accessor.pop("byteOffset", None)
    document["buffers"] = [{"byteLength": len(out), "uri": target.with_suffix(".bin").name}]
    for key in ("extensionsUsed", "extensionsRequired"):
        document[key] = sorted({*document.get(key, []), "KHR_draco_mesh_compression"})
    target.with_suffix(".bin").write_bytes(bytes(out))
    target.write_text(json.dumps(document))
    return target
