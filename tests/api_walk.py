"""The public API walked with bad arguments (run by tests/test_api_walk.py in a child
process under a memory limit, so a huge allocation or a hang fails the test, not the
machine).

``PUBLIC`` names each public callable with one valid call (its arguments); the walk replaces
one argument at a time by values hypothesis draws from what the annotation declares (a
number: NaN, inf, negative, zero, huge, text, None; an array: empty, wrong shapes, NaN,
complex, objects, text, a broadcast view of trillions of elements; a path: None, numbers,
NUL bytes, a folder; anything: None, an object, a type). A call may succeed, or raise
facet's ``InputError`` (a ``ValueError``; ``ArgumentError`` also a ``TypeError``) or
another ``FacetError`` whose message names the argument (or, for a path, the file it
names). Anything else, an error that
does not name the argument, or a ``MemoryError``, is a finding: printed as one JSON line
per finding, ``{"call": ..., "argument": ..., "value": ..., "raised": ...}``.

Run: ``python tests/api_walk.py [EXAMPLES]``."""

from __future__ import annotations

import json
import os
import sys
import tempfile
import typing
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "app"))

import facet  # noqa: E402
from facet.errors import FacetError  # noqa: E402

MODEL = str(ROOT / "models" / "default.obj")
HUGE_VIEW = np.broadcast_to(np.float32(0.5), (1 << 20, 1 << 20, 3))  # 3e12 numbers, no memory


def _splats(n: int = 2) -> dict:
    return dict(means=np.zeros((n, 3)), scales=np.ones((n, 3)),
                rotations=np.tile([1.0, 0, 0, 0], (n, 1)), opacities=np.full(n, 0.5),
                sh=np.zeros((n, 1, 3)))


def _faces() -> np.ndarray:
    return np.full((6, 4, 4, 3), 0.5, np.float32)


# The walk's working folder: the valid calls' files, and whatever a bad output path makes.
DATA = Path(os.environ.get("FACET_WALK_DATA") or tempfile.mkdtemp(prefix="facet-walk-"))
os.environ.setdefault("HYPOTHESIS_STORAGE_DIRECTORY", str(DATA / ".hypothesis"))


def _files() -> dict:
    """A splat PLY and images the valid calls read, written into DATA."""
    from PIL import Image

    from facet.formats.splat_files import write_ply

    (DATA / "folder").mkdir(parents=True, exist_ok=True)
    write_ply(facet.Splats(**_splats()), DATA / "cloud.ply")
    Image.fromarray(np.full((8, 16, 3), 128, np.uint8)).save(DATA / "sky.png")
    Image.fromarray(np.full((4, 4, 3), 128, np.uint8)).save(DATA / "face.png")
    return {"ply": str(DATA / "cloud.ply"), "sky": str(DATA / "sky.png"),
            "face": str(DATA / "face.png")}


FILES = _files()
TRIANGLE = dict(positions=np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32),
                faces=np.array([[0, 1, 2]]))

