"""Gaussian splats beside meshes: a 3DGS PLY written, read back and drawn with a mesh.

The splat scene is made here (a ring of 20,000 anisotropic splats of SH degree 1, their
colour turning with the view): ``facet.Splats(means, scales, rotations, opacities, sh)``
takes the reference implementation's quantities, ``save`` writes its PLY layout and
``facet.Splats.load`` (or ``facet.load``, ``facet render ring.ply``) reads PLY files from
3DGS, nerfstudio and gsplat and the web viewers' ``.splat``. The rasterizer composites the
splats front to back over the meshes, tested against their depth: the post in front hides
the ring behind it, and the ring's far side shows through its own hole over the floor.
"""

import sys
import tempfile
from pathlib import Path

import numpy as np

import facet


def ring(n: int = 20_000) -> facet.Splats:
    rng = np.random.default_rng(3)
    u = rng.uniform(0, 2 * np.pi, n)
    v = rng.uniform(0, 2 * np.pi, n)
    r = 1.0 + 0.22 * np.cos(v)
    means = np.column_stack([r * np.cos(u), 0.8 + 0.22 * np.sin(v), r * np.sin(u)])
    # Flat splats lying along the ring: long around it, thin across.
    scales = np.column_stack([np.full(n, 0.05), np.full(n, 0.025), np.full(n, 0.008)])
    half = -u / 2  # a rotation about y turning each splat's x axis along the ring
    rotations = np.column_stack([np.cos(half + np.pi / 4), np.zeros(n),
                                 np.sin(half + np.pi / 4), np.zeros(n)])
    colors = np.column_stack([0.55 + 0.4 * np.cos(u), 0.5 + 0.4 * np.sin(3 * u),
                              0.6 + 0.3 * np.sin(u)])
    sh = np.zeros((n, 4, 3))
    sh[:, 0] = (colors - 0.5) / 0.28209479177387814
    sh[:, 3] = [0.35, 0.0, -0.35]  # warmer seen from -x, cooler from +x
    return facet.Splats(means, scales, rotations, rng.uniform(0.6, 0.95, n), sh)


def main(out: str = "splats.png") -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = ring().save(Path(tmp) / "ring.ply")
        splats = facet.Splats.load(path)  # what 3DGS training writes, read back
    scene = facet.Scene(background=(0.93, 0.93, 0.95, 1))
    scene.add(facet.primitives.plane(4.0), facet.Material(color=(0.75, 0.75, 0.72)))
    scene.add(facet.primitives.cube(0.5), facet.Material(color=(0.2, 0.45, 0.8)),
              facet.transforms.translate((0.55, 0.6, 1.5)) @ facet.transforms.scale((1, 2.4, 1)))
    scene.add(splats)
    camera = facet.Camera.look_at(eye=(0.4, 2.0, 3.4), target=(0, 0.6, 0), fov_y=40)
    with facet.Renderer(480, 320) as renderer:
        renderer.render(scene, camera, outputs=("color",)).save(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
