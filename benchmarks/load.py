"""Load time: facet.load and the first frame of glTF files, next to a floor that does the
least possible work and to trimesh's loader.

    python benchmarks/load.py [--quick] [MODEL.glb ...]

Files: a 1.3M-triangle sphere (generated), a textured model of eight 2048x2048 PNG images
(generated: base colour and normal maps of four materials), and any given on the command
line (FlightHelmet, StainedGlassLamp: the Khronos sample models; searched in
../shared/gltf too). Rows, each the median of a few runs in a warm process:

* floor: pygltflib parses the file, numpy views every accessor the meshes use, Pillow
  decodes every image (one after another), and moderngl uploads the buffers and images
  (no mip levels): the least any loader must do;
* facet.load: the scene (checked, materials, textures decoded in parallel threads);
* first frame: facet.load and Renderer.render at 512x512 (upload, compile, draw, read);
* trimesh.load: trimesh's own glTF loader (no upload; it decodes images lazily);
* pyrender first frame: trimesh.load, pyrender.Scene.from_trimesh_scene and a 512x512
  render with one light (PYOPENGL_PLATFORM=egl; pyrender is in the 'bench' extra; its
  column is left out when it is not installed).

Prints a table; asserts nothing.
"""

from __future__ import annotations

import argparse
import io
import sys
import tempfile
from pathlib import Path

import moderngl
import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import facet  # noqa: E402

from timing import median_time  # noqa: E402

SHARED = HERE.parents[1] / "shared" / "gltf"
DTYPES = {5120: "i1", 5121: "u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def sphere_glb(folder: Path) -> Path:
    """1.3M triangles with their normals (as exported models carry them)."""
    path = folder / "sphere-1.3M.glb"
    mesh = trimesh.creation.icosphere(subdivisions=8)
    v = np.asarray(mesh.vertices)
    mesh.vertex_normals = v / np.linalg.norm(v, axis=1, keepdims=True)
    mesh.export(path, include_normals=True)
    return path


def textured_glb(folder: Path, size: int = 2048, materials: int = 4) -> Path:
    """A glb of ``materials`` quads, each with a base-colour and a normal-map PNG."""
    from PIL import Image as PilImage
    from pygltflib import (
        GLTF2,
        Accessor,
        Buffer,
        BufferView,
        Image,
        Material,
        Mesh,
        Node,
        NormalMaterialTexture,
        PbrMetallicRoughness,
        Primitive,
        Scene,
        Texture,
        TextureInfo,
    )

    rng = np.random.default_rng(0)
    blob = bytearray()

    def view(data: bytes) -> int:
        while len(blob) % 4:
            blob.append(0)
        g.bufferViews.append(BufferView(buffer=0, byteOffset=len(blob), byteLength=len(data)))
        blob.extend(data)
        return len(g.bufferViews) - 1

    g = GLTF2()
    quad = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "f4")
    uv = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], "f4")
    idx = np.array([0, 1, 2, 0, 2, 3], "u2")
    g.accessors += [Accessor(bufferView=view(quad.tobytes()), componentType=5126, count=4,
                             type="VEC3", min=[0, 0, 0], max=[1, 1, 0]),
                    Accessor(bufferView=view(uv.tobytes()), componentType=5126, count=4,
                             type="VEC2"),
                    Accessor(bufferView=view(idx.tobytes()), componentType=5123, count=6,
                             type="SCALAR")]
    small = size // 16
    for m in range(materials):
        for _kind in ("base", "normal"):
            pixels = rng.integers(0, 256, (small, small, 3), dtype=np.uint8)
            img = PilImage.fromarray(pixels).resize((size, size), PilImage.Resampling.BICUBIC)
            out = io.BytesIO()
            img.save(out, "PNG")
            g.images.append(Image(bufferView=view(out.getvalue()), mimeType="image/png"))
            g.textures.append(Texture(source=len(g.images) - 1))
        g.materials.append(Material(
            pbrMetallicRoughness=PbrMetallicRoughness(
                baseColorTexture=TextureInfo(index=2 * m)),
            normalTexture=NormalMaterialTexture(index=2 * m + 1)))
        g.meshes.append(Mesh(primitives=[Primitive(
            attributes={"POSITION": 0, "TEXCOORD_0": 1}, indices=2, material=m)]))
        g.nodes.append(Node(mesh=m, translation=[1.2 * m, 0, 0]))
    g.scenes = [Scene(nodes=list(range(materials)))]
    g.scene = 0
    g.buffers = [Buffer(byteLength=len(blob))]
    g.set_binary_blob(bytes(blob))
    path = folder / f"textured-{materials * 2}x{size}.glb"
    g.save_binary(str(path))
    return path


