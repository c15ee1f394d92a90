"""Ray tracing benchmark: facet's GPU tracer (glsl/trace/, here on whatever GL the machine
has) next to Embree (embreex, a bench-only dependency: pip install embreex) casting the same
rays on the same cores in the same run.

    python benchmarks/raytrace.py [--quick]

Primary rays: one through every pixel centre of a 1024x1024 camera framing the mesh, the
nearest hit's object or triangle (facet: the exact-channel pass, ``outputs=("ids",)``;
Embree: rtcIntersect's primID). Shadow rays: one per hit pixel towards a directional light
(facet: the colour pass with shadow rays minus the same without, the median of 7 rounds'
differences; Embree: rtcOccluded from the hit points). Build: facet's hierarchy
(facet.geometry.bvh, numpy) against Embree's scene build. Then a frame of
models/example.toml, traced with shadows and one bounce against rasterized with shadow
maps, both at 4 samples per pixel. Prints tables; asserts nothing.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np
import trimesh

from timing import median_time

HERE = Path(__file__).resolve().parent
SHARED = HERE.parents[1] / "shared" / "models"
SIZE = 1024
LIGHT = np.array([-0.4, -1.0, -0.3]) / np.linalg.norm([-0.4, -1.0, -0.3])



def _meshes(quick: bool):
    out = []
    bunny = SHARED / "stanford-bunny.obj"
    if bunny.is_file():
        m = trimesh.load(bunny, process=False)
        out.append(("bunny", np.asarray(m.vertices), np.asarray(m.faces)))
    for sub in ((5,) if quick else (5, 8)):
        ico = trimesh.creation.icosphere(subdivisions=sub)
        out.append((f"icosphere {len(ico.faces) // 1000}k", np.asarray(ico.vertices),
                    np.asarray(ico.faces)))
    return out


def _embree(vertices, faces, origins, dirs):
    """(build s, primary s, hit count, shadow s) with embreex (float32 rays, as facet's)."""
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    tri = vertices[faces].astype(np.float32)
    o, d = origins.astype(np.float32), dirs.astype(np.float32)
    t = time.perf_counter()
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, tri)
    scene.run(o[:1], d[:1])  # the first query commits the scene
    build = time.perf_counter() - t
    prim = median_time(lambda: scene.run(o, d))  # nearest hit: the triangle per ray
    found = scene.run(o, d, output=1)
    hit = found["geomID"] >= 0
    start = o[hit] + d[hit] * found["tfar"][hit, None]
    normals = np.cross(tri[found["primID"][hit], 1] - tri[found["primID"][hit], 0],
                       tri[found["primID"][hit], 2] - tri[found["primID"][hit], 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    normals *= -np.sign(np.sum(normals * d[hit], axis=1))[:, None]  # towards the eye
    start = (start + normals * 1e-4).astype(np.float32)
    to_light = np.broadcast_to(-LIGHT, start.shape).astype(np.float32)
    shadow = median_time(lambda: scene.run(start, to_light, query="OCCLUDED"))
    return build, prim, int(hit.sum()), shadow


def table(quick: bool) -> None:
    import facet
    from facet.geometry.bvh import build_bvh
    from facet.render.renderer import Renderer

    try:
        import embreex  # noqa: F401
        have_embree = True
    except ImportError:
        have_embree = False
    print(f"\nRay tracing: {SIZE}x{SIZE}, one ray per pixel centre, rays/s in millions "
          "(median of 3)" + ("" if have_embree else "; Embree: not installed "
                             "(pip install embreex)"))
    print(f"{'mesh':>16} {'faces':>8} | {'build s':>7} {'embree':>7} | {'primary':>8} "
          f"{'embree':>7} {'ratio':>6} | {'shadow':>7} {'embree':>7} {'ratio':>6}")
    with Renderer(SIZE, SIZE) as r:
        for name, vertices, faces in _meshes(quick):
            tri = vertices[faces].astype(np.float32)
            build = median_time(lambda tri=tri: build_bvh(tri.min(axis=1), tri.max(axis=1)), 1)
            scene = facet.Scene()
            scene.add(facet.Mesh(vertices, faces))
            scene.add_light(facet.DirectionalLight(LIGHT))
            camera = facet.Camera.frame(scene.bounds)
            primary, hits, shadow = _facet_times(r, scene, camera)
            rays = SIZE * SIZE
            ours_p = rays / primary / 1e6
            ours_s = hits / max(shadow, 1e-9) / 1e6
            row = f"{name:>16} {len(faces):>8} | {build:7.2f} "
            if have_embree:
                origins, dirs = _rays(camera)
                e_build, e_prim, e_hits, e_shadow = _embree(vertices, faces, origins, dirs)
                e_p, e_s = rays / e_prim / 1e6, e_hits / e_shadow / 1e6
                row += (f"{e_build:7.2f} | {ours_p:8.2f} {e_p:7.2f} {ours_p / e_p:6.2f} | "
                        f"{ours_s:7.2f} {e_s:7.2f} {ours_s / e_s:6.2f}")
            else:
                row += f"{'-':>7} | {ours_p:8.2f} {'-':>7} {'-':>6} | {ours_s:7.2f}"
            print(row)


def _facet_times(r, scene, camera):
    """(primary s, hit pixels, shadow rays s) of facet's tracer: the shadow rays' time is
    the median over 7 rounds of each round's colour with shadow rays minus the same
    without, the two renders seconds apart (a difference of two medians swung by half
    this machine's drift)."""
    def run(outputs, shadows=False):
        return r.render(scene, camera, outputs=outputs, shadows=shadows, engine="trace",
                        aa="none")

    run(("ids",))  # upload, compile
    # The ids read back: a frame's exact channels are read lazily, and the GL does the
    # work only when something waits for it.
    primary = median_time(lambda: run(("ids",)).object_ids)
    hits = int((run(("ids",)).object_ids >= 0).sum())
    run(("color",))
    run(("color",), True)
    rounds = [median_time(lambda: run(("color",), True), 1) -
              median_time(lambda: run(("color",)), 1) for _ in range(7)]
    return primary, hits, statistics.median(rounds)


def _rays(camera):
    """World origins and unit directions through every pixel centre (as the tracer)."""
    i, j = np.meshgrid(np.arange(SIZE), np.arange(SIZE))
    x, y = 2.0 * (i + 0.5) / SIZE - 1.0, 1.0 - 2.0 * (j + 0.5) / SIZE
    inv = np.linalg.inv(camera.projection(SIZE, SIZE) @ camera.view)

    def unproject(z):
        p = np.stack([x, y, np.full_like(x, z, float), np.ones_like(x, float)], -1) @ inv.T
        return p[..., :3] / p[..., 3:]

    near, far = unproject(-1.0), unproject(1.0)
    d = far - near
    return near.reshape(-1, 3), (d / np.linalg.norm(d, axis=-1, keepdims=True)).reshape(-1, 3)


def frame(quick: bool) -> None:
    import facet
    from facet.render.renderer import Renderer

    scene = facet.load_scene(HERE.parent / "models" / "example.toml")
    print("\nA frame: models/example.toml, 640x480, 4 samples per pixel, colour (median of 3)")
    print(f"{'':>44} | {'ms':>8}")
    with Renderer(640, 480) as r:
        raster = dict(shadows=True, outputs=("color",))
        traced = dict(engine="trace", shadows=True, max_depth=1, outputs=("color",))
        for kw in (raster, traced):
            r.render(scene, **kw)
        t_raster = median_time(lambda: r.render(scene, **raster))
        t_trace = median_time(lambda: r.render(scene, **traced))
    print(f"{'rasterized, shadow maps, 4x MSAA':>44} | {t_raster * 1e3:8.1f}")
    print(f"{'traced, shadow rays, one bounce, 4 spp':>44} | {t_trace * 1e3:8.1f}   "
          f"ratio {t_trace / t_raster:.1f}")


def main() -> None:
    quick = "--quick" in sys.argv
    table(quick)
    frame(quick)


if __name__ == "__main__":
    main()
