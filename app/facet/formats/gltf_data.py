"""The binary side of a glTF file as numpy: buffers (GLB chunk, .bin files, data URIs),
accessors (strided, normalized, sparse), images and Draco-compressed primitives.

Every failure is a ``MeshError`` naming the file and what it needs, e.g. a missing .bin:
``Box.gltf: needs the buffer file 'Box.bin', which is not in /models``.
"""

from __future__ import annotations

import base64
import binascii
import io
from pathlib import Path
from urllib.parse import unquote

import numpy as np

from ..budgets import budget
from ..errors import MeshError

COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16,
              5125: np.uint32, 5126: np.float32}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


def _data_uri(uri: str, what: str = "data") -> bytes | None:
    """The bytes of a ``data:`` URI (None for another URI); MeshError-ready ValueError
    naming ``what`` when its base64 is broken."""
    if not uri.startswith("data:"):
        return None
    head, _, payload = uri.partition(",")
    if not head.endswith(";base64"):
        return unquote(payload).encode()
    try:
        return base64.b64decode(payload, validate=True)
    except (binascii.Error, ValueError) as exc:
        raise ValueError(f"{what}: its data: URI is not valid base64 ({exc})") from None


KTX2_MAGIC = b"\xabKTX 20\xbb\r\n\x1a\n"
KTX2_EXTRA = "pip install 'facet-render[ktx2]' (opengl_basisu, a Basis Universal transcoder)"


def ktx2_available() -> bool:
    """Whether KTX2 / Basis Universal textures can be decoded here (the ktx2 extra)."""
    try:
        import opengl_basisu  # noqa: F401
    except ImportError:
        return False
    return True


def ktx2_pixels(raw: bytes, name: str) -> np.ndarray:
    """(H, W, 4) uint8 of a KTX2 file's first image (its top mip level), transcoded from
    Basis Universal (ETC1S or UASTC, KHR_texture_basisu) by opengl_basisu; rows from the
    top, as a PNG's (glTF's orientation for KTX2). ValueError naming the file when it
    cannot be read, the extra when the transcoder is missing."""
    from ..budgets import check_pixels

    try:
        import opengl_basisu
    except ImportError:
        raise ValueError(f"{name}: KTX2 / Basis Universal needs {KTX2_EXTRA}") from None
    try:
        texture = opengl_basisu.open(raw)
        image = texture.transcode(opengl_basisu.Target.RGBA8)
    except opengl_basisu.BasisuError as exc:
        raise ValueError(f"{name}: not a KTX2 file opengl_basisu can transcode ({exc})") \
            from None
    check_pixels(image.width, image.height, name)
    pixels = np.frombuffer(memoryview(image.data).cast("B"), np.uint8)
    return pixels[:image.height * image.width * 4].reshape(image.height, image.width, 4).copy()


