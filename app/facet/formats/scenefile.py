"""TOML scene files -> ``facet.Scene`` (see docs/scene-format.md for the format).

A scene file is a thin layer over the Python API: every table maps to one constructor
(``Material``, ``DirectionalLight``, ``Camera.look_at``, ``Scene.add`` ...). Nothing in a
scene file is ever executed; it is parsed with ``tomllib`` and validated key by key. Every
error names the file, the key path and what was expected, for example
``scene.toml: objects[2].material.shininess: expected a number >= 0, got "shiny"``; unknown
keys are errors with a did-you-mean.
"""

from __future__ import annotations

import difflib
from pathlib import Path
from typing import Any, cast

import numpy as np

from ..boundary import Crease, FilePath, checked
from ..budgets import budget
from ..errors import FacetError, SceneError
from ..geometry import transforms as T
from ..options.render import AA_KEYS, PARSERS, ParsedLayer, check_one_aa, parse_option
from ..scene.material import Material
from ..scene.pbr import PbrMaterial
from ..scene.primitives import PRIMITIVE_PARAMS, PRIMITIVES
from ..scene.scene import Scene
from ..scene.shapes import SHAPES
from .environment_files import resolve as resolve_environment
from .loading import read_parts
from .scenefile_lights import read_camera, read_lights
from .scenefile_materials import MaterialTables
from .validate import AnyKey as _Any
from .validate import Reader as _Reader
from .validate import show as _show

TOP = ("render", "materials", "objects", "lights", "cameras", "uniforms", "environment")
# The [render] table: any render option (facet.options.render parses each).
RENDER = tuple(PARSERS)
OBJECT = ("name", "mesh", "primitive", "material", "transform", "transform_end", "matrix",
          "parent", "flat", "crease", "point_size", "point_radius", "line_width",
          *sorted({p for params in PRIMITIVE_PARAMS.values() for p in params}))
TRANSFORM_OPS = ("translate", "scale", "rotate", "shear", "matrix")


@checked
def load_scene(path: FilePath, *, crease: Crease = None) -> Scene:
    """Read a TOML scene file (docs/scene-format.md).

    Parameters
    ----------
    path : str or Path
        The file.
    crease : float, optional
        The default crease angle of its mesh files (an object's ``crease`` wins).

    Returns
    -------
    Scene
        The scene, with its cameras, lights and render settings (``Scene.options``).

    Raises
    ------
    facet.SceneError
        One line naming the file and the key at fault.
    """
    from ..guard import parse_toml, read_text, regular_file

    path = regular_file(path, "scene file", SceneError)
    try:
        text = read_text(path, "scene file", SceneError)
    except UnicodeDecodeError:
        raise SceneError(f"{path.name}: not a text file (TOML must be UTF-8)") from None
    data = parse_toml(text, path.name, SceneError)
    return _SceneBuilder(_Reader(path), path.parent, crease).build(data)


