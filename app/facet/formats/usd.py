"""OpenUSD stages -> facet parts, cameras and lights (no GL), through pxr (the ``usd``
extra): what ``facet render stage.usda`` and ``facet.load`` read.

The stage is composed as USD defines it (facet.formats.usd_stage: every layer through the
guard, variants, payloads). Prims are visited as USD's default predicate and instance
proxies give them: ``active``, defined, not abstract; invisible ones (``ComputeVisibility``;
those whose visibility is time-sampled are kept and hidden while invisible by the time rig)
and those whose ``purpose`` is not wanted (default and render drawn; proxy and guide on
request) are left out. A native instance's prototype geometry is made once and placed by
each instance (facet's instancing: the same Mesh object), as are a PointInstancer's
prototypes at each of its instances.

Transforms: ``UsdGeom.XformCache`` at the time code (USD's row vectors, transposed to
facet's column vectors); the geometry stays in the file's coordinates. ``upAxis`` is
given back for framing and turntables (the scene's ``up`` option). Time: the stage is
read at its start time code; time-sampled transforms, cameras and points move through
``--time`` / ``Scene.at`` as glTF animations do (facet.formats.usd_time).

Lights (UsdLux): emission L = intensity x 2^exposure x colour (x the blackbody colour of
colorTemperature when enabled); ``normalize`` divides an area light's by its area and
makes a distant light's intensity its illuminance. facet's light of intensity I gives
irradiance pi I (facet.scene.pbr), so: DistantLight -> DirectionalLight along its -z,
I = E / pi with E = L x (the solid angle of its angular diameter ``angle``);
SphereLight -> facet's SphereLight of its radius, I = L r^2 (the irradiance far from a
sphere of radiance L; a point light where treatAsPoint or radius 0; the path tracer
samples it as an emitting sphere, the others by points of it); RectLight -> AreaLight
facing its -z, I = L w h / pi; DiskLight -> AreaLight of the disk's area; DomeLight -> the
environment (its texture times L, or a constant L).
Cameras (UsdGeom.Camera): focal length and vertical aperture give the field of view (the
window fitted to the picture's height), the aperture offsets a shifted lens
(``Camera.shift``), clipping range the near and far planes, an orthographic projection
its height, f-stop and focus distance a thin lens. Each said-once approximation is one warning line.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..errors import FacetError, FacetWarning, MeshError
from ..scene.light import AreaLight, DirectionalLight, PointLight, SphereLight
from .usd_geometry import (
    StageSettings,
    curve_arguments,
    display_color,
    gprim,
    mesh_arguments,
    points_arguments,
)
from .usd_geometry import matrix as _matrix
from .usd_shading import Shading
from .usd_stage import open_stage
from .usd_time import time_rig, visibility_codes

GPRIMS = ("Cube", "Sphere", "Cylinder", "Cone", "Capsule", "Plane")
LIGHTS = ("DistantLight", "SphereLight", "RectLight", "DiskLight", "DomeLight",
          "DomeLight_1", "CylinderLight")
DRAWN_PURPOSES = ("default", "render")


class UsdOptions:
    """What to read of a stage: ``variants`` {set: name}, ``payloads``, ``purposes``
    (default and render; proxy, guide on request)."""

    def __init__(self, variants=None, payloads: bool = True, purposes=DRAWN_PURPOSES,
                 subdivide: int = 0):
        self.variants = dict(variants or {})
        self.payloads = bool(payloads)
        self.purposes = tuple(purposes)
        self.subdivide = int(subdivide)  # refinement levels of subdivision surfaces


def read_usd(path: Path, finish, options: UsdOptions | None = None):
    """``(parts, cameras, lights, rig)`` of a stage, as facet.formats.loading.load_file
    returns them (lights may hold the environment: a facet Environment)."""

    from .usd_stage import quiet_pxr

    options = options or UsdOptions()
    stage, notes = open_stage(path, options.variants, options.payloads)
    with quiet_pxr() as said:  # (bad relationship targets are said while traversing)
        found = _traverse(stage, path, options, finish, notes)
    notes += [line.strip() for line in said
              if line.strip() and "instantiating stage on stage" not in line]
    for note in dict.fromkeys(notes):
        warnings.warn(note if note.startswith(path.name) else f"{path.name}: {note}",
                      FacetWarning, stacklevel=4)
    return found


def _traverse(stage, path: Path, options: UsdOptions, finish, notes: list):
    """The stage's parts, cameras and lights (``read_usd``'s, before its warnings)."""
    from pxr import Usd, UsdGeom

    # At the start time code (an attribute with only time samples has no default value;
    # one without samples reads its default there): what moves, the time rig moves from
    # there (facet.formats.usd_time).
    time = Usd.TimeCode(stage.GetStartTimeCode())
    cache = UsdGeom.XformCache(time)
    shading = Shading(stage, time, notes, options.subdivide)
    parts: list = []
    placed: list = []  # per part: (its prim, 4x4 geometry -> prim) for the time rig
    cameras: dict = {}
    camera_prims: dict = {}
    lights: list = []
    made: dict[str, list] = {}  # prototype (or prim) path -> its [(name, args, local)]
    said: set = set()  # what is said once a stage
    predicate = Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)
    it = iter(Usd.PrimRange(stage.GetPseudoRoot(), predicate))
    for prim in it:
        if not prim.IsA(UsdGeom.Imageable):
            continue
        image = UsdGeom.Imageable(prim)
        if image.ComputeVisibility(time) == UsdGeom.Tokens.invisible \
                and not visibility_codes(prim):  # (one that shows later: the time rig's)
            it.PruneChildren()
            continue
        purpose = image.ComputePurpose()
        if purpose not in options.purposes:
            it.PruneChildren()
            continue
        kind = prim.GetTypeName()
        world = _matrix(cache.GetLocalToWorldTransform(prim))
        where = str(prim.GetPath())
        if kind == "Camera":
            camera = usd_camera(prim, time, world, notes)
            if camera is not None:
                cameras[prim.GetName()] = camera
                camera_prims[prim.GetName()] = (prim, camera)
            continue
        if kind in LIGHTS:
            light = usd_light(prim, time, world, notes)
            if light is not None:
                lights.append(light)
            continue
        if kind in ("SkelRoot", "Skeleton") and "skel" not in said:
            said.add("skel")  # (UsdSkel: one line for the stage)
            notes.append(f"{where}: UsdSkel skinning is not applied; skinned meshes are "
                         "drawn as authored (their bind pose), the skeleton's animation "
                         "not played")
        if kind == "PointInstancer":
            before = len(parts)
            _instancer(prim, time, world, made, shading, finish, parts, notes, path)
            placed += [(None, m, None) for _, _, m in parts[before:]]
            it.PruneChildren()
            continue
        if not np.isfinite(world).all() or abs(np.linalg.det(world[:3, :3])) < 1e-12:
            notes.append(f"{where}: its transform is singular (a zero scale) or not finite; "
                         "left out")
            it.PruneChildren()
            continue
        for name, args, local in _geometry(prim, time, made, shading, finish, notes, path,
                                           where):
            parts.append((name, args, world @ local))
            placed.append((prim, local, args.get("deform")))
    if not parts:
        empty = [str(p.GetPath()) for p in stage.Traverse() if p.IsA(UsdGeom.Gprim)]
        raise MeshError(f"{path}: the stage draws nothing: " + (
            f"{', '.join(empty[:3])} hold{'s' if len(empty) == 1 else ''} no faces, points "
            "or shapes" if empty else "it has no meshes, gprims, points or curves"))
    rig = time_rig(stage, placed, camera_prims, notes)
    up = str(UsdGeom.GetStageUpAxis(stage))
    if up not in ("Y", "Z"):
        notes.append(f"upAxis {up!r} is neither Y nor Z; Y is used")
    lights.append(StageSettings("z" if up == "Z" else "y"))
    return parts, cameras, lights, rig


def _geometry(prim, time, made, shading, finish, notes, path, where) -> list:
    """[(name, args, 4x4 geometry -> prim)] of one prim (made once per prototype)."""
    key = str(prim.GetPrimInPrototype().GetPath()) if prim.IsInstanceProxy() else where
    if key not in made:
        made[key] = _make(prim, time, shading, finish, notes, path, where)
    return made[key]


def _make(prim, time, shading, finish, notes, path, where) -> list:
    from pxr import UsdGeom

    kind = prim.GetTypeName()
    rgb, alpha = display_color(prim, time)
    double = bool(UsdGeom.Gprim(prim).GetDoubleSidedAttr().Get(time)) \
        if prim.IsA(UsdGeom.Gprim) else False
    if kind == "Mesh":
        material, uv_name = shading.material_of(prim)
        args = mesh_arguments(prim, time, uv_name, notes, where, shading.subdivide)
        if args is None:
            return []
        constant = args.pop("constant_color", None)
        scheme = args.pop("subdivision")
        moving = _moving_points(prim, args.pop("point_index", None), args["positions"])
        if moving is not None:
            args["deform"] = moving
        if scheme not in ("none", "bilinear") and _has_creases(prim, time):
            notes.append(f"{where}: subdivision creases and corners are not honoured")
        if material is None:
            c = constant or (rgb, alpha)
            material = shading.fallback(c[0], c[1], double)
        elif double and not material.double_sided:
            material = _copy(material, double_sided=True)
        args["material"] = material
        args["name"] = prim.GetName()
        return [(prim.GetName(), finish(args, where), np.eye(4))]
    if kind in GPRIMS:
        shape = gprim(prim, time)
        if shape is None:
            return []
        material, _ = shading.material_of(prim)
        material = material or shading.fallback(rgb, alpha, double)
        shape_kind, params, turn = shape
        args = {"kind": "shape", "shape": shape_kind, "params": params,
                "material": material, "name": prim.GetName(), "path": str(path)}
        return [(prim.GetName(), args, turn)]
    if kind == "Points":
        args = points_arguments(prim, time, notes)
        return [] if args is None else [(prim.GetName(), _sprite(args, finish, where),
                                         np.eye(4))]
    if kind == "BasisCurves":
        args = curve_arguments(prim, time, notes)
        return [] if args is None else [(prim.GetName(), _sprite(args, finish, where),
                                         np.eye(4))]
    if prim.IsA(UsdGeom.Gprim):
        notes.append(f"{where}: a {kind} prim is not drawn (facet reads Mesh, Points, "
                     "BasisCurves and the gprims)")
    return []


def _sprite(args: dict, finish, where: str) -> dict:
    rgb = args.pop("rgb", None)
    width = args.pop("width", None)
    if width is not None and args["kind"] == "points":
        args["radius"] = width / 2.0
    if rgb is not None and "colors" not in args:
        from ..srgb import linear_to_srgb

        c = np.concatenate([linear_to_srgb(np.clip(np.asarray(rgb, float), 0, 1)), [1.0]])
        args["colors"] = np.tile(c, (len(args["positions"]), 1)).astype(np.float32)
    return finish(args, where)


def _moving_points(prim, point_index, positions):
    """Time-sampled points as morph targets (a Deformation, one target per time code, in
    the order of the mesh's vertices: ``point_index`` says which point each came from), or
    None when the points do not move; the time rig weighs them (facet.formats.usd_time)."""
    from pxr import Usd, UsdGeom

    from ..scene.animation import Deformation

    attr = UsdGeom.PointBased(prim).GetPointsAttr()
    codes = attr.GetTimeSamples()
    if point_index is None or len(codes) < 2:
        return None
    rest = np.asarray(positions, np.float64)
    targets = []
    for code in codes:
        pts = np.asarray(attr.Get(Usd.TimeCode(code)), np.float64).reshape(-1, 3)
        if pts.shape[0] <= int(np.max(point_index)):
            return None  # (a sample of another point count: drawn at rest)
        targets.append(pts[point_index] - rest)
    return Deformation(targets={"positions": np.asarray(targets, np.float32)})


def _has_creases(prim, time) -> bool:
    from pxr import UsdGeom

    mesh = UsdGeom.Mesh(prim)
    for attr in (mesh.GetCreaseIndicesAttr(), mesh.GetCornerIndicesAttr()):
        value = attr.Get(time)
        if value is not None and len(value):
            return True
    return False


def _copy(material, **changes):
    from dataclasses import replace

    return replace(material, **changes)


def _instancer(prim, time, world, made, shading, finish, parts, notes, path) -> None:
    """A PointInstancer: each prototype's geometry made once, placed at each instance."""
    from pxr import Usd, UsdGeom

    inst = UsdGeom.PointInstancer(prim)
    xforms = inst.ComputeInstanceTransformsAtTime(time, time)
    indices = inst.GetProtoIndicesAttr().Get(time)
    targets = inst.GetPrototypesRel().GetTargets()
    if xforms is None or indices is None:
        return
    stage = prim.GetStage()
    cache = UsdGeom.XformCache(time)
    protos = []
    for target in targets:
        root = stage.GetPrimAtPath(target)
        geo = []
        if root:
            root_world = _matrix(cache.GetLocalToWorldTransform(root))
            to_root = np.linalg.inv(root_world)
            for sub in Usd.PrimRange(root, Usd.TraverseInstanceProxies(
                    Usd.PrimDefaultPredicate)):
                where = str(sub.GetPath())
                for name, args, local in _geometry(sub, time, made, shading, finish, notes,
                                                   path, where):
                    sub_world = _matrix(cache.GetLocalToWorldTransform(sub))
                    geo.append((name, args, to_root @ sub_world @ local))
        protos.append(geo)
    for k, (proto, m) in enumerate(zip(indices, xforms, strict=False)):
        if not 0 <= proto < len(protos):
            continue
        place = world @ _matrix(m)
        for name, args, local in protos[proto]:
            parts.append((f"{name}[{k}]", args, place @ local))


# -- cameras and lights ----------------------------------------------------------------------
def usd_camera(prim, time, world: np.ndarray, notes: list):
    """A UsdGeom.Camera as a facet Camera (module docstring), or None (said) when its
    aperture or focal length is not positive."""
    from pxr import UsdGeom

    from ..geometry.camera import Camera

    cam = UsdGeom.Camera(prim).GetCamera(time)
    m = world.copy()
    scale = np.linalg.norm(m[:3, :3], axis=0)
    m[:3, :3] = m[:3, :3] / np.where(scale > 0, scale, 1)  # a camera looks; it has no size
    view = np.linalg.inv(m)
    near, far = cam.clippingRange.min, cam.clippingRange.max
    near = max(float(near), 1e-4)
    far = max(float(far), near * 10)
    ortho = str(cam.projection).endswith("Orthographic")
    if not (cam.verticalAperture > 0 and (ortho or cam.focalLength > 0)):
        notes.append(f"{prim.GetPath()}: a camera of vertical aperture "
                     f"{cam.verticalAperture:g} and focal length {cam.focalLength:g} sees "
                     "nothing; left out")
        return None
    # The window is fitted to the picture's height (the vertical aperture; the horizontal
    # follows the picture's aspect), centred at the aperture offsets: a shifted lens.
    shift = (float(cam.horizontalApertureOffset) / cam.verticalAperture,
             float(cam.verticalApertureOffset) / cam.verticalAperture)
    if ortho:  # apertures are in tenths of a scene unit
        camera = Camera(view, ortho_height=float(cam.verticalAperture) / 10.0, near=near,
                        far=far)
    else:
        fov_y = float(np.degrees(2 * np.arctan(cam.verticalAperture / (2 * cam.focalLength))))
        camera = Camera(view, fov_y=fov_y, near=near, far=far)
        if cam.fStop and cam.fStop > 0 and cam.focusDistance > 0:
            # lens diameter = focal length / f-number (focal length in tenths of a unit)
            camera.aperture = float(cam.focalLength / 10.0 / cam.fStop)
            camera.focus_distance = float(cam.focusDistance)
    camera.shift = shift
    return camera


def _emission(light, time, prim) -> np.ndarray:
    """L = intensity x 2^exposure x colour (x the colour temperature's), linear RGB."""
    intensity = float(light.GetIntensityAttr().Get(time) or 0.0)
    exposure = float(light.GetExposureAttr().Get(time) or 0.0)
    colour = np.array(light.GetColorAttr().Get(time) or (1, 1, 1), float)
    if light.GetEnableColorTemperatureAttr().Get(time):
        from pxr import UsdLux

        kelvin = float(light.GetColorTemperatureAttr().Get(time) or 6500.0)
        colour = colour * np.array(UsdLux.BlackbodyTemperatureAsRgb(kelvin), float)
    return intensity * 2.0 ** exposure * colour


def usd_light(prim, time, world: np.ndarray, notes: list):
    """A UsdLux light as a facet light or environment (module docstring), or None."""
    from pxr import UsdLux

    kind = prim.GetTypeName()
    light = UsdLux.LightAPI(prim)
    emission = _emission(light, time, prim)
    scale = float(emission.max(initial=0.0))
    colour = emission / scale if scale > 0 else np.ones(3)
    normalize = bool(light.GetNormalizeAttr().Get(time))
    origin = world[:3, 3]
    minus_z = world[:3, :3] @ np.array([0.0, 0.0, -1.0])
    axes = np.linalg.norm(world[:3, :3], axis=0)
    where = str(prim.GetPath())
    if kind == "DistantLight":
        angle = float(UsdLux.DistantLight(prim).GetAngleAttr().Get(time) or 0.0)
        half = np.radians(angle) / 2.0
        solid = 2 * np.pi * (1 - np.cos(half))
        irradiance = scale if normalize or solid <= 0 else scale * solid
        return DirectionalLight(direction=minus_z, color=colour,
                                intensity=irradiance / np.pi)
    if kind == "SphereLight":
        r = float(UsdLux.SphereLight(prim).GetRadiusAttr().Get(time) or 0.0) * axes.mean()
        radiance = scale / (4 * np.pi * r * r) if normalize and r > 0 else scale
        if r <= 0:  # (a point: its intensity as a point light's, I = L / pi)
            return PointLight(origin, colour, radiance / np.pi, (0.0, 0.0, 1.0))
        if UsdLux.SphereLight(prim).GetTreatAsPointAttr().Get(time):
            return PointLight(origin, colour, radiance * r * r, (0.0, 0.0, 1.0))
        return SphereLight(position=origin, color=colour, intensity=radiance * r * r,
                           attenuation=(0.0, 0.0, 1.0), radius=r)
    if kind in ("RectLight", "DiskLight"):
        if kind == "RectLight":
            rect = UsdLux.RectLight(prim)
            w = float(rect.GetWidthAttr().Get(time)) * axes[0]
            h = float(rect.GetHeightAttr().Get(time)) * axes[1]
            asset = rect.GetTextureFileAttr().Get(time)
            if asset:
                colour = colour * _mean_colour(asset, where, notes)
        else:
            r = float(UsdLux.DiskLight(prim).GetRadiusAttr().Get(time)) * axes[:2].mean()
            w = h = float(np.sqrt(np.pi) * r)  # a square of the disk's area
        area = w * h
        radiance = scale / area if normalize and area > 0 else scale
        return AreaLight(position=origin, normal=minus_z, size=(max(w, 1e-6), max(h, 1e-6)),
                         color=colour, intensity=radiance * area / np.pi,
                         attenuation=(0.0, 0.0, 1.0))
    if kind in ("DomeLight", "DomeLight_1"):
        from pxr import UsdGeom

        return _dome(prim, time, world, emission, notes, where,
                     str(UsdGeom.GetStageUpAxis(prim.GetStage())))
    notes.append(f"{where}: a {kind} is not drawn (facet reads distant, sphere, rect, disk "
                 "and dome lights)")
    return None


def _mean_colour(asset, where: str, notes: list) -> np.ndarray:
    """The mean linear colour of a light's texture (a RectLight's: drawn as a uniform
    rectangle of it, said), white when it cannot be read."""
    from ..scene.texture import Texture
    from ..srgb import srgb_to_linear

    resolved = getattr(asset, "resolvedPath", "") or ""
    try:
        if not resolved or "[" in resolved:
            raise FacetError("not found")
        pixels = Texture.load(resolved).pixels[..., :3] / 255.0
    except FacetError:
        notes.append(f"{where}: its texture {getattr(asset, 'path', asset)} cannot be read; "
                     "the light is white")
        return np.ones(3)
    notes.append(f"{where}: a textured RectLight is drawn as a uniform rectangle of its "
                 "texture's mean colour")
    return srgb_to_linear(pixels).reshape(-1, 3).mean(axis=0)


def _dome(prim, time, world, emission, notes, where, up: str = "Y"):
    """A DomeLight as the environment: its latitude-longitude texture (+Y its pole in
    its own frame, or the stage's up axis where ``poleAxis`` says "scene", USD's default)
    turned by the prim's placement and times its emission; a constant dome without one."""
    from pxr import UsdLux

    from ..scene.environment import Environment

    asset = UsdLux.DomeLight(prim).GetTextureFileAttr().Get(time)
    resolved = getattr(asset, "resolvedPath", "") if asset else ""
    if not resolved:
        if asset and getattr(asset, "path", ""):
            notes.append(f"{where}: its texture {asset.path} cannot be found; a constant "
                         "dome of its colour is used")
        return Environment.constant(np.clip(emission, 0, None))
    if "[" in resolved:
        notes.append(f"{where}: a dome texture inside a package is not read; a constant "
                     "dome of its colour is used")
        return Environment.constant(np.clip(emission, 0, None))
    try:
        env = Environment.from_equirect(resolved)
    except FacetError as exc:
        notes.append(f"{where}: its texture cannot be read ({exc}); a constant dome is used")
        return Environment.constant(np.clip(emission, 0, None))
    rotation = world[:3, :3] / np.linalg.norm(world[:3, :3], axis=0)
    # DomeLight_1's poleAxis: "scene" (its default) puts the texture's pole on the stage's
    # up axis, "Z" on z; the first DomeLight's pole is its own +Y.
    pole = UsdLux.DomeLight_1(prim).GetPoleAxisAttr().Get(time) or "scene" \
        if prim.GetTypeName() == "DomeLight_1" else "Y"
    if pole == "Z" or (pole == "scene" and up == "Z"):  # +Y of the texture -> +Z
        rotation = rotation @ np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])
    return env.transformed(rotation, np.clip(emission, 0, None))


