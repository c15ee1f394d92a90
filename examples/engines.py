"""One scene, three engines: the rasterizer, the Whitted ray tracer and the path tracer.

The Cornell box of ``models/cornell.toml`` through each engine, the same lights and
materials. The rasterizer has nothing around the mirror ball to reflect (no environment
map, no ray), so it shows it dark; the ray tracer follows the mirror and gives the area
light's soft shadows; the path tracer adds the light that bounces (colour bleeding from the
walls, the lit ceiling), here 32 samples a pixel through the denoiser (without the
denoise extra installed, 128 samples and one line saying so).
"""

import sys
from pathlib import Path

import numpy as np
from PIL import Image

import facet

MODELS = Path(__file__).resolve().parents[1] / "models"


def main(out: str = "engines.png") -> None:
    scene = facet.load_scene(MODELS / "cornell.toml")
    pictures = []
    with facet.Renderer(160, 160) as renderer:
        path = {"spp": 32, "denoise": True}  # 32 samples a pixel, then the denoiser
        try:
            from facet.render.denoise import require

            require()
        except facet.FacetError as exc:  # (no denoiser here: more samples instead)
            print(f"engines.py: {exc}; the path tracer takes 128 samples instead",
                  file=sys.stderr)
            path = {"spp": 128}
        for engine, extra in (("raster", {}), ("trace", {}), ("path", path)):
            frame = renderer.render(scene, engine=engine, outputs=("color",), **extra)
            pictures.append(frame.color[..., :3])
    Image.fromarray(np.hstack(pictures)).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