def floor_load(path: Path, ctx) -> None:
    """The least work: parse, view the accessors, decode every image, upload."""
    from PIL import Image
    from pygltflib import GLTF2

    g = GLTF2().load(str(path))
    blob = g.binary_blob()
    buffers = {}
    if blob is None:
        for i, b in enumerate(g.buffers):
            buffers[i] = (path.parent / b.uri).read_bytes()
    else:
        buffers[0] = blob
    used = {v for m in g.meshes for p in m.primitives
            for v in [*(x for x in vars(p.attributes).values() if x is not None),
                      p.indices] if v is not None}
    uploads = []
    for a in used:
        acc = g.accessors[a]
        bv = g.bufferViews[acc.bufferView]
        n = acc.count * WIDTHS[acc.type]
        data = np.frombuffer(buffers[bv.buffer], DTYPES[acc.componentType], n,
                             (bv.byteOffset or 0) + (acc.byteOffset or 0))
        uploads.append(ctx.buffer(data))
    for img in g.images:
        if img.bufferView is not None:
            bv = g.bufferViews[img.bufferView]
            raw = buffers[bv.buffer][bv.byteOffset or 0:(bv.byteOffset or 0) + bv.byteLength]
            pil = Image.open(io.BytesIO(raw))
        else:
            pil = Image.open(path.parent / img.uri)
        rgba = np.asarray(pil.convert("RGBA"))
        uploads.append(ctx.texture(pil.size, 4, rgba.tobytes()))
    ctx.finish()
    for u in uploads:
        u.release()


def pyrender_frame(path: Path, renderer) -> None:
    import pyrender

    tm = trimesh.load(path)
    scene = pyrender.Scene.from_trimesh_scene(tm)
    lo, hi = tm.bounds
    pose = np.eye(4)
    pose[:3, 3] = (lo + hi) / 2 + [0, 0, 2.5 * float(np.linalg.norm(hi - lo))]
    scene.add(pyrender.PerspectiveCamera(yfov=0.7), pose=pose)
    scene.add(pyrender.DirectionalLight(intensity=3.0), pose=pose)
    renderer.render(scene)



def table(quick: bool = False, extra: tuple = ()) -> None:
    runs = 2 if quick else 4
    ctx = moderngl.create_context(standalone=True, backend="egl")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        models = [textured_glb(folder, 1024 if quick else 2048)]
        if not quick:
            models.insert(0, sphere_glb(folder))
        for name in ("FlightHelmet", "StainedGlassLamp", *extra):
            for p in (Path(name), SHARED / name / f"{name}.gltf", SHARED / name / f"{name}.glb"):
                if p.is_file():
                    models.append(p)
                    break
            else:
                if name in ("FlightHelmet", "StainedGlassLamp"):
                    print(f"({name} not found in {SHARED}: its row is left out)")
        print("\nLoad time (seconds, median; warm process)")
        print(f"{'model':>28} | {'floor':>7} {'facet.load':>10} {'ratio':>6} | "
              f"{'first frame':>11} | {'trimesh.load':>12} {'pyrender frame':>14}")
        import os
        import warnings

        os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
        try:
            import pyrender

            offscreen = pyrender.OffscreenRenderer(512, 512)
        except Exception:  # noqa: BLE001 - not installed, or no EGL for PyOpenGL
            offscreen = None
        with facet.Renderer(512, 512) as r:
            for path in models:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")

                    def load_facet(p=path):
                        return facet.load(p)

                    def first_frame(p=path):
                        r.render(facet.load(p)).color  # noqa: B018

                    def floor(p=path):
                        with ctx:
                            floor_load(p, ctx)

                    f = median_time(floor, runs)
                    fl = median_time(load_facet, runs)
                    ff = median_time(first_frame, runs)
                    tm = median_time(lambda p=path: trimesh.load(p), runs)
                    pr = "not installed" if offscreen is None else \
                        f"{median_time(lambda p=path: pyrender_frame(p, offscreen), runs):.3f}"
                print(f"{path.name[:28]:>28} | {f:>7.3f} {fl:>10.3f} {fl / f:>6.2f} | "
                      f"{ff:>11.3f} | {tm:>12.3f} {pr:>14}")
    ctx.release()
    if offscreen is not None:
        offscreen.delete()
    print("ratio: facet.load over the floor (parse + accessors + every image decoded + "
          "uploaded); first frame: facet.load + a 512x512 render")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("models", nargs="*")
    a = ap.parse_args()
    table(a.quick, tuple(a.models))


if __name__ == "__main__":
    main()
