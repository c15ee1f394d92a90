"""The one check between a parsed glTF document and facet's reader (no GL): every index,
count, offset, stride and length checked against what it refers to, every value's type
checked, the node graph checked for cycles, shared children and depth, and the sizes held
to facet's budgets (facet.budgets), before any numpy view is made. A file that fails gets
one MeshError naming the file and the key path, e.g.
``m.glb: accessors[3].byteOffset: expected an integer >= 0, got -4096``.

It reads pygltflib's objects (or plain dicts, for extensions and what pygltflib leaves as
dicts), whose values are the file's own: a string where a number belongs is still a
string here.
"""

from __future__ import annotations

import numbers

from ..budgets import budget
from ..errors import MeshError
from ..options.values import number_problem
from .gltf_materials import TEXTURES as EXTENSION_TEXTURES

COMPONENTS = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}  # componentType: bytes
INDEX_COMPONENTS = (5121, 5123, 5125)
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
ALPHA_MODES = ("OPAQUE", "MASK", "BLEND")
TEXTURE_INFOS = ("baseColorTexture", "metallicRoughnessTexture")


def get(obj, key):
    """``obj.key`` or ``obj[key]`` (pygltflib objects and plain dicts alike), else None."""
    if isinstance(obj, dict):
        return obj.get(key)
    return getattr(obj, key, None)


