"""Path tracing benchmark: facet's path tracer (glsl/trace/path.frag, on whatever GL the
machine has) next to Mitsuba 3 (scalar_rgb, the CPU variant that works here) on the same
cores in the same run, and facet's sample rate against the size of the scene.

    python benchmarks/pathtrace.py [--quick]

Efficiency: on scenes both renderers draw alike (tests/mitsuba_scene.py translates them:
models/cornell.toml; the Cornell box as users write it, a scaled plane lamp and one-sided
plates; one-sided glossy metal plates under a small lamp; Lambertian objects under a
2048 x 1024 sky with a 3 x 3-texel sun; the glass scene of glass and mirror balls under a
constant sky; a glowing torus (an emissive mesh); and the glTF model
MetalRoughSpheresNoTextures from ../shared/gltf under an HDR sky of a bright patch and a
gradient), each renders at a few sample counts; the error is the RMSE of linear
radiance against Mitsuba at many independent samples (the glTF and
glossy scenes, whose materials go over as Mitsuba's principled BSDF, alike but not equal:
against each renderer's own picture at many samples). Mitsuba runs twice: with its
default sampler (independent numbers) and with its low-discrepancy one (ldsampler), the
peer of facet's Owen-scrambled Sobol points. Times are each renderer's render alone, the
fastest of three (facet's of a scene it has uploaded, Mitsuba's of a scene it has loaded).
For an unbiased estimator error^2 x time is about constant, so
"efficiency" is 1 / (RMSE^2 x seconds), and the ratio facet / Mitsuba says who reaches a
given error sooner (>= 1: facet). The table also gives the error each reaches in the same
wall time (interpolated in log-log). Sample rate: paths per second (256 x 256, 4 paths per
pixel, 3 bounces, under a sky) on icospheres of 20k to 1.3M triangles. Prints tables;
asserts nothing.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "tests"))


REPEATS = 3  # each timing the fastest of three runs (both renderers): this VM's noise
SPHERES = ROOT.parent / "shared" / "gltf" / "MetalRoughSpheresNoTextures" / \
    "MetalRoughSpheresNoTextures.glb"


def _hdr_sky(path: Path) -> Path:
    """A sky for the glTF scene: a gradient and a bright patch 25 degrees from the zenith
    (radiance 20 over 12 degrees: a small sun would make its mirror spheres' highlights
    a few pixels' worth of the error), as a Radiance .hdr file."""
    from facet.formats.hdr_image import write_hdr
    from facet.scene.environment import equirect_directions

    d = equirect_directions(512, 256)
    up = np.clip(d[..., 1], 0, 1)[..., None]
    img = (0.2 + 0.8 * up) * np.array([0.5, 0.7, 1.0]) * (d[..., 1:2] > 0) + \
        (d[..., 1:2] <= 0) * np.array([0.15, 0.12, 0.1])
    sun = np.array([np.sin(np.radians(25)), np.cos(np.radians(25)), 0.0])
    img[(d @ sun) > np.cos(np.radians(12.0))] = (20.0, 19.0, 17.0)
    write_hdr(path, img.astype(np.float32))
    return path


def _glossy_plates():
    """Four one-sided glossy metal plates (roughness 0.2-0.5, glTF's default one-sided
    material) tilted over a Lambertian floor, lit by a small emitting quad: Mitsuba's
    principled BSDF stands in for facet's (alike, not equal: each against its own)."""
    import facet
    from facet.geometry.camera import Camera
    from facet.scene.pbr import PbrMaterial

    scene = facet.Scene()
    scene.add(facet.primitives.plane(6.0), PbrMaterial(base_color=(0.6,) * 3, metallic=0.0,
                                                       specular=0.0))
    for i, rough in enumerate((0.2, 0.3, 0.4, 0.5)):
        x = -1.2 + 0.8 * i
        scene.add(facet.primitives.plane(0.6),
                  PbrMaterial(base_color=(0.9, 0.7, 0.4), metallic=1.0, roughness=rough),
                  facet.transforms.rotate_x(35.0 - 20 * i) @
                  facet.transforms.translate((x, 0.5, 0.0)))
    scene.add(facet.primitives.plane(0.5), PbrMaterial(
        base_color=(0, 0, 0), metallic=0.0, specular=0.0, emissive=(1, 1, 1),
        emissive_strength=40.0), facet.transforms.translate((0, 2.5, 0.3)) @
        facet.transforms.rotate_x(180.0))
    return scene, Camera.look_at((0, 1.6, 3.2), (0, 0.3, 0), fov_y=45, near=0.5, far=20)


def _emissive_mesh():
    """A glowing torus knot (an emissive triangle mesh of 2k triangles) over a Lambertian
    floor by a wall, with a box: light only from the mesh."""
    import trimesh

    import facet
    from facet.geometry.camera import Camera
    from facet.scene.pbr import PbrMaterial

    lambert = dict(metallic=0.0, specular=0.0)
    scene = facet.Scene()
    scene.add(facet.primitives.plane(6.0), PbrMaterial(base_color=(0.7,) * 3, **lambert))
    scene.add(facet.primitives.plane(6.0), PbrMaterial(base_color=(0.5, 0.6, 0.7), **lambert),
              facet.transforms.translate((0, 0, -1.5)) @ facet.transforms.rotate_x(90.0))
    scene.add(facet.primitives.cube(0.5), PbrMaterial(base_color=(0.7, 0.3, 0.2), **lambert),
              facet.transforms.translate((0.8, 0.25, 0.2)))
    knot = trimesh.creation.torus(major_radius=0.35, minor_radius=0.07, major_sections=64,
                                  minor_sections=16)
    scene.add(facet.Mesh(np.asarray(knot.vertices), np.asarray(knot.faces)),
              PbrMaterial(base_color=(0, 0, 0), emissive=(1.0, 0.8, 0.5), emissive_strength=8.0,
                          **lambert),
              facet.transforms.translate((-0.3, 0.8, 0.0)) @ facet.transforms.rotate_x(60.0))
    return scene, Camera.look_at((0, 1.4, 3.2), (0, 0.5, 0), fov_y=45, near=0.5, far=20)


def _scenes(tmp: Path):
    """(name, scene, camera, sky, own references): sky None, a constant radiance (3,), or
    an HDR file's path."""
    import facet
    import mitsuba_scene

    cornell = facet.load(ROOT / "models" / "cornell.toml")
    as_written = facet.load(mitsuba_scene.AS_WRITTEN)
    glass, camera = mitsuba_scene.glass_scene()
    sunny, sunny_camera = mitsuba_scene.sun_sky_scene()
    plates, plates_camera = _glossy_plates()
    lamp, lamp_camera = _emissive_mesh()
    out = [("Cornell box", cornell, cornell.cameras["front"], None, False),
           ("Cornell as written", as_written, as_written.cameras["front"], None, False),
           ("one-sided glossy", plates, plates_camera, None, True),
           ("2K sky with a sun", sunny, sunny_camera,
            mitsuba_scene.write_sun_sky(tmp / "sun.hdr"), False),
           ("glass + mirror, sky", glass, camera, mitsuba_scene.GLASS_SKY, False),
           ("emissive mesh", lamp, lamp_camera, None, False)]
    if SPHERES.exists():
        spheres = facet.load(SPHERES)
        with facet.Renderer(64, 64) as r:
            view = r.camera(spheres, r.options(spheres))
        out.append(("glTF spheres, HDR sky", spheres, view, _hdr_sky(tmp / "sky.hdr"), True))
    else:
        print(f"({SPHERES} is absent: the glTF scene is skipped)")
    return out


def _facet(scene, camera, size, spp, sky, seed=0):
    import facet

    kw = {"environment": {"color": list(sky)}} if isinstance(sky, tuple) else \
        {"environment": str(sky)} if sky is not None else {}
    kw["outputs"] = ("color",)  # equal work: Mitsuba draws colour only
    with facet.Renderer(size, size) as r:
        r.render(scene, camera, engine="path", spp=1, float_color=True, lights="scene", **kw)
        seconds = []
        for _ in range(REPEATS):
            start = time.perf_counter()
            image = r.render(scene, camera, engine="path", spp=spp, float_color=True,
                             lights="scene", seed=seed, **kw).color[..., :3]
            seconds.append(time.perf_counter() - start)
        return image, min(seconds)


def _mitsuba(scene, camera, size, spp, sky, seed=1, approximate=False,
             sampler="independent"):
    import mitsuba_scene

    return mitsuba_scene.timed_render(scene, camera, size, size, spp, seed=seed,
                                      environment=sky, approximate=approximate,
                                      repeats=REPEATS, sampler=sampler)


def _error_at(times, errors, budget):
    """The error reached in ``budget`` seconds, interpolated in log-log."""
    lt, le = np.log(times), np.log(errors)
    slope, icpt = np.polyfit(lt, le, 1)
    return float(np.exp(icpt + slope * np.log(budget)))


def efficiency_table(quick: bool) -> None:
    import mitsuba_scene

    if not mitsuba_scene.available():
        print("(mitsuba is not installed: pip install mitsuba; efficiency table skipped)")
        return
    size = 64 if quick else 128
    ref_spp = 1024 if quick else 2048
    facet_spp = (4, 16) if quick else (4, 16, 64)
    mitsuba_spp = (16, 64) if quick else (16, 64, 256)
    print(f"\nPath tracing against Mitsuba 3 {mitsuba_scene.VARIANT}, {size}x{size}, max_depth 8 "
          f"(Mitsuba's 10); error: RMSE of linear radiance against Mitsuba at "
          f"{ref_spp} spp (the glTF and glossy scenes: against each renderer's own at that "
          "count); Mitsuba: its default sampler (independent), Mitsuba ld: its "
          "low-discrepancy one (facet's samples are Owen-scrambled Sobol)")
    print(f"{'scene':>22} | {'renderer':>10} {'spp':>5} {'seconds':>8} {'RMSE':>8} "
          f"{'1/(RMSE^2 s)':>13}")
    import tempfile

    ratios = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, scene, camera, sky, own in _scenes(Path(tmp)):
            ratios[name] = _efficiency_rows(name, scene, camera, sky, own, size, ref_spp,
                                            facet_spp, mitsuba_spp)
    for k, sampler in enumerate(("independent, its default", "ldsampler")):
        values = {name: r[k] for name, r in ratios.items()}
        print(f"{'all scenes':>22} | efficiency facet / Mitsuba ({sampler}): lowest "
              f"{min(values.values()):.3f} ({min(values, key=values.get)}), median "
              f"{np.median(list(values.values())):.3f}")


def _efficiency_rows(name, scene, camera, sky, own, size, ref_spp, facet_spp, mitsuba_spp):
    """One scene's rows; returns facet's efficiency over Mitsuba's with its default sampler
    and over Mitsuba's with its low-discrepancy one."""
    def mitsuba(sampler):
        def run(scene, camera, size, spp, sky, seed=1):
            return _mitsuba(scene, camera, size, spp, sky, seed, approximate=own,
                            sampler=sampler)
        return run

    # The reference: Mitsuba with independent samples (a low-discrepancy reference shares
    # the structure of low-discrepancy pictures, and its error does not fall as 1 / N).
    ref, _ = mitsuba("independent")(scene, camera, size, ref_spp, sky, seed=99)
    facet_ref = _facet(scene, camera, size, ref_spp, sky, seed=99)[0] if own else ref
    rows = {}
    for who, fn, counts in (("facet", _facet, facet_spp),
                            ("Mitsuba", mitsuba("independent"), mitsuba_spp),
                            ("Mitsuba ld", mitsuba("ldsampler"), mitsuba_spp)):
        rows[who] = []
        for spp in counts:
            image, seconds = fn(scene, camera, size, spp, sky)
            rmse = float(np.sqrt(((image - (facet_ref if who == "facet" else ref)) ** 2)
                                 .mean()))
            rows[who].append((seconds, rmse))
            print(f"{name:>22} | {who:>10} {spp:>5} {seconds:>8.3f} {rmse:>8.4f} "
                  f"{1 / (rmse ** 2 * seconds):>13.1f}")
    eff = {who: np.median([1 / (e * e * t) for t, e in r]) for who, r in rows.items()}
    budget = float(np.median([t for t, _ in rows["Mitsuba"]]))
    at = {who: _error_at(*zip(*r, strict=True), budget) for who, r in rows.items()}
    ratios = (eff["facet"] / eff["Mitsuba"], eff["facet"] / eff["Mitsuba ld"])
    print(f"{name:>22} | efficiency facet / Mitsuba: {ratios[0]:.3f} (its ldsampler: "
          f"{ratios[1]:.3f}); in {budget:.2f} s facet reaches RMSE {at['facet']:.4f}, "
          f"Mitsuba {at['Mitsuba']:.4f} (ldsampler {at['Mitsuba ld']:.4f})")
    return ratios


def rate_table(quick: bool) -> None:
    import trimesh

    import facet
    from facet.geometry.camera import Camera
    from facet.scene.pbr import PbrMaterial

    size, spp = 256, 4
    print(f"\nPath tracer sample rate against triangles ({size}x{size}, {spp} paths per "
          "pixel, 3 bounces, a grey rough sphere on a floor under a sky)")
    print(f"{'triangles':>10} | {'seconds':>8} {'paths/s':>12} {'vs smallest':>12}")
    first = None
    for sub in ((5, 7) if quick else (5, 7, 8)):
        ico = trimesh.creation.icosphere(subdivisions=sub)
        scene = facet.Scene(ambient=0.0)
        scene.add(facet.Mesh(np.asarray(ico.vertices), np.asarray(ico.faces)),
                  PbrMaterial(base_color=(0.7, 0.7, 0.7), metallic=0.0, roughness=0.6),
                  facet.transforms.translate((0, 1, 0)))
        scene.add(facet.primitives.plane(6.0), PbrMaterial(base_color=(0.5, 0.5, 0.5),
                                                           metallic=0.0))
        camera = Camera.look_at((0, 1.5, 4), (0, 0.8, 0), fov_y=40, near=0.5, far=20)
        with facet.Renderer(size, size) as r:
            kw = dict(engine="path", max_depth=3, float_color=True, lights="scene",
                      environment={"color": [1, 1, 1]})
            r.render(scene, camera, spp=1, **kw)  # upload and compile
            start = time.perf_counter()
            r.render(scene, camera, spp=spp, **kw)
            seconds = time.perf_counter() - start
        rate = size * size * spp / seconds
        first = first or rate
        print(f"{len(ico.faces):>10,} | {seconds:>8.3f} {rate:>12,.0f} {first / rate:>11.2f}x")


def default_table(quick: bool) -> None:
    """The call a user makes: models/cornell.toml with its own settings (the path tracer,
    256 x 256, 64 paths per pixel), next to Mitsuba doing the same work."""
    import facet
    import mitsuba_scene

    scene = facet.load(ROOT / "models" / "cornell.toml")
    camera = scene.cameras["front"]
    size, spp = (128, 16) if quick else (256, 64)
    print(f"\nThe default call: facet.Renderer().render(models/cornell.toml) ({size}x{size}, "
          f"{spp} spp, 8-bit colour), and Mitsuba's equal work (float colour)")
    print(f"{'call':>32} | {'seconds':>8}")
    with facet.Renderer(size, size) as r:
        r.render(scene, spp=1)  # upload and compile
        start = time.perf_counter()
        r.render(scene, spp=spp)
        print(f"{'facet render (scene settings)':>32} | {time.perf_counter() - start:>8.3f}")
    if mitsuba_scene.available():
        _, seconds = _mitsuba(scene, camera, size, spp, None)
        print(f"{'Mitsuba ' + mitsuba_scene.VARIANT + ', same spp':>32} | {seconds:>8.3f}")


def main(quick: bool = False) -> None:
    import mitsuba_scene

    # (a machine whose CPU runs it, a GPU machine's say: FACET_MITSUBA_VARIANT=llvm_ad_rgb)
    mitsuba_scene.VARIANT = os.environ.get("FACET_MITSUBA_VARIANT", mitsuba_scene.VARIANT)
    efficiency_table(quick)
    default_table(quick)
    rate_table(quick)


if __name__ == "__main__":
    main("--quick" in sys.argv)
