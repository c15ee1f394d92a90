"""``facet shader``: run a Shadertoy-style fragment shader headlessly (a frame, a GIF/MP4 or
numbered PNGs, with a fixed time step so output is deterministic) or live in a window
(facet.window.shader).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..errors import InputError
from . import args as A

DEFAULT_SIZE = (640, 360)  # frames and the live window alike


def add_parser(sub) -> None:
    sh = sub.add_parser("shader", help="run a Shadertoy-style fragment shader (window or files)",
                        description="Run FILE, a fragment shader defining mainImage(out vec4 "
                        "fragColor, in vec2 fragCoord) with Shadertoy's inputs (iResolution, "
                        "iTime, iTimeDelta, iFrame, iFrameRate, iMouse, iDate, iChannel0-3, "
                        "iChannelResolution). Without -o it opens a window that reloads the "
                        "file (and its includes) when saved.",
                        formatter_class=argparse.RawDescriptionHelpFormatter,
                        epilog="examples (glsl/examples/ in a checkout):\n"
                        "  facet shader glsl/examples/waves.frag\n"
                        "  facet shader glsl/examples/waves.frag --time 1.5 -o frame.png\n"
                        "  facet shader glsl/examples/sdf.frag --time 0:4 --fps 30 -o sdf.mp4\n"
                        "  facet shader image.frag --buffer-a a.frag --channel0 buffer-a\n"
                        "  facet shader --list-uniforms glsl/examples/toon.frag")
    sh.add_argument("shader", help="fragment shader file with mainImage")
    sh.add_argument("-o", "--output", metavar="OUT",
                    help="a .png (one frame at --time), or .gif / .mp4 / frames/{:04d}.png "
                    "for a --time range")
    sh.add_argument("--time", default="0", metavar="T|A:B",
                    help="seconds for one frame, or a range start:end (default 0)")
    sh.add_argument("--fps", type=float, default=30.0, help="frames per second (default 30)")
    sh.add_argument("--size", type=A.size, metavar="WxH",
                    help=f"{A.SIZE_HELP}, of the frames and of the window (default "
                    f"{DEFAULT_SIZE[0]}x{DEFAULT_SIZE[1]})")
    sh.add_argument("--mouse", type=lambda t: A.floats(t, (2, 4), "mouse"),
                    metavar="X,Y[,CX,CY]", help="iMouse for headless frames (pixels)")
    for key in "abcd":
        sh.add_argument(f"--buffer-{key}", metavar="FILE", help=f"buffer {key.upper()} pass")
    sh.add_argument("--common", metavar="FILE", help="code prepended to every pass")
    for i in range(4):
        sh.add_argument(f"--channel{i}", metavar="IMAGE|buffer-X",
                        help=f"iChannel{i}: an image file or a buffer (buffer-a ... buffer-d)")
    sh.add_argument("--uniform", action="append", default=[], metavar="NAME=V[,V...]",
                    help="set a user uniform; repeatable")
    sh.add_argument("--list-uniforms", action="store_true",
                    help="print the active uniforms with their types and exit")
    sh.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")


def parse_time(text: str) -> tuple[float, float | None]:
    """``1.5`` -> (1.5, None); ``0:4`` -> (0.0, 4.0)."""
    try:
        if ":" in text:
            a, b = (float(v) for v in text.split(":"))
            if not (math.isfinite(a) and math.isfinite(b)) or b <= a or a < 0:
                raise ValueError
            return a, b
        t = float(text)
        if not math.isfinite(t) or t < 0:
            raise ValueError
        return t, None
    except ValueError:
        raise InputError(f"--time {text!r}: expected seconds like 1.5 or a range like 0:4 "
                         "(start < end, both >= 0)") from None


def parse_uniform(text: str) -> tuple[str, list[float]]:
    name, _, values = text.partition("=")
    try:
        numbers = [float(v) for v in values.split(",")]
    except ValueError:
        numbers = []
    if not name.isidentifier() or not values or not numbers:
        raise InputError(f"--uniform {text!r}: expected NAME=VALUE[,VALUE...], like "
                         "u_color=1,0.5,0")
    return name, numbers


def build(args, size, context=None):
    from ..lab.shadertoy import ShaderToy

    buffers = {k: getattr(args, f"buffer_{k}") for k in "abcd" if getattr(args, f"buffer_{k}")}
    channels = {i: getattr(args, f"channel{i}") for i in range(4)
                if getattr(args, f"channel{i}")}
    toy = ShaderToy(args.shader, buffers=buffers, common=args.common, channels=channels,
                    size=size, context=context)
    try:
        for text in args.uniform:
            toy.set_uniform(*parse_uniform(text))
    except BaseException:
        toy.close()
        raise
    return toy


def run(args) -> list[Path]:
    """Headless output or the uniform list; the window when there is no -o."""
    from ..image.writers import check_image_path, save_image

    start, end = parse_time(args.time)
    if not 0 < args.fps <= 240:
        raise InputError(f"--fps must be in (0, 240], got {args.fps:g}")
    mouse = tuple(args.mouse) + (0.0,) * (4 - len(args.mouse)) if args.mouse else (0,) * 4
    if args.list_uniforms:
        uniforms = mesh_uniforms(args.shader) if is_mesh_stage(args.shader) else None
        if uniforms is None:
            with build(args, args.size or (64, 64)) as toy:
                uniforms = toy.active_uniforms()
        for name, (gl_type, length, filled) in uniforms.items():
            kind = "filled by facet" if filled else "user (--uniform)"
            print(f"{name:24} {gl_type}{f'[{length}]' if length > 1 else '':6} {kind}")
        return []
    if args.output is None:
        from ..window.shader import run_window

        run_window(lambda size, ctx: build(args, size, context=ctx), args.shader,
                   args.size or DEFAULT_SIZE, args.fps)
        return []
    size = args.size or DEFAULT_SIZE
    if end is None:
        path = check_image_path(args.output)
        with build(args, size) as toy:
            image = toy.render(start, fps=args.fps, mouse=mouse)
        return [save_image(path, _to8(image))]
    from ..image.sequence import BackgroundWriter, SequenceSink, check_sequence_path
    from .sequence import progress

    check_sequence_path(args.output)
    with build(args, size) as toy:
        frames = int(round((end - start) * args.fps))
        writer = BackgroundWriter()
        sink = SequenceSink(args.output, args.fps, writer)
        try:
            with progress(frames, args.quiet, "shader") as bar:
                for i in range(frames):
                    sink.add(i, _to8(toy.render(start + i / args.fps, fps=args.fps,
                                                mouse=mouse)))
                    bar.update(1)
            written = sink.finish()
            writer.close()
        except BaseException:
            try:
                writer.close()
            finally:
                sink.abort()
            raise
    return sink.written if sink.kind == "pattern" else written


def is_mesh_stage(path) -> bool:
    """A complete stage (``#version`` first) is a mesh shader; Shadertoy code has none."""
    try:
        lines = [ln.strip() for ln in Path(path).read_text(encoding="utf-8").splitlines()]
    except (OSError, UnicodeDecodeError):
        return False
    first = next((ln for ln in lines if ln and not ln.startswith("//")), "")
    return first.startswith("#version")


def mesh_uniforms(path) -> dict[str, tuple[str, int, bool]]:
    """Active uniforms of a mesh shader linked with facet's mesh vertex shader."""
    from ..gl.context import create_headless
    from ..gl.glsl_source import glsl_root
    from ..gl.shaders import compile_program
    from ..lab.mesh_shaders import DEFAULT_VERTEX, STANDARD

    ctx = create_headless()
    try:
        prog = compile_program(ctx, glsl_root() / DEFAULT_VERTEX, Path(path),
                               {"MAX_LIGHTS": 16, "LIGHT_COUNT": 1,
                                "LIGHT_KIND_LIST": "int[1](0)"})
        found = {name: (gl_type, length, name in STANDARD)
                 for name, (gl_type, length) in prog.uniform_types().items()}
        prog.release()
        return dict(sorted(found.items()))
    finally:
        ctx.release()


def _to8(image):
    """Shader colour (floats) as 8-bit RGB; alpha is ignored, as on Shadertoy."""
    import numpy as np

    return np.rint(np.clip(image[..., :3], 0.0, 1.0) * 255.0).astype(np.uint8)
