"""Gaussian splats: facet's splat pass next to a bare moderngl floor on the same splats.

    python benchmarks/splats.py [--quick] [--frames N]

N splats of SH degree 3 (a trained 3DGS scene's layout; seeded, anisotropic, in a ball seen
from outside), 1280x720, colour read back, seconds per frame (median, interleaved rounds).
Rows: the floor (one instanced quad draw of the same splats in plain moderngl, already
sorted front to back, colours already evaluated, no SH: the GPU's share alone); facet with
equal work (no anti-aliasing, colour only) with the camera moving every frame (the splats
sorted and coloured again each time) and still (the order and colours kept); facet's
default call (4x MSAA, colour, depth and ids, moving); then the sorts alone: numpy's of N
depths (what facet does) and a GPU bitonic sort of the same keys in GL 3.3 fragment passes
(the alternative the GL 3.3 path has: log2(N)(log2(N)+1)/2 full-screen passes over a
texture of (depth, index) pairs), and the SH colours of N splats. Prints a table; asserts
nothing.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import moderngl
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import facet  # noqa: E402
from facet.render.renderer import Renderer  # noqa: E402

from run import ratio, time_interleaved  # noqa: E402

SIZE = (1280, 720)

FLOOR_VERT = """
#version 330 core
in vec2 a_corner;
in vec2 a_center;   // window pixels
in vec3 a_conic;
in float a_radius;
in vec4 a_color;    // rgb, opacity
uniform vec2 u_viewport;
flat out vec2 v_center; flat out vec3 v_conic; flat out vec4 v_color;
void main() {
    v_center = a_center; v_conic = a_conic; v_color = a_color;
    gl_Position = vec4((a_center + a_corner * a_radius) / u_viewport * 2.0 - 1.0, 0.0, 1.0);
}
"""
FLOOR_FRAG = """
#version 330 core
flat in vec2 v_center; flat in vec3 v_conic; flat in vec4 v_color;
out vec4 f_color;
void main() {
    vec2 d = v_center - gl_FragCoord.xy;
    float power = -0.5 * (v_conic.x * d.x * d.x + v_conic.z * d.y * d.y) - v_conic.y * d.x * d.y;
    if (power > 0.0) discard;
    float alpha = min(0.99, v_color.a * exp(power));
    if (alpha < 1.0 / 255.0) discard;
    f_color = vec4(v_color.rgb * alpha, alpha);
}
"""


BITONIC_FRAG = """
#version 330 core
uniform sampler2D u_keys;  // (depth, index) pairs, row by row
uniform int u_k, u_j, u_width;
out vec2 f_out;
void main() {  // one compare-exchange of the bitonic network, from this texel's side
    ivec2 c = ivec2(gl_FragCoord.xy);
    int i = c.y * u_width + c.x, p = i ^ u_j;
    vec2 a = texelFetch(u_keys, c, 0).xy;
    vec2 b = texelFetch(u_keys, ivec2(p % u_width, p / u_width), 0).xy;
    bool a_first = a.x < b.x || (a.x == b.x && a.y < b.y);
    f_out = ((i < p) == ((i & u_k) == 0)) == a_first ? a : b;
}
"""
FULLSCREEN_VERT = """
#version 330 core
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""


def gpu_sort_seconds(keys: np.ndarray) -> tuple[float, bool]:
    """(seconds, sorted right) of a bitonic sort of ``keys`` (a power-of-two square count)
    on the GPU, read back."""
    side = int(round(np.sqrt(len(keys))))
    ctx = moderngl.create_standalone_context(backend="egl")
    with ctx:
        data = np.stack([keys, np.arange(len(keys), dtype=np.float32)], 1)
        tex = [ctx.texture((side, side), 2, data.tobytes(), dtype="f4") for _ in range(2)]
        fbo = [ctx.framebuffer([t]) for t in tex]
        prog = ctx.program(vertex_shader=FULLSCREEN_VERT, fragment_shader=BITONIC_FRAG)
        vao = ctx.vertex_array(prog, [])
        prog["u_width"].value = side
        src, k = 0, 2
        start = time.perf_counter()
        while k <= len(keys):
            j = k // 2
            while j >= 1:
                tex[src].use(0)
                prog["u_k"].value, prog["u_j"].value = k, j
                fbo[1 - src].use()
                vao.render(vertices=3)
                src, j = 1 - src, j // 2
            k *= 2
        out = np.frombuffer(tex[src].read(), np.float32).reshape(-1, 2)
        seconds = time.perf_counter() - start
    ctx.release()
    return seconds, bool(np.all(np.diff(out[:, 0]) >= 0))


def cloud(n: int, seed: int = 0) -> facet.Splats:
    rng = np.random.default_rng(seed)
    means = rng.normal(0.0, 0.5, (n, 3))
    sh = rng.normal(0.0, 0.2, (n, 16, 3))
    sh[:, 0] = rng.normal(0.0, 1.0, (n, 3))
    size = 0.5 * n ** (-1 / 3)  # about the spacing of the means
    return facet.Splats(means, size * np.exp(rng.normal(0, 0.4, (n, 3))),
                        rng.normal(0, 1, (n, 4)), rng.uniform(0.2, 0.9, n), sh)


def camera(k: int) -> facet.Camera:
    angle = np.radians(0.5 * k)  # a step past the re-sort threshold every frame
    return facet.Camera.look_at((3.0 * np.sin(angle), 0.6, 3.0 * np.cos(angle)), (0, 0, 0),
                                fov_y=45, near=0.1, far=50)


