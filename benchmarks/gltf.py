"""glTF benchmark: loading and the first frame of textured sample models through facet's
glTF reader (pygltflib + numpy, per-part PBR materials, the pbr model) next to the
single-mesh path facet had before (trimesh loads the file, its parts are baked into one
mesh with the first material, drawn by Phong); then the pbr model's frame cost next to
Phong's on the same scenes.

    python benchmarks/gltf.py

Needs ../shared/gltf (the Khronos samples); prints tables, asserts nothing. Each "load +
first frame" is a fresh Renderer (context, shader compiles, uploads, image lighting
tables) in this process, interleaved between the two paths, median of 5.
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "gltf"
MODELS = ("NormalTangentTest/NormalTangentTest.glb", "AlphaBlendModeTest/AlphaBlendModeTest.glb",
          "TextureCoordinateTest/TextureCoordinateTest.glb",
          "MetalRoughSpheresNoTextures/MetalRoughSpheresNoTextures.glb")
SIZE = (800, 600)


def single_mesh_path(path: Path):
    """The old path: trimesh's glTF reader, the scene baked into one mesh, first material."""
    import trimesh

    import facet
    from facet.scene.texture import Texture

    loaded = trimesh.load(str(path), process=False)
    tm = loaded.to_geometry() if hasattr(loaded, "to_geometry") else loaded.dump(concatenate=True)
    uv = getattr(tm.visual, "uv", None)
    mat = getattr(tm.visual, "material", None)
    image = getattr(mat, "baseColorTexture", None)
    material = facet.Material(texture=None if image is None or uv is None else
                              Texture.from_pil(image))
    scene = facet.Scene()
    scene.add(facet.Mesh(np.asarray(tm.vertices), np.asarray(tm.faces),
                         uvs=None if uv is None else np.asarray(uv)), material)
    return scene


def first_frame(load):
    from facet.render.renderer import Renderer

    t = time.perf_counter()
    scene = load()
    with Renderer(*SIZE) as r:
        r.render(scene, outputs=("color",))
    return time.perf_counter() - t


def frame_time(scene, shading: str, environment) -> float:
    from facet.render.renderer import Renderer

    with Renderer(*SIZE) as r:
        r.render(scene, outputs=("color",), shading=shading, environment=environment)
        times = []
        for _ in range(7):
            t = time.perf_counter()
            r.render(scene, outputs=("color",), shading=shading, environment=environment)
            times.append(time.perf_counter() - t)
    return statistics.median(times)


def main() -> None:
    import facet

    if not SHARED.is_dir():
        print(f"(skipped: {SHARED} is absent)")
        return
    print(f"\nglTF: load + first frame, {SIZE[0]}x{SIZE[1]}, 4x MSAA, fresh renderer "
          "(median of 5)")
    print(f"{'model':>28} {'faces':>8} | {'single mesh':>11} {'facet':>7} {'ratio':>6}")
    for name in MODELS:
        path = SHARED / name
        old, new = [], []
        for _ in range(5):
            old.append(first_frame(lambda p=path: single_mesh_path(p)))
            new.append(first_frame(lambda p=path: facet.open_scene(p)))
        faces = sum(o.mesh.face_count for o in facet.open_scene(path).objects)
        a, b = statistics.median(old), statistics.median(new)
        print(f"{Path(name).stem:>28} {faces:>8} | {a * 1e3:9.0f}ms {b * 1e3:5.0f}ms "
              f"{b / a:6.2f}")

    print(f"\nPBR against Phong: the same scene, {SIZE[0]}x{SIZE[1]}, 4x MSAA, colour "
          "(median of 7)")
    print(f"{'scene':>36} | {'phong ms':>8} {'pbr ms':>7} {'ratio':>6}")
    sky = facet.Environment.sky()
    bunny = ROOT.parent / "shared" / "models" / "stanford-bunny.obj"
    scenes = [(Path(n).stem, facet.open_scene(SHARED / n)) for n in MODELS[:2]]
    if bunny.is_file():
        s = facet.Scene()
        s.add(facet.Mesh.load(bunny), facet.PbrMaterial(base_color=(0.8, 0.5, 0.3, 1),
                                                        metallic=0.3, roughness=0.4))
        scenes.append(("bunny, one PbrMaterial", s))
    for label, scene in scenes:
        for env_name, env in (("", None), (" + sky", sky)):
            phong = frame_time(scene, "phong", env)
            pbr = frame_time(scene, "pbr", env)
            print(f"{label + env_name:>36} | {phong * 1e3:8.1f} {pbr * 1e3:7.1f} "
                  f"{pbr / phong:6.2f}")


if __name__ == "__main__":
    main()
