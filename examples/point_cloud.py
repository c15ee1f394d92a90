"""A point cloud with eye-dome lighting: points without normals, shaded by their depth.

``facet.Points(positions, colors, size=...)`` draws round discs of a size in pixels (or
``radius=`` in scene units); clouds without normals get eye-dome lighting, which outlines
their shape. PLY, XYZ / PTS and PCD files load the same way (``facet render cloud.ply``).
"""

import sys

import numpy as np

import facet


def main(out: str = "point_cloud.png") -> None:
    rng = np.random.default_rng(7)
    u, v = rng.uniform(0, 2 * np.pi, (2, 250_000))
    r = 1.0 + 0.35 * np.cos(v)  # a torus, sampled
    positions = np.column_stack([r * np.cos(u), 0.35 * np.sin(v), r * np.sin(u)])
    colors = np.column_stack([0.5 + 0.5 * np.cos(u), 0.5 + 0.5 * np.sin(v),
                              np.full(len(u), 0.8)])
    scene = facet.Scene(background=(1, 1, 1, 1))
    scene.add(facet.Points(positions.astype(np.float32), colors.astype(np.float32), size=2))
    camera = facet.Camera.look_at(eye=(0, 2.2, 2.6), target=(0, 0, 0), fov_y=45)
    with facet.Renderer(400, 300) as renderer:
        renderer.render(scene, camera, outputs=("color",)).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