class SplatFloor:
    """Plain moderngl: the same splats projected once in numpy (screen-space conics, radii,
    colours), drawn sorted front to back as instanced quads with the same blending."""

    def __init__(self, s: facet.Splats, cam: facet.Camera):
        self.ctx = moderngl.create_standalone_context(backend="egl")
        w, h = SIZE
        view = cam.view
        t = s.means.astype(np.float64) @ view[:3, :3].T + view[:3, 3]
        f = h / 2 / np.tan(np.radians(22.5))
        zc = -t[:, 2]
        j = np.zeros((len(t), 2, 3))
        j[:, 0, 0], j[:, 0, 2] = f / zc, f * t[:, 0] / zc ** 2
        j[:, 1, 1], j[:, 1, 2] = f / zc, f * t[:, 1] / zc ** 2
        m = j @ view[:3, :3]
        cov = m @ s.covariances() @ np.transpose(m, (0, 2, 1))
        a, b, c = cov[:, 0, 0] + 0.3, cov[:, 0, 1], cov[:, 1, 1] + 0.3
        det = a * c - b * b
        mid = 0.5 * (a + c)
        radius = np.ceil(3 * np.sqrt(mid + np.sqrt(np.maximum(0.1, mid * mid - det))))
        centre = np.stack([f * t[:, 0] / zc + w / 2, f * t[:, 1] / zc + h / 2], 1)
        colors = s.colors(np.tile([0.0, 0.0, -1.0], (len(t), 1)))
        data = np.concatenate([centre, np.stack([c, -b, a], 1) / det[:, None], radius[:, None],
                               colors, s.opacities[:, None]], 1).astype(np.float32)
        data = data[np.argsort(zc)]
        prog = self.ctx.program(vertex_shader=FLOOR_VERT, fragment_shader=FLOOR_FRAG)
        prog["u_viewport"].value = (float(w), float(h))
        quad = self.ctx.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], np.float32).tobytes())
        inst = self.ctx.buffer(data.tobytes())
        self.vao = self.ctx.vertex_array(prog, [(quad, "2f", "a_corner"),
                                                (inst, "2f 3f 1f 4f/i", "a_center", "a_conic",
                                                 "a_radius", "a_color")])
        self.n = len(data)
        tex = self.ctx.texture(SIZE, 4, dtype="f4")
        self.fbo = self.ctx.framebuffer([tex])
        self.out = np.empty((h, w, 4), np.float32)

    def frame(self) -> None:
        with self.ctx:  # (facet's renderer has its own context, current by turns)
            self.fbo.use()
            self.fbo.clear(0.0, 0.0, 0.0, 0.0)
            self.ctx.enable(moderngl.BLEND)
            self.ctx.blend_func = moderngl.ONE_MINUS_DST_ALPHA, moderngl.ONE
            self.vao.render(moderngl.TRIANGLE_STRIP, vertices=4, instances=self.n)
            self.fbo.read_into(self.out, components=4, dtype="f4")

    def release(self) -> None:
        self.ctx.release()


def table(quick: bool, frames: int | None = None) -> None:
    n = 200_000 if quick else 1_000_000
    frames = frames or (3 if quick else 4)
    s = cloud(n)
    scene = facet.Scene()
    scene.add(s)
    print(f"\nGaussian splats: {n:,} of SH degree 3 at {SIZE[0]}x{SIZE[1]}, colour read back "
          "(seconds per frame, median)")
    floor = SplatFloor(s, camera(0))
    moved = {"equal": 0, "default": 0}
    with Renderer(*SIZE) as r:
        def equal_moving():
            moved["equal"] += 1
            r.render(scene, camera(moved["equal"]), aa="none", outputs=("color",))

        def equal_still():
            r.render(scene, camera(0), aa="none", outputs=("color",))

        def default():
            moved["default"] += 1
            frame = r.render(scene, camera(moved["default"]))
            frame.color, frame.depth, frame.object_ids  # noqa: B018 (read, as a caller)

        timings = time_interleaved([floor.frame, equal_moving, equal_still, default], frames,
                                   block=2)
    floor.release()
    side = 1 << int(np.ceil(np.log2(n) / 2))  # (the bitonic network: a power-of-two square)
    depth = np.random.default_rng(1).random(side * side, dtype=np.float32)
    start = time.perf_counter()
    np.argsort(depth, kind="stable")
    sort = time.perf_counter() - start
    gpu_sort, gpu_ok = gpu_sort_seconds(depth)
    dirs = np.tile(np.array([0.0, 0.0, -1.0], np.float32), (n, 1))
    start = time.perf_counter()
    s.colors(dirs)
    colors = time.perf_counter() - start
    names = ["floor: moderngl, sorted, no SH", "facet, equal work, moving",
             "facet, equal work, still", "facet default call, moving"]
    print(f"{'':>34} | {'seconds':>8} {'vs floor':>9}")
    for name, t in zip(names, timings, strict=True):
        print(f"{name:>34} | {t.median:>8.3f} {ratio(t, timings[0]):>8.2f}x")
    print(f"{f'numpy sort of {side * side:,} depths':>34} | {sort:>8.3f}")
    print(f"{'GPU bitonic sort of the same':>34} | {gpu_sort:>8.3f}" +
          ("" if gpu_ok else "   (NOT SORTED: a driver problem)"))
    print(f"{'numpy SH colours (degree 3) alone':>34} | {colors:>8.3f}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--frames", type=int)
    a = p.parse_args()
    table(a.quick, a.frames)


if __name__ == "__main__":
    main()