class GltfCheck:
    """Checks one parsed document (``check``); ``name`` is the file's name for messages."""

    def __init__(self, gltf, name: str):
        self.g, self.name = gltf, name

    # -- value checks --------------------------------------------------------------------
    def fail(self, path: str, problem: str):
        raise MeshError(f"{self.name}: {path}: {problem}")

    def integer(self, value, path: str, low: int = 0, high: int | None = None,
                optional: bool = True):
        if value is None and optional:
            return None
        ok = isinstance(value, numbers.Integral) and not isinstance(value, bool)
        if not ok or value < low or (high is not None and value > high):
            span = f"in [{low}, {high}]" if high is not None else f">= {low}"
            self.fail(path, f"expected an integer {span}, got {value!r}")
        return int(value)

    def number(self, value, path: str, low: float | None = None, optional: bool = True,
               above: float | None = None):
        if value is None and optional:
            return None
        problem = number_problem(value, low, above)
        if problem:
            self.fail(path, f"{problem}, got {value!r}")
        return float(value)

    def numbers(self, value, path: str, n: int):
        if value is None:
            return
        if not isinstance(value, (list, tuple)) or len(value) != n:
            self.fail(path, f"expected a list of {n} numbers, got {value!r}")
        for k, v in enumerate(value):
            self.number(v, f"{path}[{k}]", optional=False)

    def ref(self, value, collection: str, path: str, optional: bool = True):
        """An index into the document's ``collection``."""
        items = get(self.g, collection) or []
        if value is None and optional:
            return None
        self.integer(value, path, 0, max(len(items) - 1, 0), optional=False)
        if not items:
            self.fail(path, f"refers to {collection}[{value}], but the file has no "
                      f"{collection}")
        return int(value)

    def items(self, collection: str) -> list:
        value = get(self.g, collection)
        if value is None:
            return []
        if not isinstance(value, list):
            self.fail(collection, f"expected a list, got {type(value).__name__}")
        return value

    def table(self, value, path: str) -> dict:
        if value is None:
            return {}
        if not isinstance(value, dict):
            self.fail(path, f"expected an object, got {value!r}")
        return value

    # -- the document --------------------------------------------------------------------
    def check(self) -> None:
        for name in ("buffers", "bufferViews", "accessors", "images", "samplers", "textures",
                     "materials", "meshes", "cameras", "skins", "nodes", "scenes",
                     "animations"):
            items = self.items(name)
            limit = budget("nodes") if name == "nodes" else budget("gltf_items")
            if len(items) > limit:
                self.fail(name, f"{len(items):,} of them, more than facet's budget of "
                          f"{limit:,} (raise it with --budget "
                          f"{'nodes' if name == 'nodes' else 'gltf_items'}=N)")
            for i, item in enumerate(items):
                if item is None or isinstance(item, (str, numbers.Number, list)):
                    self.fail(f"{name}[{i}]", f"expected an object, got {item!r}")
                getattr(self, f"_{name.lower()}")(item, f"{name}[{i}]")
        self.ref(get(self.g, "scene"), "scenes", "scene")
        self._graph()

    def _buffers(self, b, path):
        self.integer(get(b, "byteLength"), f"{path}.byteLength", 1, budget("file_bytes"),
                     optional=False)
        uri = get(b, "uri")
        if uri is not None and not isinstance(uri, str):
            self.fail(f"{path}.uri", f"expected a string, got {uri!r}")

    def _bufferviews(self, v, path):
        self.ref(get(v, "buffer"), "buffers", f"{path}.buffer", optional=False)
        self.integer(get(v, "byteOffset"), f"{path}.byteOffset")
        self.integer(get(v, "byteLength"), f"{path}.byteLength", 1, optional=False)
        self.integer(get(v, "byteStride"), f"{path}.byteStride", 4, 252)

    def _accessors(self, a, path):
        self.ref(get(a, "bufferView"), "bufferViews", f"{path}.bufferView")
        self.integer(get(a, "byteOffset"), f"{path}.byteOffset")
        kind = get(a, "componentType")
        if not isinstance(kind, int) or isinstance(kind, bool) or kind not in COMPONENTS:
            self.fail(f"{path}.componentType", f"unknown component type {kind!r}")
        shape = get(a, "type")
        if not isinstance(shape, str) or shape not in WIDTH:
            self.fail(f"{path}.type", f"unknown type {shape!r}; expected one of "
                      f"{', '.join(WIDTH)}")
        count = self.integer(get(a, "count"), f"{path}.count", 1, optional=False)
        if count * WIDTH[shape] > budget("elements"):
            self.fail(f"{path}.count", f"{count:,} {shape} elements, more than facet's "
                      f"budget of {budget('elements'):,} numbers per accessor")
        sparse = get(a, "sparse")
        if sparse is not None:
            sp = f"{path}.sparse"
            n = self.integer(get(sparse, "count"), f"{sp}.count", 1, count, optional=False)
            indices, values = get(sparse, "indices"), get(sparse, "values")
            if indices is None or values is None:
                self.fail(sp, "needs indices and values")
            self.ref(get(indices, "bufferView"), "bufferViews", f"{sp}.indices.bufferView",
                     optional=False)
            self.integer(get(indices, "byteOffset"), f"{sp}.indices.byteOffset")
            if get(indices, "componentType") not in INDEX_COMPONENTS:
                self.fail(f"{sp}.indices.componentType", "expected 5121, 5123 or 5125 "
                          f"(unsigned integers), got {get(indices, 'componentType')!r}")
            self.ref(get(values, "bufferView"), "bufferViews", f"{sp}.values.bufferView",
                     optional=False)
            self.integer(get(values, "byteOffset"), f"{sp}.values.byteOffset")
            assert n >= 1

    def _images(self, im, path):
        self.ref(get(im, "bufferView"), "bufferViews", f"{path}.bufferView")
        uri = get(im, "uri")
        if uri is not None and not isinstance(uri, str):
            self.fail(f"{path}.uri", f"expected a string, got {uri!r}")

    def _samplers(self, s, path):
        for key in ("magFilter", "minFilter", "wrapS", "wrapT"):
            self.integer(get(s, key), f"{path}.{key}")

    def _textures(self, t, path):
        self.ref(get(t, "source"), "images", f"{path}.source")
        self.ref(get(t, "sampler"), "samplers", f"{path}.sampler")
        ext = self.table(get(t, "extensions"), f"{path}.extensions")
        for name in ("EXT_texture_webp", "KHR_texture_basisu"):
            if ext.get(name) is not None:
                at = f"{path}.extensions.{name}"
                self.ref(self.table(ext[name], at).get("source"), "images", f"{at}.source")

    def _texture_info(self, info, path):
        if info is None:
            return
        if not hasattr(info, "texCoord"):  # not pygltflib's: the extensions' must be objects
            self.table(info, path)
        self.ref(get(info, "index"), "textures", f"{path}.index", optional=False)
        self.integer(get(info, "texCoord"), f"{path}.texCoord", 0, 7)
        self.number(get(info, "scale"), f"{path}.scale")
        self.number(get(info, "strength"), f"{path}.strength")
        ext = self.table(get(info, "extensions"), f"{path}.extensions")
        tt = self.table(ext.get("KHR_texture_transform"),
                        f"{path}.extensions.KHR_texture_transform")
        at = f"{path}.extensions.KHR_texture_transform"
        self.numbers(tt.get("offset"), f"{at}.offset", 2)
        self.numbers(tt.get("scale"), f"{at}.scale", 2)
        self.number(tt.get("rotation"), f"{at}.rotation")
        self.integer(tt.get("texCoord"), f"{at}.texCoord", 0, 7)

    def _materials(self, m, path):
        pbr = get(m, "pbrMetallicRoughness")
        if pbr is not None:
            at = f"{path}.pbrMetallicRoughness"
            self.numbers(get(pbr, "baseColorFactor"), f"{at}.baseColorFactor", 4)
            self.number(get(pbr, "metallicFactor"), f"{at}.metallicFactor")
            self.number(get(pbr, "roughnessFactor"), f"{at}.roughnessFactor")
            for key in TEXTURE_INFOS:
                self._texture_info(get(pbr, key), f"{at}.{key}")
        for key in ("normalTexture", "occlusionTexture", "emissiveTexture"):
            self._texture_info(get(m, key), f"{path}.{key}")
        self.numbers(get(m, "emissiveFactor"), f"{path}.emissiveFactor", 3)
        mode = get(m, "alphaMode")
        if mode is not None and mode not in ALPHA_MODES:
            self.fail(f"{path}.alphaMode", f"expected one of {', '.join(ALPHA_MODES)}, got "
                      f"{mode!r}")
        self.number(get(m, "alphaCutoff"), f"{path}.alphaCutoff")
        double = get(m, "doubleSided")
        if double is not None and not isinstance(double, bool):
            self.fail(f"{path}.doubleSided", f"expected true or false, got {double!r}")
        ext = self.table(get(m, "extensions"), f"{path}.extensions")
        for extension, fields in EXTENSION_TEXTURES.items():
            values = self.table(ext.get(extension), f"{path}.extensions.{extension}")
            for key, _ in fields:
                self._texture_info(values.get(key), f"{path}.extensions.{extension}.{key}")
        strength = self.table(ext.get("KHR_materials_emissive_strength"),
                              f"{path}.extensions.KHR_materials_emissive_strength")
        self.number(strength.get("emissiveStrength"), f"{path}.extensions."
                    "KHR_materials_emissive_strength.emissiveStrength", low=0)

    def _meshes(self, mesh, path):
        prims = get(mesh, "primitives")
        if not isinstance(prims, list) or not prims:
            self.fail(f"{path}.primitives", "expected a list of primitives")
        for k, p in enumerate(prims):
            at = f"{path}.primitives[{k}]"
            attributes = get(p, "attributes")
            values = attributes if isinstance(attributes, dict) else \
                vars(attributes) if attributes is not None else {}
            for name, index in values.items():
                self.ref(index, "accessors", f"{at}.attributes.{name}")
            self.ref(get(p, "indices"), "accessors", f"{at}.indices")
            self.ref(get(p, "material"), "materials", f"{at}.material")
            self.integer(get(p, "mode"), f"{at}.mode", 0, 6)
            for t, target in enumerate(get(p, "targets") or []):
                for name, index in self.table(target, f"{at}.targets[{t}]").items():
                    self.ref(index, "accessors", f"{at}.targets[{t}].{name}")
            ext = self.table(get(p, "extensions"), f"{at}.extensions")
            draco = ext.get("KHR_draco_mesh_compression")
            if draco is not None:
                dp = f"{at}.extensions.KHR_draco_mesh_compression"
                draco = self.table(draco, dp)
                self.ref(draco.get("bufferView"), "bufferViews", f"{dp}.bufferView",
                         optional=False)
                for name, uid in self.table(draco.get("attributes"),
                                            f"{dp}.attributes").items():
                    self.integer(uid, f"{dp}.attributes.{name}", optional=False)

    def _cameras(self, c, path):
        kind = get(c, "type")
        persp, ortho = get(c, "perspective"), get(c, "orthographic")
        if kind == "perspective" or (kind is None and persp is not None):
            if persp is None:
                self.fail(path, "a perspective camera needs its perspective data")
            at = f"{path}.perspective"
            self.number(get(persp, "yfov"), f"{at}.yfov", above=0, optional=False)
            near = self.number(get(persp, "znear"), f"{at}.znear", above=0)
            self.number(get(persp, "zfar"), f"{at}.zfar", above=near or 0)
            self.number(get(persp, "aspectRatio"), f"{at}.aspectRatio", above=0)
        elif kind == "orthographic":
            if ortho is None:
                self.fail(path, "an orthographic camera needs its orthographic data")
            at = f"{path}.orthographic"
            for key in ("xmag", "ymag"):
                self.number(get(ortho, key), f"{at}.{key}")
            near = self.number(get(ortho, "znear"), f"{at}.znear", low=0)
            self.number(get(ortho, "zfar"), f"{at}.zfar", above=near or 0)
        else:
            self.fail(f"{path}.type", f"expected perspective or orthographic, got {kind!r}")

    def _skins(self, s, path):
        self._node_list(get(s, "joints"), f"{path}.joints")
        self.ref(get(s, "inverseBindMatrices"), "accessors", f"{path}.inverseBindMatrices")
        self.ref(get(s, "skeleton"), "nodes", f"{path}.skeleton")

    def _animations(self, a, path):
        samplers = get(a, "samplers")
        channels = get(a, "channels")
        for key, value in (("samplers", samplers), ("channels", channels)):
            if not isinstance(value, list) or not value:
                self.fail(f"{path}.{key}", f"expected a list of {key}, got {value!r}")
        for k, s in enumerate(samplers):
            at = f"{path}.samplers[{k}]"
            s = self.table(s, at)
            self.ref(s.get("input"), "accessors", f"{at}.input", optional=False)
            self.ref(s.get("output"), "accessors", f"{at}.output", optional=False)
        for k, c in enumerate(channels):
            at = f"{path}.channels[{k}]"
            c = self.table(c, at)
            self.integer(c.get("sampler"), f"{at}.sampler", 0, len(samplers) - 1,
                         optional=False)
            target = self.table(c.get("target"), f"{at}.target")
            self.ref(target.get("node"), "nodes", f"{at}.target.node")

    def _node_list(self, value, path):
        """A list of node indices (a node's children, a scene's nodes)."""
        if value is not None and not isinstance(value, list):
            self.fail(path, f"expected a list of node indices, got {value!r}")
        for k, c in enumerate(value or []):
            self.ref(c, "nodes", f"{path}[{k}]", optional=False)

    def _nodes(self, n, path):
        self._node_list(get(n, "children"), f"{path}.children")
        self.ref(get(n, "mesh"), "meshes", f"{path}.mesh")
        self.ref(get(n, "camera"), "cameras", f"{path}.camera")
        self.ref(get(n, "skin"), "skins", f"{path}.skin")
        ext = self.table(get(n, "extensions"), f"{path}.extensions")
        if ext.get("EXT_mesh_gpu_instancing") is not None:
            at = f"{path}.extensions.EXT_mesh_gpu_instancing"
            inst = self.table(ext["EXT_mesh_gpu_instancing"], at)
            for key, index in self.table(inst.get("attributes"), f"{at}.attributes").items():
                self.ref(index, "accessors", f"{at}.attributes.{key}", optional=False)
        weights = get(n, "weights")
        if weights is not None:
            self.numbers(weights, f"{path}.weights", len(weights) if isinstance(
                weights, list) else 0)
        self.numbers(get(n, "matrix"), f"{path}.matrix", 16)
        self.numbers(get(n, "rotation"), f"{path}.rotation", 4)
        self.numbers(get(n, "scale"), f"{path}.scale", 3)
        self.numbers(get(n, "translation"), f"{path}.translation", 3)

    def _scenes(self, s, path):
        self._node_list(get(s, "nodes"), f"{path}.nodes")

    def _graph(self) -> None:
        """The nodes form a forest (each node one parent at most, no cycles), no deeper
        than the depth budget: checked without recursion, in time linear in the nodes."""
        nodes = self.items("nodes")
        parent: dict[int, int] = {}
        for i, n in enumerate(nodes):
            for c in get(n, "children") or []:
                if c == i:
                    self.fail(f"nodes[{i}].children", "the node is its own child")
                if c in parent:
                    self.fail(f"nodes[{c}]", f"is a child of nodes[{parent[c]}] and of "
                              f"nodes[{i}]; a glTF node has one parent")
                parent[c] = i
        depth_limit = budget("depth")
        depth: dict[int, int] = {}
        for start in range(len(nodes)):  # each node's depth, following its parents once
            chain, k = [], start
            while k not in depth and k in parent:
                chain.append(k)
                if len(chain) > len(nodes):
                    self.fail(f"nodes[{start}]", "its parents form a cycle")
                k = parent[k]
            base = depth.get(k, 0)
            for offset, node in enumerate(reversed(chain), start=1):
                depth[node] = base + offset
            if depth.get(start, 0) > depth_limit:
                self.fail(f"nodes[{start}]", f"is {depth[start]:,} levels deep, more than "
                          f"facet's budget of {depth_limit:,} (--budget depth=N)")


def check_gltf(gltf, name: str) -> None:
    """MeshError (one line) unless ``gltf`` is well-formed for facet's reader."""
    GltfCheck(gltf, name).check()