class GltfData:
    """Decodes the accessors, images and Draco primitives of one parsed glTF document
    (``gltf``: a pygltflib.GLTF2 read from ``path``)."""

    def __init__(self, gltf, path: Path):
        self.gltf, self.path = gltf, path
        self._buffers: dict = {}  # buffer index (or ("meshopt", view)) -> bytes

    def fail(self, message: str):
        raise MeshError(f"{self.path}: {message}")

    # -- buffers -----------------------------------------------------------------------
    def buffer(self, index: int) -> bytes:
        if index not in self._buffers:
            buf = self.gltf.buffers[index]
            if buf.uri is None:  # the GLB's binary chunk
                data = self.gltf.binary_blob()
                if data is None:
                    self.fail(f"buffer {index} has no uri and the file has no binary chunk")
            else:
                try:
                    data = _data_uri(buf.uri, f"buffer {index}")
                except ValueError as exc:
                    self.fail(str(exc))
                if data is None:
                    data = self._file(buf.uri, "buffer file")
            if len(data) < (buf.byteLength or 0):
                self.fail(f"buffer {index} holds {len(data)} bytes, the file says "
                          f"{buf.byteLength}; is it truncated?")
            self._buffers[index] = bytes(data)
        return self._buffers[index]

    def _file(self, uri: str, what: str) -> bytes:
        from ..guard import check_confined, read_bytes

        p = self.path.parent / unquote(uri)
        check_confined(p, what, MeshError)  # first: outside reads the same, there or not
        if not p.exists():
            self.fail(f"needs the {what} '{unquote(uri)}', which is not in {p.parent}")
        return read_bytes(p, what, MeshError)  # not a FIFO or a device: no hang, no flood

    def view(self, index: int) -> tuple[bytes, int, int, int | None]:
        """(buffer bytes, offset, length, stride) of bufferView ``index`` (decoded first
        when it is EXT_meshopt_compression's: its own buffer is then a fallback, unread)."""
        bv = self.gltf.bufferViews[index]
        meshopt = (bv.extensions or {}).get("EXT_meshopt_compression")
        if meshopt is not None:
            data = self._meshopt(index, meshopt)
            return data, 0, len(data), bv.byteStride
        data = self.buffer(bv.buffer)
        offset, length = bv.byteOffset or 0, bv.byteLength
        if offset + length > len(data):
            self.fail(f"bufferView {index} reaches past the end of its buffer; is the file "
                      "truncated?")
        return data, offset, length, bv.byteStride

    MESHOPT_MODES = ("ATTRIBUTES", "TRIANGLES", "INDICES")
    MESHOPT_FILTERS = ("NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL")

    def _meshopt(self, index: int, ext) -> bytes:
        """bufferView ``index``'s bytes, decoded from its EXT_meshopt_compression stream
        (meshoptimizer's decoder, the meshopt package), once."""
        key = ("meshopt", index)
        if key in self._buffers:
            return self._buffers[key]
        at = f"bufferViews[{index}].extensions.EXT_meshopt_compression"
        try:
            import meshopt
        except ImportError:
            self.fail("is compressed with EXT_meshopt_compression, which needs "
                      "meshoptimizer's decoder: pip install meshopt")
        if not isinstance(ext, dict):
            self.fail(f"{at}: expected an object")

        def whole(name, low=0, optional=False, default=0):
            v = ext.get(name, None if not optional else default)
            if isinstance(v, bool) or not isinstance(v, int) or v < low:
                self.fail(f"{at}.{name}: expected an integer >= {low}, got {v!r}")
            return v

        buffer, offset = whole("buffer"), whole("byteOffset", optional=True)
        length, stride, count = whole("byteLength", 1), whole("byteStride", 1), whole("count", 1)
        mode, filt = ext.get("mode"), ext.get("filter", "NONE")
        if mode not in self.MESHOPT_MODES:
            self.fail(f"{at}.mode: expected one of {', '.join(self.MESHOPT_MODES)}, "
                      f"got {mode!r}")
        if filt not in self.MESHOPT_FILTERS:
            self.fail(f"{at}.filter: expected one of {', '.join(self.MESHOPT_FILTERS)}, "
                      f"got {filt!r}")
        if count * stride > budget("file_bytes"):
            self.fail(f"{at}: {count:,} elements of {stride} bytes decode to more than the "
                      f"{budget('file_bytes'):,} bytes a buffer may hold "
                      "(FACET_BUDGET_FILE_BYTES)")
        if buffer >= len(self.gltf.buffers or []):
            self.fail(f"{at}.buffer: no buffer {buffer}")
        data = self.buffer(buffer)
        if offset + length > len(data):
            self.fail(f"{at} reaches past the end of buffer {buffer}; is the file truncated?")
        try:
            rows = meshopt.decode_gltf_buffer(data[offset:offset + length], count, stride,
                                              mode, None if filt == "NONE" else filt)
        except Exception as exc:  # the decoder's own word for a broken stream
            self.fail(f"{at}: the compressed data does not decode ({exc})")
        out = np.ascontiguousarray(rows).view(np.uint8).tobytes()
        self._buffers[key] = out
        return out

    # -- accessors ---------------------------------------------------------------------
    def accessor(self, index: int, normalize: bool = True) -> np.ndarray:
        """(count, width) (or (count,) for scalars) of accessor ``index``; normalized
        integers become floats in [0, 1] / [-1, 1] when ``normalize``; sparse values are
        applied."""
        acc = self.gltf.accessors[index]
        dtype = np.dtype(COMPONENTS.get(acc.componentType) or self.fail(
            f"accessor {index}: unknown componentType {acc.componentType}"))
        width = WIDTH.get(acc.type) or self.fail(f"accessor {index}: unknown type {acc.type}")
        if acc.bufferView is None:
            out = np.zeros((acc.count, width), dtype)
        else:
            out = self._strided(acc.bufferView, acc.byteOffset or 0, acc.count, width, dtype)
        if acc.sparse is not None and acc.sparse.count:
            out = out.copy()
            sp = acc.sparse
            idx_dtype = np.dtype(COMPONENTS[sp.indices.componentType])
            rows = self._strided(sp.indices.bufferView, sp.indices.byteOffset or 0, sp.count,
                                 1, idx_dtype)[:, 0]
            values = self._strided(sp.values.bufferView, sp.values.byteOffset or 0, sp.count,
                                   width, dtype)
            if rows.size and rows.max() >= acc.count:
                self.fail(f"accessor {index}: sparse indices beyond its {acc.count} elements")
            out[rows.astype(np.int64)] = values
        if normalize and acc.normalized and dtype.kind in "iu":
            info = np.iinfo(dtype)
            out = np.maximum(out.astype(np.float32) / info.max, -1.0)
        return out[:, 0] if acc.type == "SCALAR" else out

    def _strided(self, view: int, offset: int, count: int, width: int, dtype) -> np.ndarray:
        """(count, width) elements of bufferView ``view`` from ``offset``; every bound is
        checked here (offset, stride and length are facet.formats.gltf_check's non-negative
        integers) before the strided view is made."""
        data, start, length, stride = self.view(view)
        item = dtype.itemsize * width
        stride = stride or item
        if stride < item:
            self.fail(f"bufferView {view}: byteStride {stride} is less than one element's "
                      f"{item} bytes")
        need = offset + stride * (count - 1) + item if count else 0
        if offset < 0 or need > length:
            self.fail(f"bufferView {view} is too short for {count} elements; is the file "
                      "truncated?")
        raw = np.frombuffer(data, np.uint8, count=length, offset=start)
        rows = np.lib.stride_tricks.as_strided(raw[offset:], (count, item), (stride, 1))
        return np.ascontiguousarray(rows).view(dtype).reshape(count, width)

    # -- images ------------------------------------------------------------------------
    def image(self, index: int):
        """A facet Texture of image ``index``, or None (with one warning naming the file)
        when its file is missing or unreadable: the material is drawn without it."""
        import warnings

        from ..errors import FacetWarning

        texture, why = self.read_image(index)
        if why is not None:
            warnings.warn(why, FacetWarning, stacklevel=2)
        return texture

    def read_image(self, index: int):
        """(Texture, None), or (None, the warning line) when image ``index``'s file is
        missing, outside the confinement folder (said alike: a confined file cannot probe
        which files exist) or unreadable. Warns nothing itself: it runs in the decoding
        threads (facet.formats.gltf_textures), where catching warnings is not safe."""
        from PIL import UnidentifiedImageError

        from ..guard import check_confined, open_image, read_bytes
        from ..scene.texture import Texture

        img = self.gltf.images[index]
        embedded = img.bufferView is not None or (img.uri or "").startswith("data:")
        name = img.name or (f"image {index} (embedded)" if embedded else img.uri) or \
            f"image {index}"
        try:
            if img.bufferView is not None:
                data, start, length, _ = self.view(img.bufferView)
                raw = data[start:start + length]
            elif (img.uri or "").startswith("data:"):
                raw = _data_uri(img.uri, name)
            else:
                uri = unquote(img.uri or "")
                p = self.path.parent / uri
                check_confined(p, f"texture {uri}", MeshError)  # before asking if it exists
                if not p.exists():
                    return None, (f"{self.path.name}: texture file '{uri}' not found in "
                                  f"{p.parent}; drawn without it")
                raw = read_bytes(p, f"texture {name}", MeshError)
            if raw[:12] == KTX2_MAGIC:
                return Texture(ktx2_pixels(raw, f"texture {name}"), str(name)), None
            with open_image(io.BytesIO(raw), f"texture {name}") as pil:
                return Texture.from_pil(pil, str(name)), None
        except (UnidentifiedImageError, OSError, ValueError, MeshError) as exc:
            return None, f"{self.path.name}: {exc}; drawn without it"

    # -- Draco -------------------------------------------------------------------------
    def draco(self, ext: dict, where: str, points: bool) -> dict[str, np.ndarray]:
        """The attributes (by glTF name) and "indices" of a KHR_draco_mesh_compression
        primitive (``where``), decoded with DracoPy; ``points``: the primitive draws
        points (a Draco point cloud has no faces: its indices are its points in order)."""
        try:
            import DracoPy
        except ImportError:
            self.fail("is Draco-compressed (KHR_draco_mesh_compression), which needs the "
                      "DracoPy package, a dependency of facet missing from this Python: "
                      "pip install DracoPy")
        data, start, length, _ = self.view(ext["bufferView"])
        try:
            mesh = DracoPy.decode(data[start:start + length])
        except Exception as exc:  # DracoPy raises its own types for corrupt data
            self.fail(f"cannot decode its Draco data ({exc})")
        attributes = ext.get("attributes") or {}
        if "POSITION" not in attributes:
            self.fail(f"{where}: its Draco extension maps no POSITION attribute "
                      "(KHR_draco_mesh_compression.attributes)")
        faces = getattr(mesh, "faces", None)
        if faces is None and not points:
            self.fail(f"{where}: its Draco data is a point cloud (no faces), but the "
                      "primitive draws triangles or lines (set its mode to 0, POINTS)")
        out = {"indices": np.arange(len(np.asarray(mesh.points).reshape(-1, 3)),
                                    dtype=np.uint32) if faces is None or points else
               np.asarray(faces, dtype=np.uint32).reshape(-1)}
        for name, uid in attributes.items():
            attr = mesh.get_attribute_by_unique_id(uid)
            if attr is None:
                self.fail(f"its Draco data has no attribute {uid} for {name}")
            out[name] = np.asarray(attr["data"])
        return out
