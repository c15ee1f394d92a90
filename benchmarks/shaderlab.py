"""Shader lab benchmark: a single-pass Shadertoy shader's frame through facet.lab.ShaderToy
next to a bare moderngl full-screen pass running the same expanded GLSL into the same
RGBA32F target (the floor: one uniform written, one triangle drawn), and a three-pass
feedback program's frame; each frame ends with glFinish so GPU work is counted.

    python benchmarks/shaderlab.py

Prints a table; asserts nothing.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

from timing import median_time

ROOT = Path(__file__).resolve().parents[1]
SIZE = (800, 450)
SHADERS = ("waves.frag", "sdf.frag")
FRAMES = 30


def finisher(ctx):
    """glFinish with the context current (ShaderToy makes it current only inside its
    calls; see facet.gl.context)."""
    def finish():
        with ctx:
            ctx.finish()
    return finish


def _median_frame(step, finish) -> float:
    step(0.0)
    finish()
    times = []
    for i in range(FRAMES):
        t = time.perf_counter()
        step(i / 60)
        finish()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def bare(toy):
    """A plain moderngl program of the toy's image pass's expanded source."""
    import moderngl

    ctx = toy.ctx
    src = toy.programs["image"].sources
    prog = ctx.program(vertex_shader=src["vertex"].text, fragment_shader=src["fragment"].text)
    target = ctx.texture(SIZE, 4, dtype="f4")
    fbo = ctx.framebuffer([target])
    vao = ctx.vertex_array(prog, [])
    res = prog.get("iResolution", None)
    if res is not None:
        res.value = (float(SIZE[0]), float(SIZE[1]), 1.0)
    t_uniform = prog.get("iTime", None)

    def step(t):
        if t_uniform is not None:
            t_uniform.value = t
        fbo.use()
        vao.render(moderngl.TRIANGLES, vertices=3)

    return step, (prog, target, fbo, vao)


def main() -> None:
    from facet.lab.shadertoy import ShaderToy

    print(f"\nShader lab: {SIZE[0]}x{SIZE[1]} RGBA32F, one frame + glFinish (median of "
          f"{FRAMES})")
    print(f"{'shader':>30} | {'moderngl ms':>11} {'facet ms':>9} {'ratio':>6}")
    for name in SHADERS:
        with ShaderToy(ROOT / "glsl" / "examples" / name, size=SIZE) as toy:
            with toy.ctx:
                step, keep = bare(toy)
                floor = _median_frame(step, toy.ctx.finish)
                for obj in keep:
                    obj.release()
            facet_ms = _median_frame(lambda t, toy=toy: toy.step(t, 1 / 60),
                                     finisher(toy.ctx))
        print(f"{name:>30} | {floor * 1e3:11.2f} {facet_ms * 1e3:9.2f} "
              f"{facet_ms / floor:6.2f}")
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        (d / "a.frag").write_text("void mainImage(out vec4 c, in vec2 p) { c = texelFetch("
                                  "iChannel0, ivec2(p), 0) * 0.99 + vec4(0.01); }")
        (d / "b.frag").write_text("void mainImage(out vec4 c, in vec2 p) { c = texture("
                                  "iChannel1, p / iResolution.xy).bgra; }")
        (d / "i.frag").write_text("void mainImage(out vec4 c, in vec2 p) { c = texture("
                                  "iChannel2, p / iResolution.xy); }")
        with ShaderToy(d / "i.frag", buffers={"a": d / "a.frag", "b": d / "b.frag"},
                       pass_channels={"a": {0: "buffer-a"}, "b": {1: "buffer-a"},
                                      "image": {2: "buffer-b"}}, size=SIZE) as toy:
            ms = _median_frame(lambda t: toy.step(t, 1 / 60), finisher(toy.ctx))
            print(f"{'3 passes (A feedback, B, image)':>30} | {'':>11} {ms * 1e3:9.2f}")
            headless(toy)
    assembly()


def headless(toy) -> None:
    """A headless picture at t = 1 s, 30 fps (31 frames): ``render`` (passes that feed no
    later frame drawn on the frame shown only) against every pass on every frame (what
    it did before; the same picture)."""
    fps, end = 30.0, 1.0

    def every_pass():
        toy.restart()
        for k in range(int(end * fps) + 1):
            toy.step(k / fps, 1 / fps, fps=fps)
        with toy.ctx:
            toy.ctx.finish()

    def rendered():
        toy.restart()
        toy.render(end, fps=fps)  # (reads the picture back: the same readback follows)

    def timed(fn) -> float:
        runs = []
        for _ in range(5):
            t = time.perf_counter()
            fn()
            runs.append(time.perf_counter() - t)
        return statistics.median(runs)

    full, carried = timed(every_pass), timed(rendered)
    print(f"{'picture at t = 1 s, 31 frames':>30} | every pass {full * 1e3:8.1f} ms, "
          f"render() {carried * 1e3:8.1f} ms ({full / carried:.1f}x)")


def assembly() -> None:
    """``#include`` expansion of the largest bundled stages (it runs once per program
    compiled) next to the floor of reading the same files' bytes."""
    from facet.gl.glsl_source import expand

    print("\nGLSL assembly: expand() of a stage and its includes (median of 20)")
    print(f"{'stage':>30} | {'lines':>6} {'read ms':>8} {'expand ms':>9} {'ratio':>6}")
    for stage in ("mesh/pbr.frag", "trace/trace.frag", "shadertoy/host.frag"):
        path = ROOT / "glsl" / stage
        source = expand(path)
        files = source.files

        def read(files=files):
            for f in files:
                f.read_bytes()

        floor = median_time(read, 20)
        ms = median_time(lambda path=path: expand(path), 20)
        print(f"{stage:>30} | {len(source.origin):6d} {floor * 1e3:8.3f} {ms * 1e3:9.3f} "
              f"{ms / floor:6.1f}")




if __name__ == "__main__":
    main()