# name: (callable, valid keyword arguments)
PUBLIC: dict[str, tuple] = {
    "Splats": (facet.Splats, _splats()),
    "Splats.from_colors": (facet.Splats.from_colors, {
        **{k: v for k, v in _splats().items() if k != "sh"}, "colors": np.full((2, 3), 0.5)}),
    "Splats.load": (facet.Splats.load, {"path": FILES["ply"]}),
    "Environment": (facet.Environment, {"faces": _faces(), "name": "env",
                                        "equirect": np.full((4, 8, 3), 0.5, np.float32)}),
    "Environment.sky": (facet.Environment.sky, {"zenith": (0.2, 0.4, 0.8),
                                                "horizon": (0.8, 0.9, 1.0),
                                                "ground": (0.3, 0.3, 0.3), "size": 8}),
    "Environment.constant": (facet.Environment.constant, {"color": (1.0, 1.0, 1.0)}),
    "Environment.from_equirect": (facet.Environment.from_equirect,
                                  {"path": FILES["sky"], "size": 8}),
    "Environment.from_faces": (facet.Environment.from_faces,
                               {"paths": [FILES["face"]] * 6}),
    "load": (facet.load, {"path": MODEL, "crease": 30.0, "confine": str(ROOT / "models")}),
    "open_scene": (facet.open_scene, {"path": MODEL, "crease": 30.0}),
    "load_scene": (facet.load_scene, {"path": str(ROOT / "models" / "example.toml"),
                                      "crease": 30.0}),
    "Mesh": (facet.Mesh, dict(TRIANGLE, name="tri")),
    "Mesh.load": (facet.Mesh.load, {"path": MODEL, "crease": 30.0}),
    "Points": (facet.Points, {"positions": np.zeros((4, 3)), "colors": np.ones((4, 3)),
                              "size": 2.0}),
    "Lines": (facet.Lines, {"positions": np.zeros((4, 3)), "width": 2.0}),
    "Camera.look_at": (facet.Camera.look_at, {"eye": (0, 0, 5), "target": (0, 0, 0),
                                              "up": (0, 1, 0), "fov_y": 45.0}),
    "Texture": (facet.Texture, {"pixels": np.zeros((4, 4, 3), np.uint8)}),
    "Texture.load": (facet.Texture.load, {"path": None}),  # (path filled below)
    "Camera.frame": (facet.Camera.frame, {"bounds": np.array([[0, 0, 0], [1, 1, 1.0]]),
                                          "direction": (0, 0, -1), "up": (0, 1, 0),
                                          "fov_y": 40.0, "aspect": 1.5, "margin": 1.1}),
    "Camera.from_intrinsics": (facet.Camera.from_intrinsics, {
        "fx": 100.0, "fy": 100.0, "cx": 32.0, "cy": 24.0, "width": 64, "height": 48,
        "near": 0.1, "far": 10.0}),
    "Material": (facet.Material, {"color": (1.0, 0.5, 0.2), "kd": 0.8, "ks": 0.3,
                                  "shininess": 32.0, "opacity": 1.0}),
    "PbrMaterial": (facet.PbrMaterial, {"base_color": (1.0, 0.5, 0.2, 1.0), "metallic": 0.0,
                                        "roughness": 0.5, "ior": 1.5,
                                        "alpha_mode": "OPAQUE"}),
    "PointLight": (facet.PointLight, {"position": (0, 1, 0), "color": (1, 1, 1),
                                      "intensity": 1.0}),
    "DirectionalLight": (facet.DirectionalLight, {"direction": (0, -1, 0), "intensity": 1.0}),
    "SpotLight": (facet.SpotLight, {"position": (0, 1, 0), "direction": (0, -1, 0)}),
    "AreaLight": (facet.AreaLight, {"position": (0, 1, 0), "normal": (0, -1, 0),
                                    "size": (1.0, 1.0), "intensity": 1.0}),
    "Scene": (facet.Scene, {"background": (0, 0, 0, 1)}),
    "Scene.add": (lambda mesh, transform=None, name="": facet.Scene().add(
        mesh, transform=transform, name=name),
        {"mesh": facet.Mesh(**TRIANGLE), "transform": np.eye(4), "name": "tri"}),
    "Scene.add_light": (lambda light: facet.Scene().add_light(light),
                        {"light": facet.PointLight()}),
    "Intrinsics": (facet.Intrinsics, {"fx": 100.0, "fy": 100.0, "cx": 32.0, "cy": 24.0,
                                      "width": 64, "height": 48}),
    "TextureSlot": (facet.TextureSlot, {"texture": facet.Texture(np.zeros((2, 2, 3), np.uint8)),
                                        "texcoord": 0,
                                        "transform": np.eye(3), "wrap": ("repeat", "clamp"),
                                        "filter": ("linear", "nearest")}),
    "primitives.sphere": (facet.primitives.sphere, {"radius": 1.0, "segments": 16,
                                                    "rings": 8}),
    "primitives.cube": (facet.primitives.cube, {"size": 1.0}),
    "primitives.cone": (facet.primitives.cone, {"radius": 0.5, "height": 1.0,
                                                "segments": 16}),
    "primitives.cylinder": (facet.primitives.cylinder, {"radius": 0.5, "height": 1.0,
                                                        "segments": 16}),
    "primitives.disk": (facet.primitives.disk, {"radius": 1.0, "segments": 16}),
    "primitives.plane": (facet.primitives.plane, {"size": 1.0}),
    "primitives.torus": (facet.primitives.torus, {"major_radius": 1.0, "minor_radius": 0.25,
                                                  "segments": 16, "rings": 8}),
    "shapes.Sphere": (facet.shapes.Sphere, {"radius": 1.0}),
    "shapes.Box": (facet.shapes.Box, {"size": 1.0}),
    "shapes.Cone": (facet.shapes.Cone, {"radius": 0.5, "height": 1.0}),
    "shapes.Cylinder": (facet.shapes.Cylinder, {"radius": 0.5, "height": 1.0}),
    "shapes.Disk": (facet.shapes.Disk, {"radius": 1.0}),
    "shapes.Plane": (facet.shapes.Plane, {"size": 2.0}),
    "transforms.translate": (facet.transforms.translate, {"offset": (1, 2, 3)}),
    "transforms.scale": (facet.transforms.scale, {"factor": 2.0}),
    "transforms.rotate": (facet.transforms.rotate, {"axis": (0, 1, 0), "degrees": 30.0}),
    "transforms.rotate_x": (facet.transforms.rotate_x, {"degrees": 30.0}),
    "transforms.look_at": (facet.transforms.look_at, {"eye": (0, 0, 5), "target": (0, 0, 0),
                                                      "up": (0, 1, 0)}),
    "transforms.perspective": (facet.transforms.perspective, {
        "fov_y": 45.0, "aspect": 1.5, "near": 0.1, "far": 10.0}),
    "transforms.orthographic": (facet.transforms.orthographic, {
        "left": -1.0, "right": 1.0, "bottom": -1.0, "top": 1.0, "near": 0.1, "far": 10.0}),
    "transforms.normal_matrix": (facet.transforms.normal_matrix, {"m": np.eye(4)}),
    "transforms.transform_points": (facet.transforms.transform_points,
                                    {"m": np.eye(4), "points": np.zeros((4, 3))}),
    "Scene.at": (lambda time=0.0, animation=None: facet.Scene().at(time, animation),
                 {"time": 1.0}),
    "Camera.orbit": (lambda center, axis, degrees: facet.Camera.look_at(
        (0, 0, 5), (0, 0, 0)).orbit(center, axis, degrees),
        {"center": (0, 0, 0), "axis": (0, 1, 0), "degrees": 30.0}),
    "Camera.projection": (lambda width, height: facet.Camera.look_at(
        (0, 0, 5), (0, 0, 0)).projection(width, height), {"width": 64, "height": 48}),
    "Mesh.colored_by": (lambda values, colormap="viridis", limits=None: facet.Mesh(
        **TRIANGLE).colored_by(values, colormap, limits),
        {"values": np.arange(3.0), "colormap": "viridis", "limits": (0.0, 2.0)}),
    "Points.sized": (lambda size=None, radius=None: facet.Points(np.zeros((2, 3))).sized(
        size, radius), {"size": 3.0}),
    "Lines.widened": (lambda width: facet.Lines(np.zeros((2, 3))).widened(width),
                      {"width": 3.0}),
    "RenderOptions.build": (lambda **o: facet.RenderOptions.build(o),
                            {"size": (32, 24), "spp": 4, "engine": "path",
                             "background": (0, 0, 0, 1), "time": 1.0}),
}
PUBLIC["Texture.load"][1]["path"] = FILES["sky"]


