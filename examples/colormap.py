"""Per-vertex scalars through a colormap, with a colour bar.

``Mesh.colored_by(values, "viridis")`` colours a mesh by any per-vertex quantity (here the
height of the torus knot); ``facet.scene.colormap.colorbar`` draws the bar with its range.
The command line does the same: ``facet render models/default.obj --scalars y --colorbar``.
"""

import sys
from pathlib import Path

from PIL import Image

import facet
from facet.scene.colormap import colorbar, scalar_range

MODELS = Path(__file__).resolve().parents[1] / "models"


def main(out: str = "colormap.png") -> None:
    mesh = facet.Mesh.load(MODELS / "default.obj")
    height = mesh.positions[:, 1]
    scene = facet.Scene(background=(1, 1, 1, 1))
    scene.add(mesh.colored_by(height, "viridis"))
    with facet.Renderer(400, 300) as renderer:
        frame = renderer.render(scene, outputs=("color",))
    picture = colorbar(frame.color[..., :3], "viridis", scalar_range(height))
    Image.fromarray(picture).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
