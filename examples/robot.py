"""A URDF robot in three joint configurations, posed again without reading it again.

``models/arm/arm.urdf`` (boxes, a cylinder and spheres as exact shapes, an STL hand found
through ``package://``) placed on a floor with ``Scene.add``; ``Scene.posed`` moves its
links to each configuration (radians, metres; the second finger mimics the first).
"""

import sys
from pathlib import Path

import numpy as np
from PIL import Image

import facet

MODELS = Path(__file__).resolve().parents[1] / "models"
POSES = ({"shoulder": 0.0, "elbow": 0.0, "slide": 0.0},
         {"shoulder": 0.8, "elbow": -1.1, "slide": 0.02},
         {"shoulder": -1.2, "elbow": 0.7, "slide": 0.05})


def main(out: str = "robot.png") -> None:
    scene = facet.Scene(background=(1, 1, 1, 1))
    scene.add(facet.shapes.Box((1.6, 1.6, 0.02)), facet.PbrMaterial(
        base_color=(0.8, 0.8, 0.78, 1.0), roughness=0.8), facet.transforms.translate(
        (0.0, 0.0, -0.06)))
    scene.add(facet.load(MODELS / "arm" / "arm.urdf", package_path=(MODELS,)))
    scene.add_light(facet.DirectionalLight(direction=(-0.4, 0.6, -1.0)))
    camera = facet.Camera.look_at((1.5, -1.3, 1.1), (0.1, 0.0, 0.35), up=(0, 0, 1), fov_y=40)
    with facet.Renderer(240, 240) as renderer:
        tiles = [renderer.render(scene.posed(pose), camera, outputs=("color",)).color
                 for pose in POSES]
    Image.fromarray(np.concatenate(tiles, axis=1)).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
