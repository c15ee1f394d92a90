"""Bring what trimesh makes: its primitives and their colours go straight into a scene.

``scene.add`` takes a ``trimesh.Trimesh`` (with its vertex colours, uvs, texture and
material), a ``trimesh.Scene`` (each part placed by its graph) or a ``trimesh.PointCloud``.
An Open3D or PyVista mesh goes in through its arrays the same way:
``facet.Mesh(np.asarray(m.vertices), np.asarray(m.triangles))``.
"""

import sys

import numpy as np
import trimesh

import facet


def main(out: str = "trimesh_scene.png") -> None:
    box = trimesh.creation.box((1, 1, 1))
    box.visual.face_colors = (220, 80, 60, 255)
    capsule = trimesh.creation.capsule(height=1.0, radius=0.35)
    capsule.apply_translation((1.4, 0, 0))
    capsule.visual.vertex_colors = (60, 120, 220, 255)
    torus = trimesh.creation.torus(major_radius=0.5, minor_radius=0.15)
    torus.apply_translation((-1.4, 0, 0))
    torus.visual.vertex_colors = np.column_stack([
        (torus.vertices - torus.vertices.min(0)) / np.ptp(torus.vertices, 0) * 255,
        np.full(len(torus.vertices), 255)]).astype(np.uint8)
    tm_scene = trimesh.Scene([box, capsule, torus])

    scene = facet.Scene(background=(0.95, 0.95, 0.95, 1))
    scene.add(tm_scene)
    camera = facet.Camera.look_at(eye=(0, 2.0, 4.5), target=(0, 0, 0), fov_y=40)
    with facet.Renderer(400, 240) as renderer:
        renderer.render(scene, camera, outputs=("color",)).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
