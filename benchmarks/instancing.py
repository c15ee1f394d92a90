"""Instancing: many placed copies of one mesh, facet against a bare moderngl floor that draws
the same instances in one instanced call.

    python benchmarks/instancing.py [--quick] [--frames N]

A ~5k-triangle icosphere placed N times on a grid (each copy turned and scaled), one
directional light, 512x512, colour read back. Rows: the floor (one glDrawElementsInstanced,
a mat4 per instance, one-light Phong); facet with equal work (no anti-aliasing, colour only);
facet's default call (4x MSAA, colour, depth and ids); and facet drawing each copy by itself
(each with its own material, so nothing is shared: what every object cost before objects
sharing a mesh and a material were batched). Prints a table; asserts nothing.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import moderngl
import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import facet  # noqa: E402
from facet.geometry import transforms as T  # noqa: E402
from facet.render.renderer import Renderer  # noqa: E402

from floor import FRAG, look_at_mvp, normals  # noqa: E402  (the floor's one-light Phong)
from run import ratio, time_interleaved  # noqa: E402

SIZE = 512
LIGHT = (-0.5, -0.6, -0.6)

VERT = """#version 330 core
in vec3 in_position; in vec3 in_normal; in mat4 in_model;
uniform mat4 u_vp; out vec3 v_n; out vec3 v_p;
void main() {
    vec4 p = in_model * vec4(in_position, 1.0);
    gl_Position = u_vp * p; v_n = mat3(in_model) * in_normal; v_p = p.xyz;
}
"""


def placements(n: int) -> np.ndarray:
    """(n, 4, 4) copies on a square grid in the xz plane, 3 units apart, each turned about
    y and scaled between 0.6 and 1.2 (seeded)."""
    rng = np.random.default_rng(1)
    side = int(np.ceil(np.sqrt(n)))
    k = np.arange(n)
    x, z = (k % side - side / 2) * 3.0, (k // side - side / 2) * 3.0
    out = np.empty((n, 4, 4))
    for i in range(n):  # (setup, not timed)
        out[i] = T.translate((x[i], 0.0, z[i])) @ T.rotate((0, 1, 0), rng.uniform(0, 360)) \
            @ T.scale(rng.uniform(0.6, 1.2))
    return out


def camera_for(n: int):
    side = int(np.ceil(np.sqrt(n))) * 3.0
    eye = np.array([0.0, side * 0.55, side * 0.75])
    return eye, np.zeros(3), side * 0.2, side * 2.5


class InstancedFloor:
    def __init__(self, positions, faces, models, eye, target, near, far):
        ctx = self.ctx = moderngl.create_context(standalone=True, backend="egl")
        self.prog = ctx.program(vertex_shader=VERT, fragment_shader=FRAG)
        vbo = ctx.buffer(np.hstack([positions, normals(positions, faces)]).astype("f4"))
        ibo = ctx.buffer(faces.astype("u4"))
        inst = ctx.buffer(models.transpose(0, 2, 1).reshape(-1, 16).astype("f4"))
        self.n = len(models)
        self.vao = ctx.vertex_array(self.prog, [(vbo, "3f 3f", "in_position", "in_normal"),
                                                (inst, "16f /i", "in_model")],
                                    index_buffer=ibo, index_element_size=4)
        self.fbo = ctx.simple_framebuffer((SIZE, SIZE))
        vp = look_at_mvp(eye, target, 1.0, near=near, far=far)
        self.prog["u_vp"].write(vp.T.astype("f4").tobytes())
        self.prog["u_eye"].value = tuple(eye)
        self.prog["u_light"].value = LIGHT

    def frame(self):
        with self.ctx:  # (facet's renderer holds a context of its own in this thread)
            self.fbo.use()
            self.ctx.enable(moderngl.DEPTH_TEST)
            self.fbo.clear(0, 0, 0, 1)
            self.vao.render(instances=self.n)
            return self.fbo.read(components=4)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="1,000 copies, few frames")
    ap.add_argument("--frames", type=int, default=None)
    a = ap.parse_args()
    table(a.quick, a.frames)


def table(quick: bool = False, frames: int | None = None) -> None:
    counts = [1_000] if quick else [1_000, 10_000]
    frames = frames or (3 if quick else 6)
    ico = trimesh.creation.icosphere(subdivisions=4)  # 5,120 triangles
    pos, faces = np.asarray(ico.vertices, "f4"), np.asarray(ico.faces, "u4")
    mesh = facet.Mesh(pos, faces, normals(pos, faces))
    print(f"\nInstancing: {len(faces):,}-triangle copies, {SIZE}x{SIZE}, one directional "
          "light, colour read back (seconds per frame, median)")
    print(f"{'copies':>8} | {'floor':>8} {'facet eq.':>10} {'default':>9} {'one by one':>11} |"
          f" {'floor/facet':>11}")
    for n in counts:
        times = _timings(n, pos, faces, mesh, frames)
        print(f"{n:>8,} | {times[0].median:>8.3f} {times[1].median:>10.3f} "
              f"{times[2].median:>9.3f} {times[3].median:>11.3f} | "
              f"{ratio(times[0], times[1]):>11.2f}")
    print("floor/facet: the floor's time over facet's equal-work time, round by round "
          "(1.0: as fast as bare moderngl)")


def _timings(n: int, pos, faces, mesh, frames: int) -> list:
    """Timings of the floor, facet (equal work), facet's default call and facet drawing
    each copy by itself, for ``n`` copies."""
    models = placements(n)
    eye, target, near, far = camera_for(n)
    floor = InstancedFloor(pos, faces, models, eye, target, near, far)
    scene, alone = facet.Scene(), facet.Scene()
    material = facet.Material((0.8, 0.8, 0.8), ka=1.0, kd=1.0, ks=0.3, shininess=32)
    for m in models:
        scene.add(mesh, material, m)
        alone.add(mesh, facet.Material((0.8, 0.8, 0.8), ka=1.0, kd=1.0, ks=0.3,
                                       shininess=32), m)
    for s in (scene, alone):
        s.add_light(facet.DirectionalLight(LIGHT))
        s.ambient = np.full(3, 0.1)
    camera = facet.Camera.look_at(eye, target, fov_y=40.0, near=near, far=far)
    equal = dict(aa="none", outputs=("color",), lights="scene", cull="off")
    with Renderer(SIZE, SIZE) as r:

        def facet_equal():
            r.render(scene, camera, **equal).color  # noqa: B018

        def facet_default():
            f = r.render(scene, camera)
            f.color, f.depth, f.object_ids  # noqa: B018

        def facet_alone():
            r.render(alone, camera, **equal).color  # noqa: B018

        times = time_interleaved([floor.frame, facet_equal, facet_default, facet_alone],
                                 frames)
    floor.ctx.release()
    return times


if __name__ == "__main__":
    main()