def _shader() -> str:
    path = DATA / "toy.frag"
    path.write_text("uniform float u_gain;\n"
                    "void mainImage(out vec4 c, in vec2 p) { c = vec4(u_gain); }\n")
    return str(path)


def _manifest() -> str:
    (DATA / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    path = DATA / "jobs.jsonl"
    path.write_text('{"model": "tri.obj", "views": 1, "size": [8, 8], "outputs": "color"}\n')
    return str(path)


def _gl_calls() -> dict:
    """The renderer's calls (one renderer, made once: a GL context in this process)."""
    renderer = facet.Renderer(16, 12)
    scene = facet.Scene()
    scene.add(facet.Mesh(**TRIANGLE))
    camera = facet.Camera.look_at((0.3, 0.3, 3), (0.3, 0.3, 0))

    toy = facet.ShaderToy(_shader(), size=(16, 12))

    def render(scene, camera, size, spp, engine, background, outputs, environment, time):
        return renderer.render(scene, camera, size=size, spp=spp, engine=engine,
                               background=background, outputs=outputs,
                               environment=environment, time=time)

    return {
        "Renderer": (lambda width, height, msaa: facet.Renderer(width, height, msaa).close(),
                     {"width": 16, "height": 12, "msaa": 4}),
        "Renderer.render": (render, {"scene": scene, "camera": camera, "size": (16, 12),
                                     "spp": 1, "engine": "raster",
                                     "background": (0, 0, 0, 1), "outputs": ("color",),
                                     "environment": "sky", "time": 0.0}),
        "Renderer.samples": (lambda scene, camera, spp: renderer.samples(scene, camera,
                                                                        spp=spp),
                             {"scene": scene, "camera": camera, "spp": 4}),
        "ShaderToy": (lambda image, size: facet.ShaderToy(image, size=size).close(),
                      {"image": _shader(), "size": (16, 12)}),
        "ShaderToy.render": (lambda time, fps, mouse: toy.render(time, fps=fps, mouse=mouse),
                             {"time": 0.5, "fps": 30.0, "mouse": (0, 0, 0, 0)}),
        "ShaderToy.set_uniform": (lambda name, value: toy.set_uniform(name, value),
                                  {"name": "u_gain", "value": 0.5}),
        "ShaderToy.resize": (lambda width, height: toy.resize(width, height),
                             {"width": 16, "height": 12}),
        "batch.render_dataset": (lambda manifest, out, workers: facet.batch.render_dataset(
            manifest, out, workers=workers), {"manifest": _manifest(), "out": str(DATA / "ds"),
                                              "workers": 1}),
        "Frame.save": (lambda path: renderer.render(scene, camera, outputs=("color",)).save(
            path), {"path": str(DATA / "frame.png")}),
    }


PUBLIC.update(_gl_calls())


# Arguments an error names by another name: the Renderer's width and height are its size
# option, checked by the one options parser, which names the option.
ALIASES = {("Renderer", "width"): "size", ("Renderer", "height"): "size"}


def bad_values(hint) -> list:
    """Bad values for a parameter annotated ``hint`` (and the ones any parameter gets)."""
    text = str(hint)
    common = [None, object(), "text", float("nan"), -1, 10**12, [], {}, type]
    numbers = [float("nan"), float("inf"), -float("inf"), -1.0, 0, -10**12, 10**30, 1e308,
               True, "1", np.float32("nan"), complex(1, 1)]
    arrays = [np.zeros(0), np.zeros((0, 3)), np.zeros((2, 2, 2, 2)), np.full(3, np.nan),
              np.zeros((2, 3), complex), np.array([None, 1, 2], object), ["a", "b", "c"],
              [[0, 0], [0]], np.zeros((1, 3)) + np.inf, HUGE_VIEW, np.zeros(3, "U1"), 7.0]
    paths = ["", "\0", "x\0y", 3, b"bytes", DATA, DATA / "folder", "/dev/zero",
             "/nonexistent/file.obj"]  # (relative names land in DATA, the working folder:
    # an output argument given one writes there, never into the checkout)
    out = list(common)
    if "Real" in text or "float" in text or "int" in text or "Integral" in text:
        out += numbers
    if "ArrayLike" in text or "Array(" in text or "object" in text or "ndarray" in text:
        out += arrays
    if "PathLike" in text or "PathArg" in text or "str" in text:
        out += paths
    if "Sequence" in text:
        out += ["abcdef", [None] * 6, [3] * 6, ["a"] * 5]
    return out


def _hints(fn) -> dict:
    target = fn.__init__ if isinstance(fn, type) else fn
    try:
        return typing.get_type_hints(target, include_extras=True)
    except Exception:
        return {}


def findings(examples: int) -> list[dict]:
    """Every finding of the walk (module docstring), hypothesis drawing ``examples`` bad
    values for each argument."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    found: list[dict] = []

    def walker(name, fn, valid, argument, values):
        @settings(max_examples=examples, database=None, derandomize=True, deadline=None,
                  suppress_health_check=list(HealthCheck))
        @given(st.sampled_from(values))
        def walk(value):
            try:
                fn(**{**valid, argument: value})
            except FacetError as exc:
                said = ALIASES.get((name, argument), argument)
                named = said in str(exc) or (  # a file's error names the file
                    isinstance(value, (str, Path)) and str(value) and str(value) in str(exc))
                if not named:
                    found.append(_finding(name, argument, value, exc, "not named"))
            except Exception as exc:  # noqa: BLE001 - each is a finding
                found.append(_finding(name, argument, value, exc, "escaped"))
        return walk

    for name, (fn, valid) in PUBLIC.items():
        hints = _hints(fn)
        fn(**valid)  # the valid call works (else the table is wrong)
        for argument in valid:
            walker(name, fn, valid, argument, bad_values(hints.get(argument, object)))()
    return found


def _finding(name, argument, value, exc, why) -> dict:
    return {"call": name, "argument": argument, "value": repr(value)[:80],
            "raised": f"{type(exc).__name__}: {str(exc)[:200]}", "why": why}


if __name__ == "__main__":
    import warnings

    warnings.simplefilter("ignore")
    os.chdir(DATA)  # what a bad output path writes lands here
    for item in findings(int(sys.argv[1]) if len(sys.argv) > 1 else 40):
        print(json.dumps(item))
    print("walked", flush=True)
