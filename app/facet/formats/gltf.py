"""glTF 2.0 (.gltf + .bin, .glb) -> facet parts and cameras, read with pygltflib and numpy.

Each primitive of each mesh a node of the default scene uses becomes one part: its own
``Mesh`` (positions, the file's normals, both texture coordinate sets, tangents, vertex
colours) with its own ``PbrMaterial``, placed by the node's world matrix (and each of its
EXT_mesh_gpu_instancing instances); a mesh used by several nodes is decoded once. Triangle
strips and fans become triangles; points and lines become ``Points`` and ``Lines``
(facet.scene.points). Animations, skins and morph targets become a Rig that poses the parts
(facet.formats.gltf_rig). Cameras become named cameras. Supported extensions: SUPPORTED
(KHR_draco_mesh_compression through DracoPy, KHR_mesh_quantization, KHR_texture_transform,
the KHR_materials_* of facet.formats.gltf_materials, _variants, KHR_lights_punctual through
facet.formats.gltf_lights, EXT_mesh_gpu_instancing, EXT_texture_webp); KHR_texture_basisu's
PNG / JPEG fallbacks are drawn; a file that *requires* another one is refused by name, one
that only uses another one gets a warning that it is ignored.

glTF is y-up, right-handed, metres, cameras looking down -z: facet's own conventions.
Vertex colours (linear in glTF) are stored sRGB-encoded, as every facet mesh's colours are.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..budgets import budget
from ..errors import FacetWarning, MeshError
from ..scene.pbr import PbrMaterial
from ..srgb import linear_to_srgb
from .gltf_cameras import gltf_camera
from .gltf_check import check_gltf
from .gltf_data import KTX2_EXTRA, GltfData, ktx2_available
from .gltf_lights import document_lights, facet_light, node_light
from .gltf_rig import read_rig, vertex_deformation
from .gltf_textures import MaterialReading, _flip_v, _texture_name
from .gltf_variants import VariantReading

SUPPORTED = {"EXT_mesh_gpu_instancing", "KHR_draco_mesh_compression", "KHR_mesh_quantization",
             "KHR_texture_transform",
             "KHR_materials_emissive_strength", "KHR_materials_unlit", "KHR_materials_ior",
             "KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_volume",
             "KHR_lights_punctual", "KHR_materials_clearcoat", "KHR_materials_sheen",
             "KHR_materials_variants", "EXT_texture_webp",
             "KHR_materials_pbrSpecularGlossiness", "EXT_meshopt_compression",
             "KHR_materials_iridescence", "KHR_materials_anisotropy",
             "KHR_materials_diffuse_transmission", "KHR_materials_dispersion",
             "KHR_xmp_json_ld"}  # (metadata: nothing to draw)
TRIANGLES, STRIP, FAN = 4, 5, 6
MODES = {0: "points", 1: "lines", 2: "line loops", 3: "line strips"}


def read_gltf(path: Path, check_mesh) -> tuple[list, dict, list, object]:
    """(parts as (name, mesh arguments, 4x4 node -> file), {camera name: Camera}, lights:
    KHR_lights_punctual's as facet lights (facet.formats.gltf_lights), and the Rig of its
    animations, skins and morph targets (facet.formats.gltf_rig; None when nothing moves);
    the parts stand at rest, the rig poses them.
    ``check_mesh(arrays, where)`` finishes a primitive's arrays into ``Mesh`` arguments.
    The document is checked (facet.formats.gltf_check) as JSON, before pygltflib builds it."""
    from pygltflib import GLTF2

    from ..guard import read_bytes

    raw = read_bytes(path, "glTF file", MeshError)  # once, through the guard
    document = _document(path, raw)
    version = str((document.get("asset") or {}).get("version", "") if isinstance(
        document.get("asset"), dict) else "")
    if not version.startswith("2."):
        raise MeshError(f"{path}: glTF {version or 'without asset.version'}; facet reads "
                        "glTF 2.0 (convert 1.0 files with the Khronos glTF-Pipeline)")
    check_gltf(document, path.name)
    try:
        gltf = GLTF2.load_from_bytes(raw) if raw[:4] == b"glTF" else \
            GLTF2.gltf_from_json(raw.decode("utf-8"))
        gltf._path, gltf._name = path.parent, path.name
    except Exception as exc:  # pygltflib raises what json/struct raise on bad files
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise MeshError(f"{path}: cannot read the file as glTF ({detail}); is it truncated "
                        "or in another format?") from None
    if gltf is None:
        raise MeshError(f"{path}: cannot read the file as glTF; is it truncated?")
    return _Reader(gltf, path, check_mesh, document).read()


def _document(path: Path, raw: bytes) -> dict:
    """The JSON document of the file ``path`` whose bytes are ``raw``: a .gltf's text, or
    a GLB's JSON chunk (its header checked: magic "glTF", container version 2, chunk
    lengths within the file)."""
    import json
    import struct

    size, head = len(raw), raw[:20]
    if head[:4] == b"glTF":
        version = struct.unpack("<I", head[4:8])[0] if len(head) >= 8 else None
        if version != 2:
            raise MeshError(f"{path}: binary glTF version {version}; facet reads version "
                            "2 (glTF 2.0)")
        length, kind = struct.unpack("<II", head[12:20]) if len(head) >= 20 else (0, 0)
        if kind != 0x4E4F534A or 20 + length > size:
            raise MeshError(f"{path}: its JSON chunk (of {length:,} bytes) does not fit in "
                            f"the file's {size:,}; is it truncated?")
        text = raw[20:20 + length]
    elif path.suffix.lower() == ".glb":
        raise MeshError(f"{path}: not a binary glTF file (it does not start with 'glTF'); "
                        "is it truncated or in another format?")
    else:
        text = raw
    from ..guard import json_depth

    limit = budget("depth")
    if json_depth(text, limit) > limit:
        raise MeshError(f"{path}: its JSON nests more than {limit:,} levels deep, facet's "
                        "budget (--budget depth=N)")
    try:
        document = json.loads(text)
    except RecursionError:
        raise MeshError(f"{path}: its JSON is nested too deeply to read") from None
    except (ValueError, UnicodeDecodeError) as exc:
        raise MeshError(f"{path}: cannot read the file as glTF ({exc}); is it truncated "
                        "or in another format?") from None
    if not isinstance(document, dict):
        raise MeshError(f"{path}: a glTF document is a JSON object")
    return document


class _Reader(MaterialReading, VariantReading):
    def __init__(self, gltf, path: Path, check_mesh, document: dict):
        self.gltf, self.path, self.check_mesh = gltf, path, check_mesh
        self.document = document
        self.data = GltfData(gltf, path)
        self.materials: dict[int, PbrMaterial] = {}
        self.textures: dict[int, object] = {}
        self.primitives: dict[tuple[int, int], dict | None] = {}
        self.skipped: set[str] = set()
        self.ktx2 = False  # (read: whether KTX2 textures are decoded here)

    def read(self) -> tuple[list, dict, list, object]:
        g = self.gltf
        required = set(g.extensionsRequired or ()) - SUPPORTED
        self.ktx2 = ktx2_available()  # KTX2 textures decoded (the ktx2 extra), else fallbacks
        if self.ktx2:
            required.discard("KHR_texture_basisu")
        if "KHR_texture_basisu" in required:
            self.data.fail("requires KHR_texture_basisu (KTX2 / Basis Universal textures), "
                           f"which needs the ktx2 extra: {KTX2_EXTRA}; or re-export its "
                           "textures as PNG or JPEG (gltf-transform png FILE OUT)")
        if required:
            self.data.fail(f"requires the glTF extension(s) {', '.join(sorted(required))}, "
                           "which facet does not support")
        ignored = set(g.extensionsUsed or ()) - SUPPORTED
        if "KHR_texture_basisu" in ignored:
            ignored.discard("KHR_texture_basisu")
            if not self.ktx2:
                self._ktx2_fallbacks()
        if ignored:
            self.warn(f"ignores the glTF extension(s) {', '.join(sorted(ignored))}")
        if not g.scenes and not g.nodes:
            self.data.fail("holds no scene and no nodes; nothing to render")
        self._decode_images()
        roots = g.scenes[g.scene or 0].nodes if g.scenes else self._roots()
        parts, cameras, lights, rigged = [], {}, [], []
        light_defs = document_lights(g, self.data.fail)
        stack = [(int(n), np.eye(4)) for n in reversed(roots or [])]
        while stack:
            index, parent = stack.pop()
            node = g.nodes[index]
            world = parent @ self._local(node)
            label = node.name or f"node{index}"
            if node.mesh is not None:
                mesh = g.meshes[node.mesh]
                prims = mesh.primitives
                copies = self._instances(index)  # EXT_mesh_gpu_instancing, else [None]
                for p in range(len(prims)):
                    args = self._primitive(node.mesh, p)
                    if args is None:
                        continue
                    suffix = f"/{p}" if len(prims) > 1 else ""
                    for k, offset in enumerate(copies):
                        copy = "" if offset is None else f"#{k}"
                        parts.append((f"{label}{suffix}{copy}", args,
                                      world if offset is None else world @ offset))
                        rigged.append((index, node.skin, args.get("deform"), offset))
            light = node_light(node, light_defs, self.data.fail)
            if light is not None:
                lights.append(facet_light(light_defs[light], world))
                if "range" in light_defs[light]:
                    self.skipped.add("KHR_lights_punctual's range (lights fall off with the "
                                     "inverse square of the distance, without end)")
            if node.camera is not None:
                name = g.cameras[node.camera].name or label
                cameras[name if name not in cameras else f"{name}{len(cameras)}"] = (
                    node.camera, world, index)
            stack.extend((int(c), world) for c in reversed(node.children or []))
        if not parts:
            self.data.fail("has nothing to draw in its scene (no triangles, points or "
                           "lines); nothing to render")
        for what in sorted(self.skipped):
            self.warn(f"leaves out {what}")
        rig = read_rig(self.document, self.data, rigged,
                       {name: node for name, (_, _, node) in cameras.items()})
        views = {name: gltf_camera(self.gltf, c, world, parts, self.data.fail)
                 for name, (c, world, _) in cameras.items()}
        return parts, views, lights, rig

    def _instances(self, index: int) -> list:
        """The instance matrices (4x4 instance -> node) of node ``index``'s
        EXT_mesh_gpu_instancing, or [None] for a plain node."""
        ext = (self.document["nodes"][index].get("extensions") or {}).get(
            "EXT_mesh_gpu_instancing")
        if ext is None:
            return [None]
        from ..scene.animation import trs_matrices

        attrs = ext.get("attributes") or {}
        where = f"nodes[{index}].extensions.EXT_mesh_gpu_instancing.attributes"
        # Each instance is an object: the count, from the accessors' own, against the
        # objects budget (every instanced node together) before anything is decoded.
        accessors = self.document.get("accessors") or []
        count = max((int(accessors[a].get("count", 0)) for a in attrs.values()
                     if isinstance(a, int) and 0 <= a < len(accessors)), default=0)
        self.instance_total = getattr(self, "instance_total", 0) + count * max(
            len(self.document["meshes"][self.document["nodes"][index]["mesh"]]
                .get("primitives") or []), 1)
        if self.instance_total > budget("objects"):
            self.data.fail(f"{where}: {self.instance_total:,} instances (with those of the "
                           f"nodes before), more than facet's budget of "
                           f"{budget('objects'):,} objects (--budget objects=N)")
        values = {}
        for key, width in (("TRANSLATION", 3), ("ROTATION", 4), ("SCALE", 3)):
            if key in attrs:
                v = np.asarray(self.data.accessor(attrs[key]), dtype=np.float64)
                if v.ndim != 2 or v.shape[1] != width:
                    self.data.fail(f"{where}.{key}: expected VEC{width} values")
                if not np.isfinite(v).all():
                    self.data.fail(f"{where}.{key} holds NaN or infinite values")
                values[key] = v
        counts = {len(v) for v in values.values()}
        if len(counts) != 1:
            self.data.fail(f"{where}: " + ("no TRANSLATION, ROTATION or SCALE" if not counts
                           else "its accessors hold different numbers of instances "
                           f"({', '.join(f'{k}: {len(v)}' for k, v in values.items())})"))
        n = counts.pop()
        rotation = values.get("ROTATION", np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)))
        if not np.all(np.linalg.norm(rotation, axis=1) > 0):
            self.data.fail(f"{where}.ROTATION holds a zero quaternion")
        return list(trs_matrices(values.get("TRANSLATION", np.zeros((n, 3))), rotation,
                                 values.get("SCALE", np.ones((n, 3)))))

    def _ktx2_fallbacks(self) -> None:
        """One line naming the KTX2 textures drawn from their PNG / JPEG fallbacks, if any
        has one (those without are named where a material uses them: gltf_textures)."""
        images = self.document.get("images") or []
        kept = []
        for i, t in enumerate(self.document.get("textures") or []):
            ext = (t.get("extensions") or {}).get("KHR_texture_basisu")
            if isinstance(ext, dict) and isinstance(t.get("source"), int):
                kept.append(_texture_name(t, ext, images, i))
        if kept:
            self.warn(f"draws the PNG / JPEG fallbacks of its KTX2 textures {', '.join(kept)} "
                      f"(KHR_texture_basisu: {KTX2_EXTRA} decodes them)")

    def warn(self, message: str) -> None:
        warnings.warn(f"{self.path.name}: {message}", FacetWarning, stacklevel=4)

    def _roots(self) -> list[int]:
        children = {int(c) for n in self.gltf.nodes for c in (n.children or [])}
        return [i for i in range(len(self.gltf.nodes)) if i not in children]

    @staticmethod
    def _local(node) -> np.ndarray:
        """The node's local matrix: ``matrix`` (column-major in the file) or T R S."""
        if node.matrix is not None and len(node.matrix) == 16:
            return np.asarray(node.matrix, dtype=np.float64).reshape(4, 4).T
        m = np.eye(4)
        if node.rotation is not None:
            x, y, z, w = np.asarray(node.rotation, dtype=np.float64) / max(
                np.linalg.norm(node.rotation), 1e-300)
            m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
        if node.scale is not None:
            m[:3, :3] = m[:3, :3] * np.asarray(node.scale, dtype=np.float64)[None, :]
        if node.translation is not None:
            m[:3, 3] = node.translation
        return m

    # -- geometry ------------------------------------------------------------------------
    def _primitive(self, mesh: int, p: int) -> dict | None:
        key = (mesh, p)
        if key not in self.primitives:
            self.primitives[key] = self._decode(mesh, p)
        return self.primitives[key]

    def _decode(self, mesh: int, p: int) -> dict | None:
        prim = self.gltf.meshes[mesh].primitives[p]
        where = f"mesh {self.gltf.meshes[mesh].name or mesh} primitive {p}"
        mode = TRIANGLES if prim.mode is None else prim.mode
        attrs = {k: v for k, v in vars(prim.attributes).items() if v is not None}
        draco = (prim.extensions or {}).get("KHR_draco_mesh_compression")
        if draco is not None:
            decoded = self.data.draco(draco, where, mode == 0)  # 0: POINTS
            indices = decoded.pop("indices")
            values = {}
            for name, array in decoded.items():
                acc = self.gltf.accessors[attrs[name]] if name in attrs else None
                if acc is not None and acc.normalized and array.dtype.kind in "iu":
                    array = np.maximum(array / np.iinfo(array.dtype).max, -1.0)
                values[name] = np.asarray(array, dtype=np.float32)
        else:
            if "POSITION" not in attrs:
                self.data.fail(f"{where} has no POSITION attribute")
            values = {k: np.asarray(self.data.accessor(v), dtype=np.float32)
                      for k, v in attrs.items()
                      if k in ("POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "TANGENT",
                               "COLOR_0")}
            count = len(values["POSITION"])
            indices = np.arange(count, dtype=np.uint32) if prim.indices is None else \
                self.data.accessor(prim.indices)
        if mode in MODES:  # points and lines (facet.scene.points)
            return self._sprites(values, indices, mode, prim, mesh, where)
        indices = np.asarray(indices)
        if mode != TRIANGLES:  # (strips and fans do index arithmetic)
            indices = indices.astype(np.int64)
        faces = _triangles(indices, mode, where, self.data.fail)
        prim_json = self.document["meshes"][mesh]["primitives"][p]
        # A Draco primitive's joints and weights come from its stream (decoded above by
        # their unique ids); its morph targets stay in plain accessors, in the stream's
        # vertex order (the extension has encoders keep it when there are targets).
        deform = vertex_deformation(prim_json, self.data, len(values["POSITION"]), where,
                                    decoded=values if draco is not None else None)
        colors = values.get("COLOR_0")
        if colors is not None:  # linear -> sRGB-encoded, alpha kept (module docstring)
            colors = np.concatenate([linear_to_srgb(np.clip(colors[:, :3], 0, 1)),
                                     colors[:, 3:4] if colors.shape[1] == 4 else
                                     np.ones((len(colors), 1))], axis=1)
        material = self._material(prim.material)
        uvs = [None if values.get(k) is None else _flip_v(values[k])
               for k in ("TEXCOORD_0", "TEXCOORD_1")]
        arrays = {"positions": values["POSITION"], "faces": faces,
                  "normals": values.get("NORMAL"), "uvs": uvs[0], "uvs1": uvs[1],
                  "tangents": values.get("TANGENT"),
                  "colors": None if colors is None else np.clip(colors, 0, 1),
                  "material": material, "deform": deform,
                  "variants": self._variants(prim_json, where),
                  "name": self.gltf.meshes[mesh].name or f"{self.path.stem}-{mesh}"}
        return self.check_mesh(arrays, where)

    def _sprites(self, values: dict, indices, mode: int, prim, mesh: int, where: str):
        """Points or Lines arguments of a POINTS / LINES / LINE_LOOP / LINE_STRIP
        primitive (its material's base colour; vertex colours; a point's normal lights
        it)."""
        from ..scene.points import strip_segments

        idx = np.asarray(indices, dtype=np.int64)
        positions = values["POSITION"]
        if len(idx) and (idx.min() < 0 or idx.max() >= len(positions)):
            self.data.fail(f"{where}: indices refer to vertices that do not exist")
        colors = values.get("COLOR_0")
        if colors is not None:  # linear -> sRGB-encoded (module docstring)
            colors = np.concatenate([linear_to_srgb(np.clip(colors[:, :3], 0, 1)),
                                     colors[:, 3:4] if colors.shape[1] == 4 else
                                     np.ones((len(colors), 1))], axis=1)
        name = self.gltf.meshes[mesh].name or f"{self.path.stem}-{mesh}"
        args = {"name": name, "material": self._material(prim.material),
                "colors": None if colors is None else np.clip(colors, 0, 1)}
        if mode == 0:
            used = np.unique(idx) if prim.indices is not None else slice(None)
            normals = values.get("NORMAL")
            args.update(kind="points", positions=positions[used],
                        normals=None if normals is None else normals[used],
                        colors=None if colors is None else args["colors"][used])
        else:
            if len(idx) < 2:
                self.data.fail(f"{where}: a line needs at least 2 vertices")
            segments = idx[:len(idx) - len(idx) % 2].reshape(-1, 2) if mode == 1 else \
                strip_segments(idx, loop=mode == 2)
            args.update(kind="lines", positions=positions, segments=segments)
        if prim.targets or "JOINTS_0" in vars(prim.attributes):
            if prim.targets or vars(prim.attributes).get("JOINTS_0") is not None:
                self.skipped.add("skins and morph targets of points and lines (drawn at "
                                 "rest)")
        return self.check_mesh(args, where)


def _triangles(indices: np.ndarray, mode: int, where: str, fail) -> np.ndarray:
    """(F, 3) counter-clockwise triangles of a triangle list, strip or fan."""
    if mode == TRIANGLES:
        n = len(indices) - len(indices) % 3
        return indices[:n].reshape(-1, 3)
    if len(indices) < 3:
        fail(f"{where}: a triangle {'strip' if mode == STRIP else 'fan'} needs at least "
             "3 indices")
    k = np.arange(len(indices) - 2)
    if mode == STRIP:  # every other triangle is wound the other way round
        odd = k % 2 == 1
        a, b = np.where(odd, k + 1, k), np.where(odd, k, k + 1)
        return np.stack([indices[a], indices[b], indices[k + 2]], axis=1)
    if mode == FAN:
        return np.stack([np.full_like(k, indices[0]), indices[k + 1], indices[k + 2]], axis=1)
    fail(f"{where}: unknown primitive mode {mode}")

