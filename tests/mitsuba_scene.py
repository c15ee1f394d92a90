"""An independent reference: a facet scene rendered by Mitsuba 3 (the ``mitsuba`` package,
variant scalar_rgb: llvm_ad_rgb crashes on this CPU; the benchmarks may set ``VARIANT``),
for the path tracer's tests and
benchmarks. Every object goes over as its triangle mesh (a PLY with its vertex normals),
so both renderers see the same geometry; the materials Mitsuba can match exactly are
translated and any other is refused:

- a Lambertian metallic-roughness material (metallic 0, specular 0): ``diffuse``;
- a perfect mirror (metallic 1, roughness 0, base colour c): ``conductor`` with
  specular_reflectance c (Schlick's F with f0 = c is c at every angle only for c = 1, so
  c must be grey and close to 1; checked);
- smooth clear glass (transmission 1, metallic 0, roughness 0, a volume: thickness > 0,
  no absorption, base colour 1): ``dielectric`` of the same ior;
- emission: an ``area`` emitter (one-sided unless double-sided: Mitsuba's emitters are);
- an area light: the emitting rectangle facet's path tracer makes of it
  (facet.render.path.area_lights), an ``area`` emitter on a black rectangle;
- a constant environment: a ``constant`` emitter; an HDR image: an ``envmap`` (Y up, row
  0 at the zenith, as facet reads them; turned half a turn about y, where Mitsuba puts
  the image's left edge).

With ``approximate=True`` (benchmarks, which measure each renderer against its own
converged picture) any other opaque metallic-roughness material goes over as Mitsuba's
``principled`` BSDF of the same base colour, metallic and roughness: alike, not equal.

facet's ``max_depth`` counts bounces after the eye ray, Mitsuba's the path's segments:
theirs = ours + 2. Mitsuba's box pixel filter matches facet's jittered supersampling.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from facet.scene.pbr import PbrMaterial

VARIANT = "scalar_rgb"


def available() -> bool:
    try:
        import mitsuba  # noqa: F401
    except ImportError:
        return False
    return True


def _bsdf(m, approximate: bool = False) -> dict:
    if not isinstance(m, PbrMaterial):
        raise ValueError("only metallic-roughness materials translate to Mitsuba")
    base = [float(c) for c in m.base_color[:3]]
    if approximate and m.transmission == 0:
        return {"type": "principled", "base_color": {"type": "rgb", "value": base},
                "metallic": float(m.metallic), "roughness": float(m.roughness),
                "specular": 0.5 * float(m.specular)}  # Mitsuba's 0.5: f0 = 0.04
    if m.metallic == 0 and m.specular == 0:
        return {"type": "diffuse", "reflectance": {"type": "rgb", "value": base}}
    if (m.transmission == 1 and m.metallic == 0 and m.roughness == 0 and m.thickness > 0
            and min(base) == 1 and not np.any(m.absorption) and m.specular == 1):
        return {"type": "dielectric", "int_ior": float(m.ior), "ext_ior": 1.0}
    if m.metallic == 1 and m.roughness == 0 and min(base) > 0.94 and np.ptp(base) == 0:
        return {"type": "conductor", "material": "none",
                "specular_reflectance": {"type": "rgb", "value": base}}
    raise ValueError(f"material {m.name!r} has no exact Mitsuba counterpart here")


def render(scene, camera, width: int, height: int, spp: int, max_depth: int = 8,
           seed: int = 0, environment=None, approximate: bool = False) -> np.ndarray:
    """(height, width, 3) float32 linear radiance of ``scene`` seen by ``camera``;
    ``environment``: the radiance (3,) of a constant sky, the path of an HDR image, or
    None; ``approximate``: see the module docstring."""
    return timed_render(scene, camera, width, height, spp, max_depth, seed, environment,
                        approximate)[0]


def timed_render(scene, camera, width: int, height: int, spp: int, max_depth: int = 8,
                 seed: int = 0, environment=None, approximate: bool = False,
                 repeats: int = 1, sampler: str = "independent") -> tuple[np.ndarray, float]:
    """``render``'s picture and the seconds Mitsuba's render took (the fastest of
    ``repeats``), the scene's translation and loading not counted (benchmarks/pathtrace.py
    times facet's renders of an uploaded scene alike)."""
    import time

    import mitsuba as mi
    import trimesh

    mi.set_variant(VARIANT)
    with tempfile.TemporaryDirectory() as tmp:
        desc = {"type": "scene",
                "integrator": {"type": "path", "max_depth": max_depth + 2},
                "sensor": _sensor(camera, width, height, spp, seed, sampler)}
        if isinstance(environment, (str, Path)):
            # Mitsuba's u = atan2(x, -z) / 2 pi, facet's 0.5 + that: half a turn about y.
            desc["sky"] = {"type": "envmap", "filename": str(environment),
                           "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 180)}
        elif environment is not None:
            desc["sky"] = {"type": "constant", "radiance": {
                "type": "rgb", "value": [float(c) for c in environment]}}
        from facet.render.path.area_lights import AreaEmitters

        for i, obj in enumerate(scene.objects + AreaEmitters().objects(scene)):
            mesh = obj.mesh
            m = np.asarray(obj.transform, dtype=np.float64)
            pos = mesh.positions @ m[:3, :3].T + m[:3, 3]
            nrm = mesh.normals @ np.linalg.inv(m[:3, :3])
            nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
            faces = mesh.faces
            if np.linalg.det(m[:3, :3]) < 0:
                faces = faces[:, ::-1]
            path = Path(tmp) / f"object{i}.ply"
            trimesh.Trimesh(pos, faces, vertex_normals=nrm, process=False).export(path)
            shape = {"type": "ply", "filename": str(path), "face_normals": False,
                     "bsdf": _bsdf(obj.material, approximate)}
            mat = obj.material
            if np.any(mat.emissive * mat.emissive_strength > 0):
                radiance = [float(c) for c in mat.emissive * mat.emissive_strength]
                if mat.double_sided:
                    raise ValueError("Mitsuba's area emitters are one-sided")
                shape["emitter"] = {"type": "area",
                                    "radiance": {"type": "rgb", "value": radiance}}
            desc[f"object{i}"] = shape
        loaded = mi.load_dict(desc)
        seconds = []
        for _ in range(repeats):
            start = time.perf_counter()
            image = mi.render(loaded, spp=spp, seed=seed)
            seconds.append(time.perf_counter() - start)
    return np.array(image, dtype=np.float32)[..., :3], min(seconds)


def _sensor(camera, width, height, spp, seed, sampler="independent") -> dict:
    import mitsuba as mi

    to_world = np.linalg.inv(np.asarray(camera.view, dtype=np.float64))
    eye, forward = to_world[:3, 3], -to_world[:3, 2]
    up = to_world[:3, 1]
    return {"type": "perspective", "fov": float(camera.fov_y), "fov_axis": "y",
            "near_clip": float(camera.near), "far_clip": float(camera.far),
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[float(v) for v in eye], target=[float(v) for v in eye + forward],
                up=[float(v) for v in up]),
            "sampler": {"type": sampler, "sample_count": spp, "seed": seed},
            "film": {"type": "hdrfilm", "width": width, "height": height,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"}}


DATA = Path(__file__).resolve().parent / "data"
CORNELL_REFERENCE = DATA / "cornell-mitsuba.npy"
CORNELL_SIZE, CORNELL_SPP = 48, 4096
GLASS_REFERENCE = DATA / "glass-mitsuba.npy"
GLASS_SKY = (1.0, 0.9, 0.8)


def glass_scene():
    """A glass ball (ior 1.5), a mirror ball and a red box on a grey floor under a
    constant sky: (scene, camera)."""
    import facet
    from facet.geometry.camera import Camera

    scene = facet.Scene(ambient=0.0)
    lambert = dict(metallic=0.0, specular=0.0)
    scene.add(facet.primitives.plane(6.0), PbrMaterial(base_color=(0.5, 0.5, 0.5), **lambert))
    scene.add(facet.primitives.cube(0.5), PbrMaterial(base_color=(0.8, 0.1, 0.1), **lambert),
              facet.transforms.translate((-0.2, 0.25, -1.0)))
    glass = PbrMaterial(base_color=(1, 1, 1), metallic=0.0, roughness=0.0, transmission=1.0,
                        thickness=1.0, ior=1.5)
    scene.add(facet.primitives.sphere(0.5, segments=96, rings=48), glass,
              facet.transforms.translate((-0.6, 0.5, 0.0)))
    mirror = PbrMaterial(base_color=(1, 1, 1), metallic=1.0, roughness=0.0)
    scene.add(facet.primitives.sphere(0.5, segments=96, rings=48), mirror,
              facet.transforms.translate((0.6, 0.5, 0.0)))
    camera = Camera.look_at((0, 1.4, 3.2), (0, 0.4, 0), fov_y=35, near=0.5, far=20)
    return scene, camera


AS_WRITTEN = DATA / "cornell-as-written.toml"
AS_WRITTEN_REFERENCE = DATA / "cornell-as-written-mitsuba.npy"
SUN_SKY_REFERENCE = DATA / "sun-sky-mitsuba.npy"
SUN_IN_VIEW_REFERENCE = DATA / "sun-in-view-mitsuba.npy"
DEFAULTS_SIZE, DEFAULTS_SPP = 64, 4096


def write_sun_sky(path: Path, in_view: bool = False) -> Path:
    """A 2048 x 1024 Radiance sky as users download them: a blue gradient over a brown
    ground and a sun of 3 x 3 texels behind the camera of ``sun_sky_scene`` (radiance
    3000, at a row and column that are no multiples of 4: a thinned grid missed it; behind
    the camera, the shadows fall behind the objects, in view); ``in_view``: the sun where
    that camera sees it, over the floor's far edge (the eye's sight of a small sun: the
    cube map held 20% too little of its light)."""
    from facet.formats.hdr_image import write_hdr
    from facet.scene.environment import equirect_directions

    d = equirect_directions(2048, 1024)
    up = np.clip(d[..., 1:2], 0, 1)
    img = np.where(d[..., 1:2] > 0, (0.3 + 0.7 * up) * np.array([0.35, 0.5, 0.9]),
                   np.array([0.12, 0.1, 0.08])).astype(np.float32)
    row, column = (527, 1039) if in_view else (301, 2001)
    img[row:row + 3, column:column + 3] = (3000.0, 2800.0, 2500.0)
    write_hdr(path, img)
    return path


def sun_sky_scene():
    """What users put under such a sky, with every default left (no ambient line, one-sided
    materials): a Lambertian floor, box and two balls: (scene, camera). (No glass or
    mirror: the sun seen through or in them is a few pixels' fireflies in both
    renderers, which would swamp the comparison; tests/test_path_mitsuba.py has glass.)"""
    import facet
    from facet.geometry.camera import Camera

    scene = facet.Scene()
    lambert = dict(metallic=0.0, specular=0.0)
    scene.add(facet.primitives.plane(8.0), PbrMaterial(base_color=(0.6, 0.6, 0.6), **lambert))
    scene.add(facet.primitives.cube(0.6), PbrMaterial(base_color=(0.7, 0.2, 0.15), **lambert),
              facet.transforms.rotate_y(25.0) @ facet.transforms.translate((0.0, 0.3, 0.0)))
    scene.add(facet.primitives.sphere(0.35, segments=64, rings=32),
              PbrMaterial(base_color=(0.8, 0.8, 0.8), **lambert),
              facet.transforms.translate((0.9, 0.35, 0.3)))
    scene.add(facet.primitives.sphere(0.4, segments=64, rings=32),
              PbrMaterial(base_color=(0.2, 0.4, 0.7), **lambert),
              facet.transforms.translate((-0.9, 0.4, 0.4)))
    camera = Camera.look_at((0, 1.6, 3.4), (0, 0.35, 0), fov_y=40, near=0.5, far=20)
    return scene, camera


def cornell_reference() -> np.ndarray:
    """(48, 48, 3) Mitsuba's picture of models/cornell.toml at 4096 paths per pixel
    (cached in tests/data; ``python tests/mitsuba_scene.py`` renders it again)."""
    return np.load(CORNELL_REFERENCE)


if __name__ == "__main__":
    import facet

    root = Path(__file__).resolve().parents[1]
    cornell = facet.load(root / "models" / "cornell.toml")
    image = render(cornell, cornell.cameras["front"], CORNELL_SIZE, CORNELL_SIZE,
                   CORNELL_SPP)
    np.save(CORNELL_REFERENCE, image.astype(np.float32))
    print(CORNELL_REFERENCE, image.mean(axis=(0, 1)))
    glass, camera = glass_scene()
    image = render(glass, camera, CORNELL_SIZE, CORNELL_SIZE, CORNELL_SPP,
                   environment=GLASS_SKY)
    np.save(GLASS_REFERENCE, image.astype(np.float32))
    print(GLASS_REFERENCE, image.mean(axis=(0, 1)))
    as_written = facet.load(AS_WRITTEN)
    image = render(as_written, as_written.cameras["front"], DEFAULTS_SIZE, DEFAULTS_SIZE,
                   DEFAULTS_SPP)
    np.save(AS_WRITTEN_REFERENCE, image.astype(np.float32))
    print(AS_WRITTEN_REFERENCE, image.mean(axis=(0, 1)))
    with tempfile.TemporaryDirectory() as tmp:
        sky, camera = write_sun_sky(Path(tmp) / "sky.hdr"), None
        scene, camera = sun_sky_scene()
        image = render(scene, camera, DEFAULTS_SIZE, DEFAULTS_SIZE, DEFAULTS_SPP,
                       environment=sky)
    np.save(SUN_SKY_REFERENCE, image.astype(np.float32))
    print(SUN_SKY_REFERENCE, image.mean(axis=(0, 1)))
    with tempfile.TemporaryDirectory() as tmp:
        sky = write_sun_sky(Path(tmp) / "sky.hdr", in_view=True)
        image = render(scene, camera, DEFAULTS_SIZE, DEFAULTS_SIZE, DEFAULTS_SPP,
                       environment=sky)
    np.save(SUN_IN_VIEW_REFERENCE, image.astype(np.float32))
    print(SUN_IN_VIEW_REFERENCE, image.mean(axis=(0, 1)))
