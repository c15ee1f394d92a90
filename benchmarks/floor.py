"""The floor: the least any renderer on this GL must do, as a bare moderngl script.

Loads a mesh with trimesh, computes smooth normals with numpy, draws it once per frame with
a one-light per-fragment Phong shader into an offscreen framebuffer (optionally 4x MSAA,
resolved), and reads the colour back. With ``exact=True`` it also makes and reads what
facet's default outputs add, linear depth and an id per pixel centre, the least way bare GL
allows: in the same pass (a second render target) without MSAA, in a second single-sample
pass with it (no MSAA sample lies at the pixel centre). Used by benchmarks/run.py for
frame times, and run as a whole process for the cold start:

    python benchmarks/floor.py MODEL OUT.png [--size 1024x1024] [--msaa 4]
"""

from __future__ import annotations

import argparse

import moderngl
import numpy as np

VERT = """#version 330 core
in vec3 in_position; in vec3 in_normal;
uniform mat4 u_mvp; out vec3 v_n; out vec3 v_p;
void main() { gl_Position = u_mvp * vec4(in_position, 1.0); v_n = in_normal; v_p = in_position; }
"""
FRAG = """#version 330 core
in vec3 v_n; in vec3 v_p; uniform vec3 u_eye; uniform vec3 u_light; out vec4 f_color;
void main() {
    vec3 N = normalize(v_n), L = -u_light, V = normalize(u_eye - v_p);
    float d = max(dot(N, L), 0.0);
    float s = d > 0.0 ? pow(max(dot(reflect(-L, N), V), 0.0), 32.0) : 0.0;
    vec3 C = vec3(0.8);
    f_color = vec4(clamp(0.1 * C + 0.8 * C * d + 0.3 * s, 0.0, 1.0), 1.0);
#ifdef EXACT
    f_exact = uvec2(floatBitsToUint(v_w), 1u);
#endif
}
"""
# The exact pair (depth bits, id) alone: the second pass under MSAA.
EXACT_VERT = """#version 330 core
in vec3 in_position; uniform mat4 u_mvp; out float v_w;
void main() { gl_Position = u_mvp * vec4(in_position, 1.0); v_w = gl_Position.w; }
"""
EXACT_FRAG = """#version 330 core
in float v_w; layout(location = 1) out uvec2 f_exact;
void main() { f_exact = uvec2(floatBitsToUint(v_w), 1u); }
"""


def _with_exact(source: str, vertex: bool) -> str:
    """The colour shaders with the exact pair as a second output (clip w = linear depth)."""
    if vertex:
        return source.replace("out vec3 v_p;", "out vec3 v_p; out float v_w;").replace(
            "v_p = in_position; }", "v_p = in_position; v_w = gl_Position.w; }")
    return source.replace("out vec4 f_color;", "out vec4 f_color; in float v_w;\n"
                          "layout(location = 1) out uvec2 f_exact;").replace(
        "#version 330 core", "#version 330 core\n#define EXACT")


def normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = positions[faces]
    fn = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    rep = np.repeat(fn, 3, axis=0)
    idx = faces.reshape(-1)
    n = np.stack([np.bincount(idx, rep[:, k], minlength=len(positions)) for k in range(3)], 1)
    return (n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)).astype("f4")


def look_at_mvp(eye, target, aspect, fov=40.0, near=0.1, far=100.0) -> np.ndarray:
    w = np.asarray(eye, float) - target
    w /= np.linalg.norm(w)
    u = np.cross([0, 1, 0], w)
    u /= np.linalg.norm(u)
    v = np.cross(w, u)
    view = np.eye(4)
    view[:3, :3] = [u, v, w]
    view[:3, 3] = -view[:3, :3] @ eye
    f = 1 / np.tan(np.radians(fov) / 2)
    proj = np.zeros((4, 4))
    proj[0, 0], proj[1, 1] = f / aspect, f
    proj[2, 2], proj[2, 3], proj[3, 2] = -(far + near) / (far - near), -2 * far * near / (
        far - near), -1
    return proj @ view