def describe_stage(path: Path) -> list[str]:
    """Lines for ``facet info``: the layers, prims by type, variant sets (with the
    selection as composed), the time range and the stage's units."""
    from collections import Counter

    from pxr import Usd, UsdGeom

    from .usd_stage import quiet_pxr, variant_sets

    stage, _ = open_stage(path)
    with quiet_pxr():
        kinds = Counter(p.GetTypeName() or "(typeless)" for p in Usd.PrimRange(
            stage.GetPseudoRoot(), Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate))
            if not p.IsPseudoRoot())
        layers = [layer.realPath or layer.identifier for layer in stage.GetUsedLayers()
                  if not layer.anonymous]
        sets = variant_sets(stage)
        lights = [str(p.GetPath()) for p in stage.Traverse() if p.GetTypeName() in LIGHTS]
    lines = [f"{'usd layers':22} {len(layers)}: " + ", ".join(Path(x).name for x in layers),
             f"{'usd prims':22} " + ", ".join(f"{k} {n}" for k, n in sorted(kinds.items())),
             f"{'usd variant sets':22} " + ("; ".join(
                 f"{k} = {chosen or '(none)'} of {', '.join(names)}"
                 for k, (names, chosen) in sorted(sets.items())) or "none"),
             f"{'usd lights':22} " + (", ".join(lights) or "none"),
             f"{'usd up axis':22} {UsdGeom.GetStageUpAxis(stage)}, "
             f"{UsdGeom.GetStageMetersPerUnit(stage):g} m per unit"]
    if stage.HasAuthoredTimeCodeRange():
        lines.append(f"{'usd time codes':22} {stage.GetStartTimeCode():g} to "
                     f"{stage.GetEndTimeCode():g} at {stage.GetTimeCodesPerSecond():g} per "
                     "second")
    return lines
