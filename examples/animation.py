"""A skinned glTF animation, posed at four times and set side by side.

``time`` poses the scene's glTF animations (skins, morph targets, node transforms) the same
way in every front: ``Renderer.render(..., time=t)``, ``facet render --time T``, sequences
with ``--time A:B --fps F -o anim.gif``.
"""

import sys
from pathlib import Path

import numpy as np
from PIL import Image

import facet

MODELS = Path(__file__).resolve().parents[1] / "models"


def main(out: str = "animation.png") -> None:
    scene = facet.open_scene(MODELS / "bending-strip.glb")
    camera = facet.Camera.look_at(eye=(0, 1.0, 5.0), target=(0, 1.0, 0), fov_y=45)
    with facet.Renderer(160, 200, background=(1, 1, 1, 1)) as renderer:
        frames = [renderer.render(scene, camera, time=t, outputs=("color",)).color[..., :3]
                  for t in (0.0, 0.5, 1.0, 1.5)]
    Image.fromarray(np.hstack(frames)).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
