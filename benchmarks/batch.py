"""Batch benchmark: a dataset of 200 models of about 20k triangles (icospheres of varying
size and position, written as PLY), 256x256, 8 views each on a sphere, colour + depth +
normals + transforms.json: one worker, local workers, and Ray on this machine; and what a
model costs besides its views (load, upload, teardown).

    python benchmarks/batch.py [--models N] [--blender PYTHON]

Then path-traced datasets: the same models at 16 paths a pixel (``engine = "path"``,
colour) under a white sky, one worker: equal work, the sky alone (``lights = "scene"``),
and the default call, the sky and facet's camera rig (two directional lights). Beside
them Blender's Cycles on the CPU when PYTHON (or FACET_BPY_PYTHON) is a Python with
``bpy`` (benchmarks/blender_peer.py ``dataset``): the same models, the same cameras,
material, sky, lights, samples and bounces (no denoiser, no adaptive sampling), every
model imported and every view written as a PNG, timed whole as facet's run is. Prints
tables; asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh


def make_models(folder: Path, n: int) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    base = trimesh.creation.icosphere(subdivisions=5)  # 20,480 triangles
    rng = np.random.default_rng(0)
    lines = []
    for i in range(n):
        mesh = base.copy()
        mesh.apply_scale(rng.uniform(0.5, 2.0, 3))
        mesh.apply_translation(rng.uniform(-1, 1, 3))
        path = folder / f"m{i:04d}.ply"
        mesh.export(path)
        lines.append(json.dumps({"model": f"models/{path.name}"}))
    manifest = folder.parent / "dataset.jsonl"
    defaults = {"size": [256, 256], "outputs": ["color", "depth", "normals"],
                "views": {"plan": "sphere", "count": 8}}
    manifest.write_text(json.dumps({"defaults": defaults}) + "\n" + "\n".join(lines) + "\n")
    return manifest


def overhead(manifest: Path, models: int = 12, reps: int = 3) -> tuple[float, float]:
    """(seconds per model besides its views, seconds of its 8 views): a worker's run of
    ``models`` jobs (facet.batch.runner.render_jobs: load one ahead, upload, render, write,
    let go) against the same views and files of scenes already loaded and uploaded;
    interleaved ``reps`` times, medians."""
    from facet.batch.layout import write_transforms, write_view
    from facet.batch.manifest import load_manifest
    from facet.batch.runner import job_options, render_jobs
    from facet.formats.source import open_scene
    from facet.render.renderer import Renderer

    jobs = load_manifest(manifest)[:models + 1]
    whole, views = [], []
    with Renderer() as r, tempfile.TemporaryDirectory() as tmp:
        list(render_jobs(jobs[:1], Path(tmp) / "warm", r))  # programs compiled
        for rep in range(reps):
            t = time.perf_counter()
            list(render_jobs(jobs[1:], Path(tmp) / f"a{rep}", r))
            whole.append((time.perf_counter() - t) / models)
            ready = []
            for job in jobs[1:]:
                scene = open_scene(job.model)
                opts = job_options(job, scene, r)
                cams = job.views.cameras(scene.bounds, opts.up)
                r.render(scene, cams[0], opts).settle()  # uploaded
                ready.append((job, scene, cams, opts))
            t = time.perf_counter()
            for k, (job, scene, cams, opts) in enumerate(ready):
                folder = Path(tmp) / f"b{rep}-{k}"
                entries = [write_view(folder, i, r.render(scene, cam, opts), opts.outputs)
                           for i, cam in enumerate(cams)]
                write_transforms(folder, job, opts.size, cams, entries)
            views.append((time.perf_counter() - t) / models)
            del ready
    w, v = statistics.median(whole), statistics.median(views)
    return w - v, v


# The floor's shader lit like facet's default for a lightless model: the key and fill
# directional lights of the camera rig (facet.scene.light.camera_rig), Phong each.
FRAG_RIG = """#version 330 core
in vec3 v_n; in vec3 v_p; uniform vec3 u_eye; uniform vec3 u_key; uniform vec3 u_fill;
out vec4 f_color;
float phong(vec3 N, vec3 L, vec3 V) {
    float d = max(dot(N, L), 0.0);
    return 0.8 * d + (d > 0.0 ? 0.3 * pow(max(dot(reflect(-L, N), V), 0.0), 32.0) : 0.0);
}
void main() {
    vec3 N = normalize(v_n), V = normalize(u_eye - v_p);
    float I = 0.1 + 0.85 * phong(N, -u_key, V) + 0.3 * phong(N, -u_fill, V);
    f_color = vec4(vec3(clamp(0.8 * I, 0.0, 1.0)), 1.0);
}
"""


def floor_seconds(models: list[Path], out: Path) -> float:
    """The bare moderngl floor of a colour-only dataset: one context, per model trimesh
    load + smooth normals + upload, the same 8 sphere views (facet's view plan gives the
    matrices) lit by the same two rig lights, drawn with 4x MSAA and back-face culling as
    facet does for these closed meshes, each written as a PNG at the same zlib level;
    buffers released per model."""
    from PIL import Image

    from facet.batch.views import ViewPlan
    from facet.image.writers import PNG_COMPRESS_LEVEL
    from facet.scene.light import camera_rig

    from floor import VERT, Floor, normals

    floor = Floor(256, 256, msaa=4, cull=True)
    floor.prog = floor.ctx.program(vertex_shader=VERT, fragment_shader=FRAG_RIG)
    out.mkdir(parents=True, exist_ok=True)
    t = time.perf_counter()
    with floor.ctx:
        for k, path in enumerate(models):
            mesh = trimesh.load(path, process=False)
            pos, faces = np.asarray(mesh.vertices, "f4"), np.asarray(mesh.faces, "u4")
            vbo = floor.ctx.buffer(np.hstack([pos, normals(pos, faces)]).astype("f4"))
            ibo = floor.ctx.buffer(faces)
            floor.vao = floor.ctx.vertex_array(
                floor.prog, [(vbo, "3f 3f", "in_position", "in_normal")], index_buffer=ibo,
                index_element_size=4)
            for i, cam in enumerate(ViewPlan("sphere", 8).cameras(mesh.bounds)):
                mvp = cam.projection(256, 256) @ cam.view
                floor.prog["u_mvp"].write(mvp.T.astype("f4").tobytes())
                floor.prog["u_eye"].value = tuple(float(v) for v in cam.eye)
                key, fill = camera_rig(cam.view)
                floor.prog["u_key"].value = tuple(float(v) for v in key.direction)
                floor.prog["u_fill"].value = tuple(float(v) for v in fill.direction)
                image = np.ascontiguousarray(floor.frame()[..., :3])
                Image.fromarray(image).save(out / f"{k:04d}-{i}.png",
                                            compress_level=PNG_COMPRESS_LEVEL)
            for obj in (floor.vao, ibo, vbo):
                obj.release()
    seconds = time.perf_counter() - t
    floor.ctx.release()
    return seconds


def _row(label: str, render_dataset, manifest: Path, out: Path, **kw) -> None:
    t = time.perf_counter()
    counts = render_dataset(manifest, out, **kw)
    dt = time.perf_counter() - t
    print(f"{label:>38} | {counts['views'] / dt:8.1f} {dt:7.1f}")


def table(n: int) -> None:
    from facet.batch import render_dataset

    with tempfile.TemporaryDirectory() as tmp:
        manifest = make_models(Path(tmp) / "models", n)
        extra, views = overhead(manifest)
        print(f"\nBatch: {n} models of 20k triangles, 256x256, 8 views each, colour + depth + "
              "normals + transforms.json")
        print(f"{'':>38} | {'views/s':>8} {'s':>7}")
        for label, kw in [("1 worker", dict(workers=1)), ("2 local workers", dict(workers=2))]:
            _row(label, render_dataset, manifest, Path(tmp) / label.replace(" ", "-"), **kw)
        # Equal work against the bare moderngl floor: colour PNGs only, one process.
        floor = floor_seconds(sorted((Path(tmp) / "models").glob("*.ply")), Path(tmp) / "floor")
        print(f"{'floor, colour only':>38} | {n * 8 / floor:8.1f} {floor:7.1f}")
        _row("1 worker, colour only", render_dataset, manifest, Path(tmp) / "colour",
             workers=1, defaults={"outputs": ["color"]})
        try:
            import ray
        except ImportError:
            print("(Ray not installed: pip install 'facet-render[ray]')")
        else:
            t = time.perf_counter()
            ray.init(include_dashboard=False, log_to_driver=False, configure_logging=False)
            started = time.perf_counter() - t
            _row("Ray, local cluster", render_dataset, manifest, Path(tmp) / "ray", ray=True)
            ray.shutdown()
            print(f"(the Ray cluster's start, {started:.1f} s, is not counted)")
        print(f"per model besides its views (load, one ahead in a thread; upload; teardown): "
              f"{extra * 1e3:.0f} ms, {extra / views:.0%} of its 8 views' {views * 1e3:.0f} ms")


PATH_SPP = 16
PATH_LIGHTS = (("sky", "scene"), ("sky + rig (default call)", "auto"))


def path_table(n: int, blender_python: str | None) -> None:
    """Path-traced views a second: facet batch against Cycles (module docstring)."""
    from facet.batch import render_dataset

    with tempfile.TemporaryDirectory() as tmp:
        manifest = make_models(Path(tmp) / "models", n)
        lines = manifest.read_text().splitlines()
        print(f"\nPath-traced dataset: {n} models of 20k triangles, 256x256, 8 views each, "
              f"{PATH_SPP} paths a pixel, colour, under a white sky")
        print(f"{'':>38} | {'views/s':>8} {'s':>7}")
        for label, lights in PATH_LIGHTS:
            head = json.loads(lines[0])
            head["defaults"].update(engine="path", spp=PATH_SPP, outputs=["color"],
                                    environment={"color": [1.0, 1.0, 1.0]}, lights=lights)
            path_manifest = manifest.with_name(f"path-{lights}.jsonl")
            path_manifest.write_text("\n".join([json.dumps(head), *lines[1:]]) + "\n")
            _row(f"facet batch, {label}", render_dataset, path_manifest,
                 Path(tmp) / f"path-{lights}", workers=1)
            if not blender_python:
                continue
            jobs = Path(tmp) / f"cycles-{lights}.json"
            jobs.write_text(json.dumps(cycles_jobs(path_manifest)))
            cmd = [blender_python, str(Path(__file__).with_name("blender_peer.py")),
                   "dataset", str(jobs), str(Path(tmp) / f"cycles-{lights}")]
            done = subprocess.run(cmd, capture_output=True, text=True)
            if done.returncode != 0:
                print(f"(blender failed: {done.stderr.strip().splitlines()[-1:]})")
                continue
            got = json.loads(done.stdout.strip().splitlines()[-1])
            name = f"Cycles {got['version'].split()[0]}, {label}"
            print(f"{name:>38} | {got['views'] / got['seconds']:8.1f} {got['seconds']:7.1f}")
        if not blender_python:
            print(f"{'Cycles (CPU)':>38} | not run (give --blender or FACET_BPY_PYTHON)")


def cycles_jobs(manifest: Path) -> dict:
    """The dataset of ``manifest`` as blender_peer.py's ``dataset`` reads it: each model's
    path and views (facet's cameras, and the world directions and strengths of the lights
    facet adds, if any), with facet's material for a PLY, the sky, samples and bounces."""
    from facet.batch.manifest import load_manifest
    from facet.formats.source import open_scene
    from facet.render.capabilities import CAPABILITIES
    from facet.render.materials import as_pbr
    from facet.scene.light import active_lights

    models = []
    for job in load_manifest(manifest):
        scene = open_scene(job.model)
        pbr = as_pbr(scene.objects[0].material)
        lights = job.options.get("lights", "auto")
        views = []
        for camera in job.views.cameras(np.array(scene.bounds), (0.0, 1.0, 0.0), 1.0,
                                        size=(256, 256)):
            # A Cycles sun of strength S gives irradiance S; facet's directional light of
            # intensity i gives pi i (its radiance off white diffuse is i cos).
            suns = [[*map(float, light.direction), float(np.pi * light.intensity)]
                    for light in active_lights(scene.lights, camera.view, lights)]
            views.append({"to_world": np.linalg.inv(camera.view).tolist(),
                          "fov_y": camera.fov_y, "near": camera.near, "far": camera.far,
                          "suns": suns})
        models.append({"path": str(job.model), "views": views})
    return {"size": 256, "samples": PATH_SPP, "bounces": CAPABILITIES["path"].max_depth,
            "sky": [1.0, 1.0, 1.0], "base_color": [float(c) for c in pbr.base_color[:3]],
            "roughness": float(pbr.roughness), "ior": float(pbr.ior), "models": models}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", type=int, default=200)
    ap.add_argument("--blender", default=os.environ.get("FACET_BPY_PYTHON"))
    a = ap.parse_args()
    table(a.models)
    path_table(max(2, a.models // 20), a.blender)


if __name__ == "__main__":
    main()
