"""glTF benchmark: loading and the first frame of textured sample models through facet's
glTF reader (pygltflib + numpy, per-part PBR materials, the pbr model) next to the
single-mesh path facet had before (trimesh loads the file, its parts are baked into one
mesh with the first material and its base-colour image, drawn by Phong): as whole
processes (`facet render` against the old path in a script) and as a fresh Renderer in a
warm process. The new path decodes and uploads every image the materials use (the old one
drew one). Then the pbr model's frame cost next to Phong's on the same scenes.

    python benchmarks/gltf.py

Needs ../shared/gltf (the Khronos samples); prints tables, asserts nothing.
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


def cold(command) -> float:
    """Seconds of a whole process: start, imports, context, load, first frame, PNG."""
    import subprocess
    import sys

    t = time.perf_counter()
    subprocess.run([sys.executable, *command], check=True, capture_output=True)
    return time.perf_counter() - t


def first_frame(load):
    from facet.render.renderer import Renderer

    t = time.perf_counter()
    scene = load()
    with Renderer(*SIZE) as r:
        r.render(scene, outputs=("color",))
    return time.perf_counter() - t


def frame_times(scene, environment, frames: int = 11) -> dict[str, float]:
    """Median seconds per frame by the phong and the pbr model, one renderer, the two
    models taking turns frame by frame (so drift in machine load hits both alike)."""
    from facet.render.renderer import Renderer

    times = {"phong": [], "pbr": []}
    with Renderer(*SIZE) as r:
        for shading in times:  # warm-up: compiles, uploads, image lighting tables
            r.render(scene, outputs=("color",), shading=shading, environment=environment)
        for _ in range(frames):
            for shading, out in times.items():
                t = time.perf_counter()
                r.render(scene, outputs=("color",), shading=shading, environment=environment)
                out.append(time.perf_counter() - t)
    return {k: statistics.median(v) for k, v in times.items()}


def main(load: bool = True) -> None:

    if not SHARED.is_dir():
        print(f"(skipped: {SHARED} is absent)")
        return
    if load:
        load_table()
    frame_table()


def load_table() -> None:
    import tempfile

    import facet

    print(f"\nglTF: load + first frame, {SIZE[0]}x{SIZE[1]}, 4x MSAA (median of 5): a whole "
          "process writing the PNG, and a fresh Renderer in a warm process")
    print(f"{'model':>28} {'faces':>8} {'images':>6} | {'process: single':>15} "
          f"{'facet':>6} {'ratio':>5} | {'in-process: single':>18} {'facet':>6} {'ratio':>5}")
    out = Path(tempfile.mkdtemp()) / "out.png"
    for name in MODELS:
        path = SHARED / name
        rows = {k: [] for k in ("cold old", "cold new", "warm old", "warm new")}
        for _ in range(5):
            rows["cold old"].append(cold([__file__, "--single-mesh", str(path), str(out)]))
            rows["cold new"].append(cold(["-m", "facet", "render", str(path), "-o", str(out),
                                          "--size", f"{SIZE[0]}x{SIZE[1]}", "-q"]))
            rows["warm old"].append(first_frame(lambda p=path: single_mesh_path(p)))
            rows["warm new"].append(first_frame(lambda p=path: facet.open_scene(p)))
        scene = facet.open_scene(path)
        faces = sum(o.mesh.face_count for o in scene.objects)
        images = len({id(s.texture) for o in scene.objects for s in o.material.slots.values()})
        m = {k: statistics.median(v) for k, v in rows.items()}
        print(f"{Path(name).stem:>28} {faces:>8} {images:>6} | {m['cold old'] * 1e3:13.0f}ms "
              f"{m['cold new'] * 1e3:4.0f}ms {m['cold new'] / m['cold old']:5.2f} | "
              f"{m['warm old'] * 1e3:16.0f}ms {m['warm new'] * 1e3:4.0f}ms "
              f"{m['warm new'] / m['warm old']:5.2f}")



def frame_table() -> None:
    import facet

    print(f"\nPBR against Phong: the same scene, {SIZE[0]}x{SIZE[1]}, 4x MSAA, colour "
          "(median of 11, interleaved)")
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
            t = frame_times(scene, env)
            print(f"{label + env_name:>36} | {t['phong'] * 1e3:8.1f} {t['pbr'] * 1e3:7.1f} "
                  f"{t['pbr'] / t['phong']:6.2f}")


if __name__ == "__main__":
    import sys

    if sys.argv[1:2] == ["--frames"]:  # the second table only
        main(load=False)
    elif sys.argv[1:2] == ["--single-mesh"]:  # the old path, as one process (table 1)
        from facet.render.renderer import Renderer

        with Renderer(*SIZE) as r:
            r.render(single_mesh_path(Path(sys.argv[2])), outputs=("color",)).save(sys.argv[3])
    else:
        main()
