"""Point clouds: facet's discs against a bare moderngl GL_POINTS floor on the same points.

    python benchmarks/points.py [--quick] [--frames N]

N points sampled on a sphere's surface with random colours (seeded), 1024x768, colour read
back (seconds per frame, median). Rows: the floor (one glDrawArrays(GL_POINTS) of 2-pixel
square points, position and an 8-bit colour per point); facet with equal work as near as it
comes (2-pixel discs, no anti-aliasing, no eye-dome lighting, colour only); facet's default
call for a cloud (3-pixel discs, eye-dome lighting, 4x MSAA, colour, depth and ids). The
viewer draws through the same pass sequence (Renderer.present), so its frame time is the
render's without the readback. Prints a table; asserts nothing.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import moderngl
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import facet  # noqa: E402
from facet.render.renderer import Renderer  # noqa: E402

from floor import look_at_mvp  # noqa: E402
from run import ratio, time_interleaved  # noqa: E402

SIZE = (1024, 768)
EYE = np.array([0.0, 0.6, 3.2])

VERT = """#version 330 core
in vec3 in_position; in vec4 in_color; uniform mat4 u_mvp; out vec4 v_color;
void main() { gl_Position = u_mvp * vec4(in_position, 1.0); gl_PointSize = 2.0;
              v_color = in_color; }
"""
FRAG = """#version 330 core
in vec4 v_color; out vec4 f_color;
void main() { f_color = v_color; }
"""


def cloud(n: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(2)
    p = rng.normal(size=(n, 3)).astype("f4")
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    return p, rng.integers(0, 256, (n, 4), dtype=np.uint8)


class PointsFloor:
    def __init__(self, positions, colors, size=SIZE):
        ctx = self.ctx = moderngl.create_context(standalone=True, backend="egl")
        self.prog = ctx.program(vertex_shader=VERT, fragment_shader=FRAG)
        self.vao = ctx.vertex_array(self.prog, [(ctx.buffer(positions), "3f", "in_position"),
                                                (ctx.buffer(colors), "4f1", "in_color")])
        self.n = len(positions)
        self.fbo = ctx.simple_framebuffer(size)
        mvp = look_at_mvp(EYE, np.zeros(3), size[0] / size[1], near=0.5, far=10.0)
        self.prog["u_mvp"].write(mvp.T.astype("f4").tobytes())

    def frame(self):
        with self.ctx:
            self.fbo.use()
            self.ctx.enable(moderngl.DEPTH_TEST | moderngl.PROGRAM_POINT_SIZE)
            self.fbo.clear(0, 0, 0, 1)
            self.vao.render(mode=moderngl.POINTS, vertices=self.n)
            return self.fbo.read(components=4)


def _timings(n: int, frames: int) -> list:
    positions, colors = cloud(n)
    floor = PointsFloor(positions, colors)
    equal, default = facet.Scene(), facet.Scene()
    equal.add(facet.Points(positions, colors, size=2, edl=False))
    default.add(facet.Points(positions, colors))
    camera = facet.Camera.look_at(EYE, (0, 0, 0), fov_y=40.0, near=0.5, far=10.0)
    with Renderer(*SIZE) as r:

        def facet_equal():
            r.render(equal, camera, aa="none", outputs=("color",)).color  # noqa: B018

        def facet_default():
            f = r.render(default, camera)
            f.color, f.depth, f.object_ids  # noqa: B018

        times = time_interleaved([floor.frame, facet_equal, facet_default], frames)
    floor.ctx.release()
    return times


def table(quick: bool = False, frames: int | None = None) -> None:
    counts = [1_000_000] if quick else [1_000_000, 10_000_000]
    frames = frames or (3 if quick else 6)
    print(f"\nPoint clouds: N points on a sphere, {SIZE[0]}x{SIZE[1]}, colour read back "
          "(seconds per frame, median)")
    print(f"{'points':>12} | {'GL_POINTS':>9} {'facet eq.':>10} {'default':>9} | "
          f"{'floor/facet':>11}")
    for n in counts:
        t = _timings(n, frames)
        print(f"{n:>12,} | {t[0].median:>9.3f} {t[1].median:>10.3f} {t[2].median:>9.3f} | "
              f"{ratio(t[0], t[1]):>11.2f}")
    print("facet eq.: 2-pixel discs (the floor's are 2-pixel squares), no MSAA, no eye-dome "
          "lighting; default: 3-pixel discs, eye-dome lighting, 4x MSAA, depth and ids")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="1M points, few frames")
    ap.add_argument("--frames", type=int, default=None)
    a = ap.parse_args()
    table(a.quick, a.frames)


if __name__ == "__main__":
    main()
