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


DATA = Path(os.environ.get("FACET_WALK_DATA", "/tmp"))  # valid files for the valid calls


def _files() -> dict:
    """A splat PLY and images the valid calls read, written into DATA."""
    from PIL import Image

    from facet.formats.splat_files import write_ply

    DATA.mkdir(parents=True, exist_ok=True)
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
}
PUBLIC["Texture.load"][1]["path"] = FILES["sky"]


def bad_values(hint) -> list:
    """Bad values for a parameter annotated ``hint`` (and the ones any parameter gets)."""
    text = str(hint)
    common = [None, object(), "text", float("nan"), -1, 10**12, [], {}, type]
    numbers = [float("nan"), float("inf"), -float("inf"), -1.0, 0, -10**12, 10**30, 1e308,
               True, "1", np.float32("nan"), complex(1, 1)]
    arrays = [np.zeros(0), np.zeros((0, 3)), np.zeros((2, 2, 2, 2)), np.full(3, np.nan),
              np.zeros((2, 3), complex), np.array([None, 1, 2], object), ["a", "b", "c"],
              [[0, 0], [0]], np.zeros((1, 3)) + np.inf, HUGE_VIEW, np.zeros(3, "U1"), 7.0]
    paths = ["", "\0", "x\0y", 3, b"bytes", ROOT, ROOT / "tests", "/dev/zero",
             "/nonexistent/file.obj"]
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
                named = argument in str(exc) or (  # a file's error names the file
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
    os.chdir(ROOT / "models")
    for item in findings(int(sys.argv[1]) if len(sys.argv) > 1 else 40):
        print(json.dumps(item))
    print("walked", flush=True)
