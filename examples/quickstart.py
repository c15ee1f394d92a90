"""Render a model: load a mesh, give it a material and a light, frame it, save the picture.

The smallest complete facet program: a scene, a camera framed on it, one render.
"""

import sys
from pathlib import Path

import facet

MODELS = Path(__file__).resolve().parents[1] / "models"


def main(out: str = "quickstart.png") -> None:
    scene = facet.Scene(background=(1, 1, 1, 1))
    mesh = facet.Mesh.load(MODELS / "torus.off")
    scene.add(mesh, facet.Material(color=(0.2, 0.45, 0.8), ks=0.5, shininess=64))
    scene.add_light(facet.DirectionalLight(direction=(-1, -2, -1)))
    camera = facet.Camera.frame(scene.bounds, aspect=4 / 3)
    with facet.Renderer(480, 360) as renderer:
        frame = renderer.render(scene, camera, outputs=("color",))
    frame.save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
