"""Layering: geometry and scene never load GL (a scene file using every key loads where
moderngl cannot be imported); imports point down the layers with no circles; the CLI's
--help loads nothing heavy."""

import ast
import json
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "app" / "facet"
EVERY_KEY = Path(__file__).resolve().parent / "data" / "every-key.toml"
# Layers, lowest first (DESIGN.md): a module may import its own layer or lower ones.
# DESIGN.md's layers, bottom up: imports point down only (the README lists them too).
LAYERS = [{"errors", "paths", "srgb", "guard", "budgets", "lazy", "boundary"}, {"geometry"},
          {"scene"},
          {"formats", "options"}, {"gl"},
          {"render", "image"}, {"lab", "batch", "viewing"},
          {"cli", "window", "notebook", "serve"}, {"__init__", "__main__"}]


def _run(code: str) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True).stdout


def _loaded_after(code: str) -> set[str]:
    out = _run(code + "\nimport sys, json\nprint(json.dumps(sorted(sys.modules)))")
    return set(json.loads(out.splitlines()[-1]))


def test_geometry_and_scene_do_not_import_gl():
    mods = _loaded_after("import facet.geometry, facet.scene, facet.gl.glsl_source\n"
                         "import facet.render.shading\n"
                         "facet.scene.Mesh([[0,0,0],[1,0,0],[0,1,0]], [[0,1,2]])")
    assert "facet.geometry.camera" in mods and "facet.scene.mesh" in mods
    assert not {m for m in mods if m.split(".")[0] in ("moderngl", "glfw", "glcontext")}


def test_a_scene_file_with_every_key_loads_without_gl():
    """moderngl, glcontext and glfw are made unimportable: loading the scene and resolving
    its render options must not need them, directly or through a helper."""
    out = _run("import sys\n"
               "for name in ('moderngl', 'glcontext', 'glfw'):\n"
               "    sys.modules[name] = None  # any import of it raises ImportError\n"
               "from facet.formats import load_scene\n"
               "from facet.options.render import options_for\n"
               f"scene = load_scene({str(EVERY_KEY)!r})\n"
               "opts = options_for(scene, {'msaa': 2})\n"
               "print(len(scene.objects), opts.size, opts.shading, opts.aa, opts.shadows)")
    assert out.split() == ["7", "(64,", "48)", "blinn", "msaa:2", "True"]


def test_the_every_key_file_covers_every_key():
    """The file above must use every key the scene-file parser knows (so adding a key
    without trying it here fails)."""
    from facet.formats import scenefile as sf
    from facet.formats import scenefile_lights as sl

    data = tomllib.loads(EVERY_KEY.read_text())
    assert set(data) == set(sf.TOP)
    # msaa and spp are sugar for aa and may not share a table with it (test_options.py)
    assert set(data["render"]) | {"msaa", "spp"} == set(sf.RENDER)
    from facet.formats import scenefile_materials as sm

    tables = data["materials"].values()
    assert set().union(*(m for m in tables if not sm.is_pbr(m))) == set(sm.MATERIAL)
    assert set().union(*(m for m in tables if sm.is_pbr(m))) == set(sm.PBR + sm.SHARED)
    slots = [v for m in tables for k, v in m.items() if k.endswith("_texture")
             and isinstance(v, dict)]
    assert set().union(*slots) == set(sm.SLOT_KEYS)
    objects = set().union(*data["objects"])
    assert objects == set(sf.OBJECT)
    steps = {op for o in data["objects"] for s in o.get("transform", []) for op in s}
    assert steps == set(sf.TRANSFORM_OPS)
    for kind, keys in sl.LIGHT.items():
        used = [set(x) - {"type"} for x in data["lights"] if x["type"] == kind]
        assert used and used[0] == set(keys), kind
    for kind, keys in sl.CAMERA.items():
        used = [set(c) - {"type"} for c in data["cameras"].values() if c["type"] == kind]
        assert used and used[0] == set(keys), kind


def _imports() -> dict[str, set[str]]:
    """facet module -> the facet modules it imports, at module level or inside functions."""
    modules = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        modules[name] = path
    graph = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
        found = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    base = ".".join(package.split(".")[:len(package.split(".")) - node.level + 1]
                                    + ([node.module] if node.module else []))
                for alias in node.names:
                    target = f"{base}.{alias.name}"
                    found.add(target if target in modules else base)
            elif isinstance(node, ast.Import):
                found.update(a.name for a in node.names)
        graph[name] = {m for m in found if m in modules and m != name}
    return graph


