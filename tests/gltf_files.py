"""Small glTF files built in code for the loader tests: a document dict plus one binary
buffer, written as .gltf + .bin (or with the buffer as a data URI) or as .glb."""

from __future__ import annotations

import base64
import json
import struct
from pathlib import Path

import numpy as np

FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125
TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4", 16: "MAT4"}


class GltfBuilder:
    """Accumulates accessors into one buffer; ``doc`` is the glTF JSON being built."""

    def __init__(self):
        self.doc = {"asset": {"version": "2.0"}, "buffers": [], "bufferViews": [],
                    "accessors": [], "meshes": [], "nodes": [], "scenes": [{"nodes": []}],
                    "scene": 0}
        self.data = bytearray()

    def view(self, raw: bytes, stride: int | None = None) -> int:
        while len(self.data) % 4:
            self.data.append(0)
        bv = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)}
        if stride:
            bv["byteStride"] = stride
        self.data += raw
        self.doc["bufferViews"].append(bv)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, values, component=FLOAT, normalized=False, minmax=False) -> int:
        a = np.asarray(values)
        width = 1 if a.ndim == 1 else a.shape[1]
        dtype = {FLOAT: "<f4", UBYTE: "u1", USHORT: "<u2", UINT: "<u4"}[component]
        acc = {"bufferView": self.view(a.astype(dtype).tobytes()), "componentType": component,
               "count": len(a), "type": TYPES[width]}
        if normalized:
            acc["normalized"] = True
        if minmax:
            acc["min"] = a.reshape(len(a), -1).min(0).tolist()
            acc["max"] = a.reshape(len(a), -1).max(0).tolist()
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def mesh(self, primitives: list[dict]) -> int:
        self.doc["meshes"].append({"primitives": primitives})
        return len(self.doc["meshes"]) - 1

    def node(self, root: bool = True, **node) -> int:
        self.doc["nodes"].append(node)
        index = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(index)
        return index

    def material(self, **material) -> int:
        self.doc.setdefault("materials", []).append(material)
        return len(self.doc["materials"]) - 1

    def texture(self, png: bytes, sampler: dict | None = None) -> int:
        image = {"bufferView": self.view(png), "mimeType": "image/png"}
        self.doc.setdefault("images", []).append(image)
        tex = {"source": len(self.doc["images"]) - 1}
        if sampler is not None:
            self.doc.setdefault("samplers", []).append(sampler)
            tex["sampler"] = len(self.doc["samplers"]) - 1
        self.doc.setdefault("textures", []).append(tex)
        return len(self.doc["textures"]) - 1

    def write_gltf(self, path: Path, bin_name: str | None = None) -> Path:
        """.gltf with the buffer in ``bin_name`` (written beside it) or as a data URI."""
        buf = {"byteLength": len(self.data)}
        if bin_name is None:
            buf["uri"] = "data:application/octet-stream;base64," + \
                base64.b64encode(bytes(self.data)).decode()
        else:
            buf["uri"] = bin_name
            (path.parent / bin_name).write_bytes(bytes(self.data))
        doc = dict(self.doc, buffers=[buf])
        path.write_text(json.dumps(doc))
        return path

    def write_glb(self, path: Path) -> Path:
        while len(self.data) % 4:
            self.data.append(0)
        doc = dict(self.doc, buffers=[{"byteLength": len(self.data)}])
        js = json.dumps(doc).encode()
        js += b" " * (-len(js) % 4)
        body = struct.pack("<II", len(js), 0x4E4F534A) + js + \
            struct.pack("<II", len(self.data), 0x004E4942) + bytes(self.data)
        path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
        return path


def png(pixels: np.ndarray) -> bytes:
    import io

    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(np.asarray(pixels, np.uint8)).save(out, "PNG")
    return out.getvalue()


def quad(b: GltfBuilder, material: int | None = None, **extra_attributes) -> int:
    """A unit quad in the xy plane facing +z, uv (0, 0) at its top-left (glTF's v down)."""
    pos = b.accessor(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float),
                     minmax=True)
    uv = b.accessor(np.array([[0, 1], [1, 1], [1, 0], [0, 0]], float))
    idx = b.accessor(np.array([0, 1, 2, 0, 2, 3]), USHORT)
    prim = {"attributes": {"POSITION": pos, "TEXCOORD_0": uv, **extra_attributes},
            "indices": idx}
    if material is not None:
        prim["material"] = material
    return b.mesh([prim])
