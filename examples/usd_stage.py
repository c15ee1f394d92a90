"""An OpenUSD stage: its variant sets, payload, light and camera, refined on request.

``models/usd/stage.usda`` through its own camera, which moves along its time samples
(here at 1 s, time code 24): as authored (the ball's shadingVariant
"blue", the soft cube drawn as its control cage, as usdview draws it by default), then
with the variant "red" chosen and the Catmull-Clark cube refined two levels. The plinth
comes from a payload, the sun is a UsdLux DistantLight, the materials UsdPreviewSurface.
"""

import sys
from pathlib import Path

import numpy as np
from PIL import Image

import facet

STAGE = Path(__file__).resolve().parents[1] / "models" / "usd" / "stage.usda"


def main(out: str = "usd_stage.png") -> None:
    tiles = []
    with facet.Renderer(320, 240) as renderer:
        for options in ({}, {"variants": {"shadingVariant": "red"}, "subdivide": 2}):
            scene = facet.load(STAGE, **options).at(1.0)  # the stage at 1 s
            frame = renderer.render(scene, scene.cameras["renderCam"], outputs=("color",))
            tiles.append(frame.color)
    Image.fromarray(np.concatenate(tiles, axis=1)).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