class Floor:
    def __init__(self, width: int, height: int, msaa: int = 0, cull: bool = False,
                 exact: bool = False):
        ctx = self.ctx = moderngl.create_context(standalone=True, backend="egl")
        self.cull = cull  # back faces culled (the mesh is closed and seen from outside)
        self.size = (width, height)
        together = exact and not msaa  # the exact pair from the colour pass
        self.prog = ctx.program(vertex_shader=_with_exact(VERT, True) if together else VERT,
                                fragment_shader=_with_exact(FRAG, False) if together
                                else FRAG)
        self.fbo = ctx.simple_framebuffer(self.size)
        self.ms = ctx.simple_framebuffer(self.size, samples=msaa) if msaa else None
        self.vao = self.exact_vao = None
        self.exact = self.exact_prog = None
        if exact:
            pair = ctx.renderbuffer(self.size, 2, dtype="u4")
            self.exact = ctx.framebuffer([self.fbo.color_attachments[0], pair],
                                         self.fbo.depth_attachment)
            self.exact_read = ctx.framebuffer([pair])
            if msaa:
                self.exact_prog = ctx.program(vertex_shader=EXACT_VERT,
                                              fragment_shader=EXACT_FRAG)

    def upload(self, positions, normals_, faces):
        ctx = self.ctx
        vbo = ctx.buffer(np.hstack([positions, normals_]).astype("f4"))
        ibo = ctx.buffer(faces.astype("u4"))
        self.vao = ctx.vertex_array(self.prog, [(vbo, "3f 3f", "in_position", "in_normal")],
                                    index_buffer=ibo, index_element_size=4)
        if self.exact_prog is not None:
            self.exact_vao = ctx.vertex_array(self.exact_prog, [(vbo, "3f 12x", "in_position")],
                                              index_buffer=ibo, index_element_size=4)
        lo, hi = positions.min(0), positions.max(0)
        centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo) / 2
        eye = centre + np.array([0.5, 0.4, 1.0]) / np.linalg.norm([0.5, 0.4, 1.0]) * radius * 3
        # The camera (benchmarks/run.py gives facet the same one, so both shade equal areas).
        self.eye, self.target, self.near, self.far = eye, centre, radius, radius * 5
        mvp = look_at_mvp(eye, centre, self.size[0] / self.size[1], near=radius,
                          far=radius * 5)
        self.prog["u_mvp"].write(mvp.T.astype("f4").tobytes())
        if self.exact_prog is not None:
            self.exact_prog["u_mvp"].write(mvp.T.astype("f4").tobytes())
        self.prog["u_eye"].value = tuple(eye)
        self.prog["u_light"].value = (-0.5, -0.6, -0.6)

    def frame(self) -> np.ndarray:
        """Colour, read back (row 0 at the top); with ``exact``, the exact pair too."""
        target = self.ms or self.exact or self.fbo
        target.use()
        self.ctx.cull_face = "back"
        self.ctx.enable(moderngl.DEPTH_TEST | (moderngl.CULL_FACE if self.cull else 0))
        if target is self.exact:  # one pass: clear the pair and colour on the framebuffer
            # that draws them (llvmpipe folds that into the pass; another framebuffer's
            # clear would be a pass over memory of its own)
            target.color_mask = ((False,) * 4, (True,) * 4)
            target.clear(0, 0, 0, 0, depth=1.0)
            target.color_mask = ((True,) * 4, (False,) * 4)
            target.depth_mask = False
            target.clear(0, 0, 0, 1)
            target.depth_mask = True
            target.color_mask = ((True,) * 4, (True,) * 4)
        else:
            target.clear(0, 0, 0, 1)
        self.vao.render()
        if self.ms:
            self.ctx.copy_framebuffer(self.fbo, self.ms)
        data = self.fbo.read(components=4)
        if self.exact_vao is not None:  # MSAA: the second, single-sample pass
            self.exact.use()
            self.exact.color_mask = ((False,) * 4, (True,) * 4)
            self.exact.clear(depth=1.0)  # the pair (colour masked) and depth
            self.exact_vao.render()
        if self.exact is not None:
            self.exact_read.read(components=2, dtype="u4")
        return np.frombuffer(data, np.uint8).reshape(self.size[1], self.size[0], 4)[::-1]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("out")
    ap.add_argument("--size", default="1024x1024")
    ap.add_argument("--msaa", type=int, default=0)
    a = ap.parse_args()
    import trimesh
    from PIL import Image

    mesh = trimesh.load(a.model, process=False)
    mesh.merge_vertices()
    pos = np.asarray(mesh.vertices, "f4")
    faces = np.asarray(mesh.faces, "u4")
    w, h = (int(v) for v in a.size.split("x"))
    floor = Floor(w, h, a.msaa)
    floor.upload(pos, normals(pos, faces), faces)
    Image.fromarray(np.ascontiguousarray(floor.frame()[..., :3])).save(a.out)


if __name__ == "__main__":
    main()
