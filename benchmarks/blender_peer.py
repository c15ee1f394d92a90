"""Blender's side of benchmarks/stages.py and benchmarks/batch.py, run by a Python that has
``bpy`` (Blender 4.5 as a module: ``pip install bpy==4.5.*`` in a Python 3.11 of its own,
named by FACET_BPY_PYTHON): import a USD stage, or a robot's link meshes, and render
Workbench pictures, timing each step; or render a path-traced dataset with Cycles. Prints
one JSON line.

    python blender_peer.py stage STAGE SIZE VIEWS OUT_DIR
    python blender_peer.py robot POSES.npz SIZE VIEWS OUT_DIR
    python blender_peer.py dataset JOBS.json OUT_DIR

``dataset`` (benchmarks/batch.py's path-traced rows): facet's dataset again in Cycles on
the CPU, every core: each model of JOBS.json imported as it is (no axis conversion), its
material the one facet gives a PLY (base colour, roughness and IOR in JOBS.json, the
Principled BSDF), under a sky of one colour, with the sun lamps of each view (none, or the
world directions and strengths of facet's camera rig), seen by facet's cameras (their
camera -> world matrices and vertical fields of view), at SAMPLES paths a pixel (no
denoiser, no adaptive sampling, the bounces facet takes) and the Standard view transform.
Times the whole run (imports, scene updates and every render with its PNG), not
Blender's start.
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix, Vector


def setup(size: int, engine: str = "BLENDER_WORKBENCH") -> None:
    scene = bpy.context.scene
    scene.render.engine = engine
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    scene.collection.objects.link(cam)
    scene.camera = cam


def look(centre, radius: float, angle: float, up_z: bool) -> None:
    cam = bpy.context.scene.camera
    d = 2.6 * radius
    if up_z:
        eye = Vector((centre[0] + d * math.cos(angle), centre[1] + d * math.sin(angle),
                      centre[2] + 0.5 * d))
    else:
        eye = Vector((centre[0] + d * math.cos(angle), centre[1] + 0.5 * d,
                      centre[2] + d * math.sin(angle)))
    cam.location = eye
    direction = Vector(centre) - eye
    cam.rotation_euler = direction.to_track_quat("-Z", "Z" if up_z else "Y").to_euler()
    cam.data.clip_end = 10 * d


def dataset(jobs_file: Path, out: Path) -> dict:
    """The ``dataset`` kind (module docstring): seconds for every view of every model."""
    jobs = json.loads(jobs_file.read_text())
    scene = bpy.context.scene
    scene.cycles.device = "CPU"
    scene.cycles.samples = jobs["samples"]
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = jobs["bounces"]
    scene.view_settings.view_transform = "Standard"
    scene.render.dither_intensity = 0.0  # (facet's 8-bit colour is not dithered)
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (*jobs["sky"], 1.0)
    scene.world = world
    cam = scene.camera
    cam.data.sensor_fit = "VERTICAL"
    material = bpy.data.materials.new("facet-default")
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*jobs["base_color"], 1.0)
    bsdf.inputs["Roughness"].default_value = jobs["roughness"]
    bsdf.inputs["IOR"].default_value = jobs["ior"]
    suns = []
    for k in range(max(len(v["suns"]) for m in jobs["models"] for v in m["views"])):
        lamp = bpy.data.lights.new(f"sun{k}", "SUN")
        lamp.angle = 0.0  # a delta light, as facet's directional lights
        suns.append(bpy.data.objects.new(f"sun{k}", lamp))
        scene.collection.objects.link(suns[-1])
    views = 0
    t = time.perf_counter()
    for i, model in enumerate(jobs["models"]):
        bpy.ops.wm.ply_import(filepath=model["path"], forward_axis="Y", up_axis="Z")
        obj = bpy.context.selected_objects[0]
        obj.data.materials.append(material)
        for k, view in enumerate(model["views"]):
            cam.matrix_world = Matrix(view["to_world"])
            cam.data.angle = math.radians(view["fov_y"])
            cam.data.clip_start, cam.data.clip_end = view["near"], view["far"]
            for k, sun in enumerate(suns):
                light = view["suns"][k] if k < len(view["suns"]) else None
                sun.hide_render = light is None
                if light is not None:
                    sun.rotation_euler = Vector(light[:3]).to_track_quat("-Z", "Y").to_euler()
                    sun.data.energy = light[3]
            render(out, i * 1000 + k)
            views += 1
        bpy.data.objects.remove(obj)
    return {"seconds": time.perf_counter() - t, "views": views}


def render(out: Path, k: int) -> None:
    bpy.context.scene.render.filepath = str(out / f"view{k:04d}.png")
    bpy.ops.render.render(write_still=True)


def bounds(objects) -> tuple[list, float]:
    pts = np.array([list(o.matrix_world @ Vector(c)) for o in objects for c in o.bound_box])
    lo, hi = pts.min(0), pts.max(0)
    return list((lo + hi) / 2), float(np.linalg.norm(hi - lo) / 2)


def orbit(objects, views: int, out: Path) -> tuple[float, float]:
    """(seconds of the first picture, seconds a picture after it) of ``objects`` seen from
    ``views`` + 1 directions around them, z up."""
    centre, radius = bounds(objects)
    look(centre, radius, 0.3, up_z=True)
    t1 = time.perf_counter()
    render(out, 0)
    first = time.perf_counter() - t1
    t2 = time.perf_counter()
    for k in range(1, views + 1):
        look(centre, radius, 0.3 + 2 * math.pi * k / views, up_z=True)
        render(out, k)
    return first, (time.perf_counter() - t2) / views


def main() -> None:
    kind = sys.argv[1]
    if kind == "dataset":
        out = Path(sys.argv[3])
        out.mkdir(parents=True, exist_ok=True)
        bpy.ops.wm.read_factory_settings(use_empty=True)
        jobs = json.loads(Path(sys.argv[2]).read_text())
        setup(jobs["size"], "CYCLES")
        print(json.dumps({**dataset(Path(sys.argv[2]), out),
                          "version": bpy.app.version_string}))
        return
    source, size, views, out = sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), \
        Path(sys.argv[5])
    out.mkdir(parents=True, exist_ok=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    setup(size)
    t0 = time.perf_counter()
    if kind == "stage":
        bpy.ops.wm.usd_import(filepath=source)
        loaded = time.perf_counter() - t0
        # (Blender's import turns y-up stages z-up)
        meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
        first, per_view = orbit(meshes, views, out)
    else:
        data = np.load(source)
        files, poses = list(data["files"]), data["poses"]  # poses (V, L, 4, 4)
        links = []
        for f in files:
            bpy.ops.wm.stl_import(filepath=str(f))
            links.append(bpy.context.selected_objects[0])
        loaded = time.perf_counter() - t0
        for o, m in zip(links, poses[0], strict=True):
            o.matrix_world = Matrix(m.tolist())
        bpy.context.view_layer.update()
        centre, radius = bounds(links)
        look(centre, 1.6 * radius, 0.3, up_z=True)
        t1 = time.perf_counter()
        render(out, 0)
        first = time.perf_counter() - t1
        t2 = time.perf_counter()
        for k in range(1, views + 1):
            for o, m in zip(links, poses[k % len(poses)], strict=True):
                o.matrix_world = Matrix(m.tolist())
            render(out, k)
        per_view = (time.perf_counter() - t2) / views
    print(json.dumps({"load": loaded, "first": first, "per_view": per_view,
                      "version": bpy.app.version_string}))


if __name__ == "__main__":
    main()
