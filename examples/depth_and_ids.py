"""Colour, linear depth and object ids from one render, side by side.

Depth is float32 in scene units along the camera axis (0 where nothing was hit); ids are the
index ``scene.add`` returned (-1 for background). Both come as numpy arrays, exact per pixel
centre, never blended by anti-aliasing.
"""

import sys

import numpy as np
from PIL import Image

import facet
from facet.scene.colormap import colormap


def main(out: str = "depth_and_ids.png") -> None:
    scene = facet.Scene(background=(0.1, 0.1, 0.12, 1))
    prims = facet.primitives
    scene.add(prims.sphere(0.6), facet.Material(color=(0.9, 0.5, 0.2)),
              facet.transforms.translate((-0.8, 0, 0)))
    scene.add(prims.cube(0.9), facet.Material(color=(0.3, 0.7, 0.4)),
              facet.transforms.compose(facet.transforms.translate((0.8, 0, -0.6)),
                                       facet.transforms.rotate_y(30)))
    scene.add(prims.plane(4.0), facet.Material(color=(0.7, 0.7, 0.7)),
              facet.transforms.translate((0, -0.6, 0)))
    camera = facet.Camera.look_at(eye=(0, 1.5, 3.5), target=(0, 0, 0), fov_y=45)
    with facet.Renderer(320, 240) as renderer:
        frame = renderer.render(scene, camera, outputs=("color", "depth", "ids"))
    hit = frame.depth > 0
    near, far = frame.depth[hit].min(), frame.depth[hit].max()
    depth = np.where(hit, (frame.depth - near) / (far - near), 1.0)
    depth_rgb = (colormap("viridis")(1.0 - depth) * 255).round().astype(np.uint8)
    palette = np.array([[40, 40, 48], [230, 159, 0], [86, 180, 233], [0, 158, 115]], np.uint8)
    ids_rgb = palette[frame.object_ids + 1]
    Image.fromarray(np.hstack([frame.color[..., :3], depth_rgb, ids_rgb])).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
