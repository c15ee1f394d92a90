"""``facet shader``: run a Shadertoy-style fragment shader headlessly (a frame, a GIF/MP4 or
numbered PNGs, with a fixed time step so output is deterministic) or live in a window
(facet.window.shader).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import InputError
from . import args as A

DEFAULT_SIZE = (640, 360)  # frames and the live window alike


def add_parser(sub) -> None:
    sh = sub.add_parser("shader", help="run a Shadertoy or glslViewer fragment shader (window "
                        "or files)",
                        description="Run FILE: a Shadertoy shader (mainImage(out vec4 "
                        "fragColor, in vec2 fragCoord) with iResolution, iTime, iTimeDelta, "
                        "iFrame, iFrameRate, iMouse, iDate, iChannel0-3, iChannelResolution), "
                        "a glslViewer / Book of Shaders one (its own main() writing "
                        "gl_FragColor, reading u_time, u_resolution, u_mouse), a Shadertoy "
                        "JSON export (.json) or a project file (.toml). Without -o it opens a "
                        "window that reloads the files (and their includes) when saved.",
                        formatter_class=argparse.RawDescriptionHelpFormatter,
                        epilog="examples (glsl/examples/ in a checkout):\n"
                        "  facet shader glsl/examples/waves.frag\n"
                        "  facet shader glsl/examples/waves.frag --time 1.5 -o frame.png\n"
                        "  facet shader glsl/examples/sdf.frag --time 0:4 --fps 30 -o sdf.mp4\n"
                        "  facet shader image.frag --buffer-a a.frag --channel a:0=buffer-a "
                        "--channel image:0=buffer-a\n"
                        "  facet shader export.json --media textures/ --time 2 -o f.png\n"
                        "  facet shader book.frag --time 1 -o f.png   # void main(), u_time\n"
                        "  facet shader --list-uniforms glsl/examples/toon.frag")
    sh.add_argument("shader", help="fragment shader (mainImage, or main() glslViewer-style), "
                    "a Shadertoy JSON export, or a .toml project")
    sh.add_argument("-o", "--output", type=A.output_path, metavar="OUT",
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
    sh.add_argument("--cube-a", metavar="FILE",
                    help="Cube A pass (mainCubemap), rendered to a cube map (cube-a)")
    sh.add_argument("--cube-size", type=int, default=512, metavar="N",
                    help="texels along a Cube A face (default 512)")
    sh.add_argument("--common", metavar="FILE", help="code prepended to every pass")
    sh.add_argument("--channel", action="append", default=[], metavar="[PASS:]N=SRC[:OPT]",
                    help="channel N of one pass (image, a-d, cube; default every pass): "
                    "SRC is buffer-a..d, cube-a, keyboard, none, an image, or cube:DIR|IMAGE; "
                    "OPT any of nearest, linear, mipmap, clamp, repeat, vflip, noflip; "
                    "repeatable")
    for i in range(4):
        sh.add_argument(f"--channel{i}", metavar="SRC",
                        help=f"iChannel{i} of every pass that sets no channel {i} of its own")
    sh.add_argument("--media", metavar="DIR", help="where a JSON export's textures are "
                    "(default: beside it)")
    sh.add_argument("--date", metavar="YYYY-MM-DD[THH:MM[:SS]]|now",
                    help="iDate / u_date (default: 2000-01-01 for frames, so they repeat; "
                    "the wall clock in the window)")
    sh.add_argument("--uniform", action="append", default=[], metavar="NAME=V[,V...]",
                    help="set a user uniform; repeatable")
    sh.add_argument("--list-uniforms", action="store_true",
                    help="print the active uniforms with their types and exit")
    sh.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    A.add_confine_option(sh)


def parse_date(text: str):
    """``now`` -> None (the wall clock); ``2024-05-01`` or ``2024-05-01T12:30[:15]``."""
    import datetime

    if text == "now":
        return None
    try:
        return datetime.datetime.fromisoformat(text)
    except ValueError:
        raise InputError(f"--date {text!r}: expected YYYY-MM-DD, YYYY-MM-DDTHH:MM[:SS] or "
                         "now") from None


def _existing_file(path) -> None:
    from ..guard import regular_file

    regular_file(path, "file")


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


def build(args, size, context=None, date="default"):
    from ..lab import project as P
    from ..lab.shadertoy import DEFAULT_DATE, ShaderToy
    from ..lab.shadertoy_json import load_shadertoy_json

    date = parse_date(args.date) if args.date else DEFAULT_DATE if date == "default" else date
    kind = Path(args.shader).suffix.lower()
    loose = [f"--{f.replace('_', '-')}" for f in ("buffer_a", "buffer_b", "buffer_c",
                                                   "buffer_d", "cube_a", "common")
             if getattr(args, f)]
    if kind in (".json", ".toml") and (loose or args.channel or any(
            getattr(args, f"channel{i}") for i in range(4))):
        raise InputError(f"{args.shader}: a {kind[1:].upper()} file brings its own passes "
                         "and channels; leave out --buffer-X, --cube-a, --common and "
                         "--channel")
    if args.media and kind != ".json":
        raise InputError("--media is where a Shadertoy JSON export's textures are; give it "
                         "with a .json file")
    if not 1 <= args.cube_size <= 4096:
        raise InputError(f"--cube-size must be in [1, 4096], got {args.cube_size}")
    common = dict(size=size, context=context, cube_size=args.cube_size, date=date)
    if kind == ".json" or kind == ".toml":
        _existing_file(args.shader)
        project = load_shadertoy_json(args.shader, args.media) if kind == ".json" else \
            P.load_project(args.shader)
        toy = ShaderToy(project=project, **common)
    else:
        buffers = {k: getattr(args, f"buffer_{k}") for k in "abcd"
                   if getattr(args, f"buffer_{k}")}
        channels = {i: getattr(args, f"channel{i}") for i in range(4)
                    if getattr(args, f"channel{i}")}
        per_pass: dict = {}
        for text in args.channel:
            key, n, ch = P.parse_compact(text, "--channel")
            for k in [key] if key else ["image", *buffers, *(["cube"] if args.cube_a else [])]:
                per_pass.setdefault(k, {})[n] = ch
        toy = ShaderToy(args.shader, buffers=buffers, common=args.common, channels=channels,
                        cube=args.cube_a, pass_channels=per_pass, **common)
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

    start, end = A.parse_time(args.time)
    if not A.MIN_FPS <= args.fps <= 240:  # below, a frame's GIF duration overflows
        raise InputError(f"--fps must be in [{A.MIN_FPS:g}, 240], got {args.fps:g}")
    mouse = tuple(args.mouse) + (0.0,) * (4 - len(args.mouse)) if args.mouse else (0,) * 4
    if args.list_uniforms:
        uniforms = mesh_uniforms(args.shader) if is_mesh_stage(args.shader) else None
        if uniforms is None:
            with build(args, args.size or (64, 64)) as toy:
                uniforms = toy.active_uniforms()
        for name, (gl_type, length, filled) in uniforms.items():
            kind = "filled by facet" if filled else "user (--uniform)"
            of_type = f"{gl_type}[{length}]" if length > 1 else gl_type
            print(f"{name:24} {of_type:12} {kind}")  # (the type's column, array or not)
        return []
    if args.output is None:
        from ..window.shader import run_window

        # The window's iDate is the wall clock unless --date fixes it.
        run_window(lambda size, ctx: build(args, size, context=ctx, date=None), args.shader,
                   args.size or DEFAULT_SIZE, args.fps)
        return []
    size = args.size or DEFAULT_SIZE
    if end is None:
        path = check_image_path(args.output)
        with build(args, size) as toy:
            image = toy.render(start, fps=args.fps, mouse=mouse)
        return [save_image(path, _to8(image, str(path)))]
    from ..image.sequence import BackgroundWriter, SequenceSink, check_sequence_path
    from .sequence import progress

    check_sequence_path(args.output)
    from ..options.render import MAX_FRAMES

    frames = int(round((end - start) * args.fps))
    if frames > MAX_FRAMES:  # the same cap as turntables, checked before any work
        raise InputError(f"--time {args.time} at --fps {args.fps:g} is {frames:,} frames; "
                         f"a sequence holds at most {MAX_FRAMES:,}")
    with build(args, size) as toy:
        writer = BackgroundWriter()
        sink = SequenceSink(args.output, args.fps, writer)
        try:
            with progress(frames, args.quiet, "shader") as bar:
                for i in range(frames):
                    sink.add(i, _to8(toy.render(start + i / args.fps, fps=args.fps,
                                                mouse=mouse), f"frame {i}"))
                    bar.update(1)
            written = sink.finish()
            writer.close()
        except BaseException:
            try:
                writer.close()
            except Exception:  # noqa: S110 - what stopped the loop is what is raised: a
                pass  # writer's error after Ctrl-C / SIGTERM must not turn it into exit 1
            finally:
                sink.abort()
            raise
    return sink.written if sink.kind == "pattern" else written


def is_mesh_stage(path) -> bool:
    """A mesh shader: a complete stage (``#version`` first) that is neither Shadertoy code
    (mainImage) nor glslViewer code (gl_FragColor, u_resolution)."""
    import re

    from ..guard import read_text

    try:  # through the guard: a FIFO or a file outside --confine is refused, not opened
        text = read_text(path, "shader file")
    except (OSError, UnicodeDecodeError):
        return False
    lines = [ln.strip() for ln in text.splitlines()]
    first = next((ln for ln in lines if ln and not ln.startswith("//")), "")
    return first.startswith("#version") and not re.search(
        r"\bmainImage\b|\bgl_FragColor\b|\bu_resolution\b", text)


def mesh_uniforms(path) -> dict[str, tuple[str, int, bool]]:
    """Active uniforms of a mesh shader linked with facet's mesh vertex shader."""
    from ..gl.context import create_headless
    from ..gl.glsl_source import glsl_root
    from ..gl.shaders import compile_program
    from ..render.raster.user_shaders import DEFAULT_VERTEX, STANDARD
    from ..render.raster.variant import Variant
    from ..render.state import LIGHT_KIND
    from ..scene.light import DirectionalLight

    ctx = create_headless()
    try:  # linked as the viewer would, for one directional light
        defines = Variant("phong", (LIGHT_KIND[DirectionalLight],)).defines()
        prog = compile_program(ctx, glsl_root() / DEFAULT_VERTEX, Path(path), defines)
        found = {name: (gl_type, length, name in STANDARD)
                 for name, (gl_type, length) in prog.uniform_types().items()}
        prog.release()
        return dict(sorted(found.items()))
    finally:
        ctx.release()


def _to8(image, where: str = "frame"):
    """Shader colour (floats) as 8-bit RGB; alpha is ignored, as on Shadertoy. NaN and
    infinite values are written black and counted in one warning line."""
    import warnings

    import numpy as np

    from ..errors import FacetWarning

    rgb = image[..., :3]
    bad = ~np.isfinite(rgb).all(axis=-1)
    if bad.any():
        warnings.warn(f"{where}: {int(bad.sum())} pixels are NaN or infinite (written black): "
                      "look for divisions by zero, sqrt or log of negative numbers, or "
                      "normalize(vec3(0))", FacetWarning, stacklevel=2)
        rgb = np.where(bad[..., None], 0.0, rgb)
    return np.rint(np.clip(rgb, 0.0, 1.0) * 255.0).astype(np.uint8)