class _SceneBuilder(MaterialTables):
    def __init__(self, r: _Reader, base: Path, crease: float | None = None):
        self.r, self.base, self.crease = r, base, crease
        self.parts_cache: dict[tuple, tuple[list, Any]] = {}  # (path, crease[, "flat"])
        self.primitive_cache: dict[tuple, Any] = {}  # (kind, flat, sizes) -> its geometry
        self.texture_cache: dict[Path, object] = {}

    def build(self, data: dict) -> Scene:
        r = self.r
        r.table(data, "", TOP)
        options = self.render_options(data.get("render", {}))
        self.uniforms = {name: self.uniform_value(v, f"uniforms.{name}") for name, v in
                         r.table(data.get("uniforms", {}), "uniforms", _Any()).items()}
        scene = Scene(options=options)
        materials = {name: self.material(m, f"materials.{name}")
                     for name, m in r.table(data.get("materials", {}), "materials",
                                            _Any()).items()}
        self.objects(scene, data.get("objects", []), materials)
        read_lights(self.r, scene, data.get("lights", []))
        if "environment" in data:  # one parser for here and [render] environment
            try:
                scene.environment = resolve_environment(
                    parse_option("environment", data["environment"], self.base))
            except FacetError as exc:
                r.fail("environment", str(exc).removeprefix("environment: "))
        cameras = r.table(data.get("cameras", {}), "cameras", _Any())
        for name, cam in cameras.items():
            scene.add_camera(name, read_camera(self.r, cam, f"cameras.{name}", scene))
        camera = options.get("camera")
        if camera is not None and not _picks_camera(scene, camera):
            close = difflib.get_close_matches(camera, list(scene.cameras), n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            r.fail("render.camera", f"no camera named {_show(camera)}{hint}")
        return scene

    def render_options(self, t: dict) -> ParsedLayer:
        """The [render] table's options, parsed by the parser every front shares (relative
        file names from the scene file's folder)."""
        r = self.r
        r.table(t, "render", RENDER)
        try:
            check_one_aa(t)
        except FacetError as exc:
            r.fail("render", str(exc))
        return ParsedLayer({("aa" if k in AA_KEYS else k): self.option(k, v)
                            for k, v in t.items()})

    def option(self, key: str, value):
        try:
            return parse_option(key, value, self.base)
        except FacetError as exc:
            self.r.fail(f"render.{key}", _strip_key(str(exc), key))

    def objects(self, scene: Scene, items, materials: dict) -> None:
        r = self.r
        if not isinstance(items, list):
            r.fail("objects", "expected an array of tables ([[objects]])")
        if len(items) > budget("objects"):
            r.fail("objects", f"{len(items):,} objects, more than facet's budget of "
                   f"{budget('objects'):,} (--budget objects=N)")
        nodes: dict[str, dict] = {}
        for i, t in enumerate(items):
            where = f"objects[{i}]"
            r.table(t, where, OBJECT)
            name = r.string(t["name"], f"{where}.name") if "name" in t else f"object{i}"
            if name in nodes:
                r.fail(f"{where}.name", f"the name {_show(name)} is already used by "
                       f"{nodes[name]['where']}")
            local = self.local_transform(t, where)
            # Motion blur: the local transform at shutter close (default: not moving).
            end = self.steps(t["transform_end"], f"{where}.transform_end") \
                if "transform_end" in t else local
            nodes[name] = {"where": where, "t": t, "local": local, "local_end": end}
        order = self.resolve_parents(nodes)
        for name in order:
            node = nodes[name]
            t, where = node["t"], node["where"]
            parent = t.get("parent")
            node["world"] = (nodes[parent]["world"] if parent else np.eye(4)) @ node["local"]
            node["world_end"] = (nodes[parent]["world_end"] if parent else np.eye(4)) @ \
                node["local_end"]  # children move with their parents
            moving = not np.array_equal(node["world_end"], node["world"])
            material = None
            if "material" in t:
                material = self.object_material(t["material"], f"{where}.material", materials)
            parts, rig = self.geometry(t, where)
            ids: list[int] = []
            for part_name, mesh, matrix in parts:
                try:
                    ids.append(cast(int, scene.add(  # one geometry: an id
                        mesh, material, node["world"] @ matrix, name=part_name or name,
                        transform_end=node["world_end"] @ matrix if moving else None)))
                except FacetError as exc:
                    r.fail(where, str(exc))
            if rig is not None:  # the model's animations, skins and morphs, placed here
                from ..scene.animation import Animated

                scene.animated.append(Animated(rig, ids, node["world"]))

    def resolve_parents(self, nodes: dict) -> list[str]:
        """Node names with every parent before its children (in time linear in the nodes);
        cycles, unknown parents and chains deeper than the depth budget fail."""
        r = self.r
        order: list[str] = []
        state: dict[str, str] = {}
        limit = budget("depth")
        for name in nodes:
            chain: list[str] = []
            seen: set[str] = set()
            current = name
            while current is not None and state.get(current) != "done":
                if current in seen:
                    loop = " -> ".join([*chain[chain.index(current):], current])
                    r.fail(f"{nodes[name]['where']}.parent", f"parent cycle: {loop}")
                if len(chain) >= limit:
                    r.fail(f"{nodes[name]['where']}.parent", f"parents more than {limit:,} "
                           "levels deep, facet's budget (--budget depth=N)")
                chain.append(current)
                seen.add(current)
                parent = nodes[current]["t"].get("parent")
                if parent is not None:
                    parent = r.string(parent, f"{nodes[current]['where']}.parent")
                    if parent not in nodes:
                        close = difflib.get_close_matches(parent, list(nodes), n=1)
                        hint = f" (did you mean '{close[0]}'?)" if close else ""
                        r.fail(f"{nodes[current]['where']}.parent",
                               f"no object named {_show(parent)}{hint}")
                current = parent
            for n in reversed(chain):
                state[n] = "done"
                order.append(n)
        return order

    def local_transform(self, t: dict, where: str) -> np.ndarray:
        r = self.r
        if "matrix" in t and "transform" in t:
            r.fail(where, "give either 'transform' (a list of steps) or 'matrix', not both")
        if "matrix" in t:
            m = r.matrix(t["matrix"], f"{where}.matrix")
        else:
            m = self.steps(t.get("transform", []), f"{where}.transform")
        if abs(np.linalg.det(m[:3, :3])) < 1e-12:
            r.fail(f"{where}.transform", "the transform is singular (a zero scale?)")
        return m

    def steps(self, steps, where: str) -> np.ndarray:
        """The matrix of a list of transform steps, applied first to last."""
        if not isinstance(steps, list):
            self.r.fail(where, "expected a list of steps like "
                        "[{scale = 2}, {translate = [0, 1, 0]}]")
        m = T.compose(*(self.step(s, f"{where}[{i}]") for i, s in enumerate(steps)))
        if abs(np.linalg.det(m[:3, :3])) < 1e-12:
            self.r.fail(where, "the transform is singular (a zero scale?)")
        return m

    def step(self, s, where: str) -> np.ndarray:
        r = self.r
        r.table(s, where, TRANSFORM_OPS)
        if len(s) != 1:
            r.fail(where, f"each step holds exactly one operation ({', '.join(TRANSFORM_OPS)})")
        op, v = next(iter(s.items()))
        at = f"{where}.{op}"
        if op == "translate":
            return T.translate(r.vector(v, at))
        if op == "scale":
            f = r.vector(v, at) if isinstance(v, list) else np.repeat(r.number(v, at), 3)
            if np.any(f == 0):
                r.fail(at, f"a scale of 0 flattens the object; got {_show(v)}")
            return T.scale(f)
        if op == "rotate":
            r.table(v, at, ("axis", "degrees"))
            if "degrees" not in v or "axis" not in v:
                r.fail(at, 'expected {axis = "x"|"y"|"z"|[x, y, z], degrees = number}')
            axis = v["axis"]
            if isinstance(axis, str):
                axis = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}.get(axis) or r.fail(
                    f"{at}.axis", f'expected "x", "y", "z" or [x, y, z], got {_show(axis)}')
            else:
                axis = r.vector(axis, f"{at}.axis")
                if not np.linalg.norm(axis) > 0:
                    r.fail(f"{at}.axis", "the rotation axis must not be [0, 0, 0]")
            return T.rotate(axis, r.number(v["degrees"], f"{at}.degrees"))
        if op == "shear":
            pairs = ("xy", "xz", "yx", "yz", "zx", "zy")
            r.table(v, at, pairs)
            return T.shear(**{k: r.number(x, f"{at}.{k}") for k, x in v.items()})
        return r.matrix(v, at)

    def object_material(self, value, where: str, materials: dict) -> Material | PbrMaterial:
        if isinstance(value, str):
            if value not in materials:
                close = difflib.get_close_matches(value, list(materials), n=1)
                hint = f" (did you mean '{close[0]}'?)" if close else ""
                self.r.fail(where, f"no material named {_show(value)}{hint}")
            return materials[value]
        return self.material(value, where)

    def geometry(self, t: dict, where: str) -> tuple[list, Any]:
        """An object's parts (name, mesh or shape, transform) and its rig: a file's
        (``mesh``), a primitive's, or none (a group node)."""
        r = self.r
        if "mesh" in t and "primitive" in t:
            r.fail(where, "give either 'mesh' (a file) or 'primitive', not both")
        kind = t.get("primitive")
        params = [p for p in t if p in {p for ps in PRIMITIVE_PARAMS.values() for p in ps}]
        if kind is None and params:
            r.fail(f"{where}.{params[0]}", "size parameters belong to a 'primitive'")
        if "mesh" in t:
            path = self.base / r.string(t["mesh"], f"{where}.mesh")
            from .splat_files import is_splat_file

            try:
                splats = is_splat_file(path)  # its header read through facet.guard
            except FacetError as exc:
                r.fail(f"{where}.mesh", str(exc))
            if splats:  # Gaussian splats (3DGS PLY, .splat): one cloud
                return self._splat_file(t, where, path)
            return self._mesh_file(t, where, path)
        if kind is None:
            return [], None  # a group node: only a transform for its children
        return self._primitive(t, where, r.choice(kind, f"{where}.primitive",
                                                  tuple(PRIMITIVES)), params)

    def _splat_file(self, t: dict, where: str, path: Path) -> tuple[list, Any]:
        from .splat_files import read_splats

        r = self.r
        extra = [k for k in ("crease", "flat", "point_size", "point_radius", "line_width")
                 if k in t]
        if extra:
            r.fail(f"{where}.{extra[0]}", "a file of Gaussian splats takes no "
                   f"{extra[0]} (splats keep their own sizes and colours)")
        if (path, "splats") not in self.parts_cache:
            try:
                cloud = [(None, read_splats(path), np.eye(4))]
            except FacetError as exc:
                r.fail(f"{where}.mesh", str(exc))
            self.parts_cache[path, "splats"] = cloud, None
        return self.parts_cache[path, "splats"]

    def _mesh_file(self, t: dict, where: str, path: Path) -> tuple[list, Any]:
        """A mesh file's parts (read once per file and crease), flat-shaded and with its
        sprites resized as the object asks."""
        r = self.r
        crease = self.crease
        if "crease" in t:
            crease = r.number(t["crease"], f"{where}.crease", minimum=0)
            if crease > 180:
                r.fail(f"{where}.crease", f"expected degrees in [0, 180] (180: fully "
                       f"smooth), got {_show(t['crease'])}")
        if (path, crease) not in self.parts_cache:
            try:
                parts, _, _, rig = read_parts(path, crease)
            except FacetError as exc:
                r.fail(f"{where}.mesh", str(exc))
            self.parts_cache[path, crease] = parts, rig
        parts, rig = self.parts_cache[path, crease]
        if t.get("flat"):
            if rig is not None:  # one vertex per face corner: the skin data follows
                rig = rig.with_corners([m.faces.reshape(-1) for _, m, _ in parts])
            if (path, crease, "flat") not in self.parts_cache:  # made once per file
                self.parts_cache[path, crease, "flat"] = [
                    (n, m.flat_shaded() if m.kind == "mesh" else m, x)
                    for n, m, x in parts], None
            parts = self.parts_cache[path, crease, "flat"][0]
        sizes = {k: r.number(t[k], f"{where}.{k}", above=0) if k in t else None
                 for k in ("point_size", "point_radius", "line_width")}
        if any(v is not None for v in sizes.values()):
            from ..scene.points import resize_sprites

            try:
                parts = [(n, resize_sprites(m, **sizes), x) for n, m, x in parts]
            except FacetError as exc:
                r.fail(where, str(exc))
        return [(n if len(parts) > 1 else None, m, x) for n, m, x in parts], rig

    def _primitive(self, t: dict, where: str, kind: str, params: list) -> tuple[list, Any]:
        """A primitive's one part: an exact shape, or its tessellation (flat = true, or
        no shape of that kind); objects of one primitive and size share it."""
        r = self.r
        for p in params:
            if p not in PRIMITIVE_PARAMS[kind]:
                r.fail(f"{where}.{p}", f"{kind} takes {', '.join(PRIMITIVE_PARAMS[kind])}")
        kwargs: dict[str, Any] = {}
        for p in params:
            v = t[p]
            if kind == "plane" and v == float("inf"):  # size = inf: the infinite plane
                kwargs[p] = None
                continue
            kwargs[p] = r.vector(v, f"{where}.{p}", len(v)) if isinstance(v, list) else \
                r.number(v, f"{where}.{p}", above=0)
        # (a scene of 30,000 equal spheres tessellates, checks and uploads one)
        key = (kind, bool(t.get("flat")),
               tuple((k, None if v is None else tuple(np.ravel(v).tolist()))
                     for k, v in sorted(kwargs.items())))
        if key not in self.primitive_cache:
            try:
                # Primitives are exact shapes for the ray tracer (a torus, or flat = true,
                # a mesh); the rasterizer draws their tessellation.
                made: Any
                if kind in SHAPES and not t.get("flat"):
                    made = SHAPES[kind](**kwargs)
                else:
                    if kwargs.get("size", 0) is None:
                        r.fail(f"{where}.size", "an infinite plane cannot be flat-shaded")
                    mesh = PRIMITIVES[kind](**kwargs)
                    made = mesh.flat_shaded() if t.get("flat") else mesh
            except SceneError:
                raise
            except FacetError as exc:
                r.fail(where, str(exc))
            self.primitive_cache[key] = made
        return [(None, self.primitive_cache[key], np.eye(4))], None


def _strip_key(message: str, key: str | None) -> str:
    """An option parser's message without its leading ``key: `` (the caller names the key)."""
    return message[len(key) + 2:] if key and message.startswith(f"{key}: ") else message


def _picks_camera(scene, name) -> bool:
    """Whether ``name`` picks one of the scene's cameras (a name, "first" or an index)."""
    try:
        scene.camera_key(name)
    except FacetError:
        return False
    return True
