"""Re-render the README's glTF gallery with `facet render` (needs ../shared/gltf beside the
repository): each Khronos sample seen from the front, lit only by the generated sky as its
environment (the samples bring no lights), next to the sample's own reference screenshot
(copied with its licence).

    .venv/bin/python docs/gallery/render.py
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
SHARED = HERE.parents[2] / "shared" / "gltf"
# (folder, file, view direction towards the model, extra flags)
MODELS = [
    ("OrientationTest", "OrientationTest.glb", (-1.0, -0.7, -1.2), []),
    ("TextureCoordinateTest", "TextureCoordinateTest.glb", (0, 0, -1), []),
    ("TextureSettingsTest", "TextureSettingsTest.glb", (0, 0, -1), []),
    ("MetalRoughSpheresNoTextures", "MetalRoughSpheresNoTextures.glb", (0, 0, -1), []),
    ("NormalTangentTest", "NormalTangentTest.glb", (0, 0, -1), []),
    ("AlphaBlendModeTest", "AlphaBlendModeTest.glb", (0, -0.25, -1), []),
    ("VertexColorTest", "VertexColorTest.glb", (0, 0, -1), []),
    ("BoxVertexColors", "BoxVertexColors.glb", (-1.0, -0.8, -1.3), []),
]
WIDTH, HEIGHT = 320, 240


def main() -> None:
    import facet

    if not SHARED.is_dir():
        sys.exit(f"{SHARED} is absent")
    for folder, name, direction, extra in MODELS:
        path = SHARED / folder / name
        bounds = facet.open_scene(path).bounds
        camera = facet.Camera.frame(bounds, direction, aspect=WIDTH / HEIGHT, margin=1.08)
        center = bounds.mean(axis=0)
        out = HERE / f"{folder}.png"
        subprocess.run([sys.executable, "-m", "facet", "render", str(path), "-o", str(out),
                        "--size", f"{WIDTH}x{HEIGHT}", "--env", "sky", "--lights", "scene",
                        "--aa", "jittered:8",
                        "--eye", ",".join(f"{v:.6g}" for v in camera.eye),
                        "--target", ",".join(f"{v:.6g}" for v in center), "-q", *extra],
                       check=True)
        out.with_suffix(".json").unlink()
        ref = Image.open(SHARED / folder / "screenshot.png").convert("RGB")
        ref.thumbnail((WIDTH, HEIGHT))
        ref.save(HERE / f"{folder}-reference.png")
        shutil.copy(SHARED / folder / "LICENSE.md", HERE / f"{folder}-LICENSE.md")
        print(out, np.asarray(Image.open(out)).mean().round(1))


if __name__ == "__main__":
    main()