def _layer(module: str) -> int:
    top = module.split(".")[1] if "." in module else "__init__"
    return next(i for i, names in enumerate(LAYERS) if top in names)


def test_the_scene_model_reads_no_files():
    """scene/ is the model only: no module of it imports the readers (facet.formats) or the
    options (facet.options); its classes' ``load`` find their readers through
    facet.scene.readers, which facet.formats fills (and ``import facet`` imports)."""
    graph = _imports()
    above = [(a, b) for a, targets in graph.items() if a.startswith("facet.scene")
             for b in targets if b.startswith(("facet.formats", "facet.options"))]
    assert not above, above
    assert "facet.formats" in graph["facet"]
    out = _run("import facet.scene.mesh as m, facet.scene.readers as r, sys\n"
               "m.Mesh.load('models/default.obj'.replace('models', "
               f"{str(ROOT / 'models')!r}))\n"
               "print('facet.formats.loading' in sys.modules)")
    assert out.strip() == "True"


def test_options_read_no_files_and_the_sequence_keeps_out_of_the_engines():
    """options/ imports nothing of formats/ (an environment file is named by the options,
    read by facet.formats.environment_files.resolve); the renderer and its destinations
    reach no engine's modules (engines are found through facet.render.engine's table and
    answer through its interface)."""
    graph = _imports()
    into_formats = [(a, b) for a, targets in graph.items() if a.startswith("facet.options")
                    for b in targets if b.startswith("facet.formats")]
    assert not into_formats, into_formats
    engines = ("facet.render.raster", "facet.render.trace", "facet.render.path")
    for module in ("facet.render.renderer", "facet.render.destination",
                   "facet.render.sequence"):
        reached = [b for b in graph[module] if b.startswith(engines)]
        assert not reached, (module, reached)


def test_imports_point_down_the_layers():
    upward = [(a, b) for a, targets in _imports().items() for b in targets
              if _layer(b) > _layer(a)]
    assert not upward, upward


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import circles of ``graph`` (its strongly connected components of two or more)."""
    index, low, stack, on_stack, circles = {}, {}, [], set(), []

    def visit(v):  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    sys.setrecursionlimit(10_000)
    for v in graph:
        if v not in index:
            visit(v)
    return circles


def test_no_import_circles():
    assert not _circles(_imports()), _circles(_imports())


def test_the_layer_and_circle_checks_can_fail():
    """The graph is real (the renderer imports the engines' table, the rasterizer its
    forward pass, which imports users' mesh shaders, below the lab), and a circle fed to
    the check is found."""
    graph = _imports()
    assert "facet.render.engine" in graph["facet.render.sequence"]
    assert "facet.render.raster.forward" in graph["facet.render.raster.engine"]
    assert "facet.render.raster.user_shaders" in graph["facet.render.raster.forward"]
    assert not any(m.startswith("facet.lab") for m in graph["facet.render.raster.forward"])
    assert _layer("facet.cli.render") > _layer("facet.lab.shadertoy") > \
        _layer("facet.render.renderer") > _layer("facet.gl")
    fed = {k: set(v) for k, v in graph.items()}
    fed["facet.gl.shaders"].add("facet.render.renderer")  # renderer -> ... -> gl -> renderer
    circles = _circles(fed)
    assert any({"facet.gl.shaders", "facet.render.renderer"} <= set(c) for c in circles)


def test_only_gl_imports_moderngl_and_only_window_imports_glfw():
    owners = {"moderngl": "gl", "glcontext": "gl", "glfw": "window"}
    found = []
    for path in PACKAGE.rglob("*.py"):
        package = path.relative_to(PACKAGE).parts[0]
        for node in ast.walk(ast.parse(path.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            for name in names:
                owner = owners.get(name.split(".")[0])
                if owner is not None and owner != package:
                    found.append((str(path.relative_to(PACKAGE)), name))
    assert not found, found


def test_cli_help_is_light():
    mods = _loaded_after("import facet.cli\nfacet.cli.build_parser()")
    heavy = {"numpy", "trimesh", "moderngl", "PIL", "glfw"}
    assert not heavy & {m.split(".")[0] for m in mods}


def test_renderer_does_load_gl():
    """The check above can fail: the renderer module does pull in moderngl."""
    mods = _loaded_after("import facet.render.renderer")
    assert "moderngl" in mods
