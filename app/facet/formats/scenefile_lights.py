"""Scene files: the [[lights]] array and the [cameras.NAME] tables (facet.formats.scenefile
reads the rest). Each table maps to one constructor: the lights of facet.scene.light and
``Camera.look_at`` / orthographic / ``Camera.from_intrinsics``."""

from __future__ import annotations

import numpy as np

from ..errors import FacetError, SceneError
from ..geometry import transforms as T
from ..geometry.camera import Camera
from ..geometry.framing import depth_range
from ..scene.light import AreaLight, DirectionalLight, PointLight, SpotLight
from ..scene.scene import Scene
from .validate import Reader

LIGHT = {"ambient": ("color", "intensity"),
         "directional": ("direction", "color", "intensity"),
         "point": ("position", "color", "intensity", "attenuation"),
         "spot": ("position", "direction", "color", "intensity", "attenuation",
                  "inner_angle", "outer_angle"),
         "area": ("position", "normal", "size", "color", "intensity", "attenuation")}
CAMERA = {"perspective": ("eye", "target", "up", "fov", "near", "far", "aperture",
                          "focus_distance"),
          "orthographic": ("eye", "target", "up", "height", "near", "far"),
          "intrinsics": ("fx", "fy", "cx", "cy", "width", "height", "pose", "near", "far")}

def read_lights(r: Reader, scene: Scene, items) -> None:
    """The [[lights]] array into ``scene`` (the ambient entry sets ``scene.ambient``)."""
    if not isinstance(items, list):
        r.fail("lights", "expected an array of tables ([[lights]])")
    ambient_seen = False
    for i, t in enumerate(items):
        where = f"lights[{i}]"
        if not isinstance(t, dict) or "type" not in t:
            r.fail(where, f"expected a table with type = {' | '.join(LIGHT)}")
        kind = r.choice(t["type"], f"{where}.type", tuple(LIGHT))
        r.table(t, where, ("type", *LIGHT[kind]))
        kw = {}
        for key in LIGHT[kind]:
            if key not in t:
                continue
            at = f"{where}.{key}"
            if key == "color":
                kw[key] = r.color(t[key], at)
            elif key in ("direction", "position", "attenuation", "normal"):
                kw[key] = r.vector(t[key], at)
            elif key == "size":
                kw[key] = tuple(r.vector(t[key], at, 2))
            else:
                kw[key] = r.number(t[key], at, minimum=0)
        try:
            if kind == "ambient":
                if ambient_seen:
                    r.fail(where, "only one ambient light per scene")
                ambient_seen = True
                scene.ambient = np.clip(kw.get("color", np.ones(3)) *
                                        kw.get("intensity", 1.0), 0, 1)
                continue
            cls = {"directional": DirectionalLight, "point": PointLight,
                   "spot": SpotLight, "area": AreaLight}[kind]
            scene.add_light(cls(**kw))
        except SceneError:
            raise
        except FacetError as exc:
            r.fail(where, str(exc))

def read_camera(r: Reader, t, where: str, scene: Scene) -> Camera:
    """One [cameras.NAME] table (look-at cameras fit near/far to the scene's bounds)."""
    if not isinstance(t, dict) or "type" not in t:
        r.fail(where, f"expected a table with type = {' | '.join(CAMERA)}")
    kind = r.choice(t["type"], f"{where}.type", tuple(CAMERA))
    r.table(t, where, ("type", *CAMERA[kind]))
    near = r.number(t["near"], f"{where}.near", above=0) if "near" in t else None
    far = r.number(t["far"], f"{where}.far", above=0) if "far" in t else None
    try:
        if kind == "intrinsics":
            for key in ("fx", "fy", "cx", "cy", "width", "height"):
                if key not in t:
                    r.fail(where, f"an intrinsics camera needs {key}")
            pose = r.matrix(t["pose"], f"{where}.pose") if "pose" in t else None
            return Camera.from_intrinsics(
                r.number(t["fx"], f"{where}.fx", above=0),
                r.number(t["fy"], f"{where}.fy", above=0),
                r.number(t["cx"], f"{where}.cx"), r.number(t["cy"], f"{where}.cy"),
                r.integer(t["width"], f"{where}.width"),
                r.integer(t["height"], f"{where}.height"), pose,
                near=near or 0.01, far=far or 100.0)
        if "eye" not in t:
            r.fail(where, f"a {kind} camera needs eye (and usually target)")
        eye = r.vector(t["eye"], f"{where}.eye")
        target = r.vector(t["target"], f"{where}.target") if "target" in t else \
            scene.bounds.mean(axis=0)
        up = r.vector(t["up"], f"{where}.up") if "up" in t else np.array([0.0, 1.0, 0.0])
        view = T.look_at(eye, target, up)
        fitted = depth_range(view, scene.bounds) if scene.objects else (0.1, 100.0)
        near, far = near or fitted[0], far or fitted[1]
        if kind == "orthographic":
            height = r.number(t.get("height", 0), f"{where}.height", above=0)
            return Camera(view, ortho_height=height, near=near, far=far)
        fov = r.number(t.get("fov", 40.0), f"{where}.fov", above=0)
        cam = Camera(view, fov_y=fov, near=near, far=far)
        if "aperture" in t:
            cam.aperture = r.number(t["aperture"], f"{where}.aperture", minimum=0)
        if "focus_distance" in t:
            cam.focus_distance = r.number(t["focus_distance"], f"{where}.focus_distance",
                                          above=0)
        from ..geometry.lens import check_lens

        check_lens(cam)
        return cam
    except SceneError:
        raise
    except FacetError as exc:
        message = str(exc)
        if "up is parallel" in message:
            message = "the camera looks along its up vector; choose another 'up'"
        r.fail(where, message)
