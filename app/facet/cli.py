"""The ``facet`` command line: ``facet render`` and ``facet info``.

A user's mistake prints one line ``facet: error: ...`` on stderr and exits with status 2,
leaving no output file. Heavy modules (numpy, trimesh, moderngl, Pillow) are imported inside
the commands, so ``facet --help`` starts instantly and each command loads only what it uses.
"""

from __future__ import annotations

import argparse
import sys

EXIT_USAGE = 2

RENDER_EPILOG = """\
conventions:
  world axes are right-handed with y up; the camera looks down its -z axis.
  images have row 0 at the top. --depth writes linear depth along the camera axis in scene
  units, float32, 0 where nothing was hit (perspective and --ortho alike).
  colours are floats in [0, 1]. Angles are in degrees.

lights (repeat --light for several; default: a key and a fill light set from the camera):
  dir:DX,DY,DZ[:R,G,B[:INTENSITY]]             directional; D is where the light travels
  point:X,Y,Z[:R,G,B[:INTENSITY]]              point light at X,Y,Z
  spot:X,Y,Z:DX,DY,DZ[:R,G,B[:INTENSITY[:DEG]]] spot light, cone half-angle DEG (default 30)

examples:
  facet render bunny.obj -o bunny.png
  facet render bunny.obj -o bunny.png --size 1280x720 --msaa 4 --depth bunny-depth.npy
  facet render part.stl -o part.png --ortho --shading flat --light dir:-1,-2,-1
  facet render bunny.obj --outputs color,depth,normals,ids --out-dir renders/ --png16
  facet render bunny.obj -o banding.png --bits 4 --dither floyd-steinberg
  facet render scene.toml --camera top -o top.png
  facet render bunny.obj --turntable 36 -o spin.gif

Every render also writes its camera as JSON beside the image (K, world-to-camera, near/far,
size): OUT.json for -o OUT.png, camera.json in --out-dir.
"""


class _Parser(argparse.ArgumentParser):
    """argparse that reports a usage error in one line (plus where to find help)."""

    def error(self, message: str):
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _floats(text: str, n: tuple[int, ...], what: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    import math

    if len(values) not in n or not all(math.isfinite(v) for v in values):
        want = " or ".join(str(k) for k in n)
        raise argparse.ArgumentTypeError(f"{what}: expected {want} comma-separated numbers, "
                                         f"got {text!r}")
    return values


def _vec3(text: str) -> list[float]:
    return _floats(text, (3,), "vector")


def _color(text: str) -> list[float]:
    values = _floats(text, (3,), "colour")
    if min(values) < 0 or max(values) > 1:
        raise argparse.ArgumentTypeError(f"colour {text!r}: each channel must be in [0, 1]")
    return values


def _background(text: str) -> list[float]:
    values = _floats(text, (3, 4), "background")
    if min(values) < 0 or max(values) > 1:
        raise argparse.ArgumentTypeError(f"background {text!r}: each channel must be in [0, 1]")
    return values


def _size(text: str) -> tuple[int, int]:
    parts = text.lower().split("x")
    try:
        w, h = (int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"size: expected WIDTHxHEIGHT like 800x600, "
                                         f"got {text!r}") from None
    if w < 1 or h < 1:
        raise argparse.ArgumentTypeError(f"size {text!r}: width and height must be >= 1")
    return w, h


def _light(text: str):
    """Parse a --light spec (see RENDER_EPILOG) into a facet light."""
    from .scene.light import DirectionalLight, PointLight, SpotLight

    kind, _, rest = text.partition(":")
    fields = rest.split(":") if rest else []
    shapes = {"dir": 1, "directional": 1, "point": 1, "spot": 2}
    if kind not in shapes or len(fields) < shapes[kind]:
        raise argparse.ArgumentTypeError(
            f"light {text!r}: expected dir:DX,DY,DZ, point:X,Y,Z or spot:X,Y,Z:DX,DY,DZ "
            "(optionally followed by :R,G,B:INTENSITY)")
    geo = [_vec3(f) for f in fields[:shapes[kind]]]
    extra = fields[shapes[kind]:]
    max_extra = 3 if kind == "spot" else 2
    if len(extra) > max_extra:
        raise argparse.ArgumentTypeError(f"light {text!r}: too many ':' fields")
    color = _color(extra[0]) if extra else [1.0, 1.0, 1.0]
    intensity = _floats(extra[1], (1,), f"light {text!r} intensity")[0] if len(extra) > 1 \
        else 1.0
    try:
        if kind in ("dir", "directional"):
            return DirectionalLight(direction=geo[0], color=color, intensity=intensity)
        if kind == "point":
            return PointLight(position=geo[0], color=color, intensity=intensity)
        angle = _floats(extra[2], (1,), f"light {text!r} angle")[0] if len(extra) > 2 else 30.0
        return SpotLight(position=geo[0], direction=geo[1], color=color, intensity=intensity,
                         inner_angle=0.8 * angle, outer_angle=angle)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"light {text!r}: {exc}") from None


def _shader_options(p) -> None:
    """--frag / --vert / --uniform: the model's own GLSL (docs in facet.scene.shader)."""
    p.add_argument("--frag", metavar="FILE", help="the model's own fragment shader "
                   "(see glsl/examples/, e.g. toon.frag)")
    p.add_argument("--vert", metavar="FILE", help="the model's own vertex shader")
    p.add_argument("--uniform", action="append", default=[], metavar="NAME=V[,V...]",
                   help="a uniform of --frag/--vert; repeatable")


def build_parser() -> argparse.ArgumentParser:
    from .render.shading import SHADING_MODELS

    SHADING_CHOICES = tuple(SHADING_MODELS)

    parser = _Parser(prog="facet", description="facet: headless GPU rendering of meshes with "
                     "Phong shading (OpenGL through EGL; Mesa llvmpipe when there is no GPU).")
    parser.add_argument("--version", action="version", version="facet 0.1.0")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    r = sub.add_parser("render", help="render a mesh to a PNG (and depth to .npy)",
                       description="Render MODEL (OBJ, STL, PLY, OFF, GLB/glTF) headlessly to "
                       "an image. Without MODEL, renders facet's bundled default model.",
                       epilog=RENDER_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("model", nargs="?", help="mesh file or .toml scene file (default: the "
                   "bundled torus knot)")
    r.add_argument("-o", "--output", metavar="OUT.png",
                   help="image to write (default: MODEL's name with .png, in the current folder)")
    r.add_argument("--size", type=_size, metavar="WxH",
                   help="image size in pixels (default: the scene file's, else 800x600)")
    r.add_argument("--eye", type=_vec3, metavar="X,Y,Z",
                   help="camera position (default: framed to fit the model)")
    r.add_argument("--target", type=_vec3, metavar="X,Y,Z",
                   help="point the camera looks at (default: the model's centre)")
    r.add_argument("--up", type=_vec3, default=[0.0, 1.0, 0.0], metavar="X,Y,Z",
                   help="camera up direction (default 0,1,0)")
    r.add_argument("--fov", type=float, default=40.0, metavar="DEG",
                   help="vertical field of view in degrees (default 40)")
    r.add_argument("--ortho", action="store_true",
                   help="parallel (orthographic) projection, sized to fit the model")
    r.add_argument("--light", type=_light, action="append", default=[], metavar="KIND:...",
                   help="add a light (see below); repeatable")
    r.add_argument("--color", type=_color, metavar="R,G,B",
                   help="material colour, floats in [0, 1] (default: the file's or grey)")
    r.add_argument("--texture", metavar="IMAGE|checker",
                   help="diffuse texture for the model (needs texture coordinates); "
                   "'checker' generates a checkerboard")
    r.add_argument("--srgb", action="store_true",
                   help="colour management: treat input colours and textures as sRGB, light "
                   "in linear space, write sRGB (default: the shading value as is)")
    r.add_argument("--shading", choices=SHADING_CHOICES, metavar="MODEL",
                   help=f"shading model: {', '.join(SHADING_CHOICES)} (default phong)")
    r.add_argument("--msaa", type=int, choices=(0, 2, 4, 8), metavar="N",
                   help="multisample anti-aliasing samples for colour: 0, 2, 4 or 8 (default 4)")
    r.add_argument("--aperture", type=float, default=0.0, metavar="A",
                   help="depth of field: lens diameter in scene units (needs --focus)")
    r.add_argument("--focus", type=float, metavar="F",
                   help="depth of field: distance along the view that stays sharp")
    r.add_argument("--env", metavar="sky|IMAGE|DIR",
                   help="environment: a generated sky, an equirectangular image, or a folder "
                   "of six cube faces (px nx py ny pz nz); background and reflections")
    r.add_argument("--shadows", action="store_true",
                   help="shadow maps for directional, spot and point lights")
    r.add_argument("--pcf", type=int, default=1, choices=(0, 1, 2), metavar="R",
                   help="shadow filter kernel radius in texels: 0 (one tap), 1 (3x3, "
                   "default), 2 (5x5)")
    r.add_argument("--aa", metavar="MODE",
                   help="anti-aliasing: none, msaa:N, or supersampling ssaa:PATTERN:N (also "
                   "PATTERN:N) with PATTERN grid, random, poisson or jittered, e.g. "
                   "--aa jittered:16 (colour only; depth and ids stay exact)")
    r.add_argument("--background", type=_background, metavar="R,G,B[,A]",
                   help="background colour; A=0 for transparent (default 0,0,0)")
    r.add_argument("--camera", metavar="NAME", help="which of the scene file's cameras to use")
    r.add_argument("--turntable", type=int, metavar="N",
                   help="render N frames orbiting the model; -o takes .gif, .mp4 or a "
                   "pattern like frames/{:04d}.png")
    r.add_argument("--fps", type=float, default=30.0,
                   help="frame rate of GIF/MP4 turntables (default 30)")
    r.add_argument("--depth", metavar="OUT.npy", help="also write linear depth (float32 .npy)")
    r.add_argument("--ids", metavar="OUT.npy",
                   help="also write object ids (int32 .npy, -1 = background)")
    out = r.add_argument_group("dataset outputs and colour quantisation")
    out.add_argument("--outputs", metavar="LIST",
                     help="channels to write into --out-dir: any of color,depth,ids,normals,"
                     "position,uv (default color)")
    out.add_argument("--out-dir", metavar="DIR", help="write each channel as files in DIR "
                     "(PNG, exact .npy, previews, camera.json) instead of -o")
    out.add_argument("--png16", action="store_true",
                     help="also write depth in millimetres and normals as 16-bit PNG")
    out.add_argument("--normals-space", choices=("world", "camera"), default="world",
                     help="space of the normals output (default world)")
    out.add_argument("--bits", default="8", metavar="N|R,G,B",
                     help="colour bits per channel: 8 (default), 16 (16-bit PNG), three values "
                     "like 5,6,5, or one value below 8 for grey (e.g. 4)")
    out.add_argument("--dither", default="none",
                     choices=("none", "bayer4", "bayer8", "floyd-steinberg"),
                     help="dithering when reducing bits or palettes (default none)")
    out.add_argument("--palette", type=int, metavar="N",
                     help="reduce the colour image to N colours (2..256)")
    out.add_argument("--palette-method", choices=("median-cut", "kmeans"),
                     default="median-cut", help="palette method (default median-cut)")
    r.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    _shader_options(r)
    v = sub.add_parser("view", help="open a model or scene file in an interactive window",
                       description="Explore MODEL (a mesh or .toml scene file) in a window. "
                       "Drag to orbit, right-drag to pan, scroll to zoom; press h for keys.",
                       epilog=_viewer_keys(), formatter_class=argparse.RawDescriptionHelpFormatter)
    v.add_argument("model", nargs="?", help="mesh file or .toml scene file (default: the "
                   "bundled torus knot)")
    v.add_argument("--size", type=_size, default=(1280, 720), metavar="WxH",
                   help="window size (default 1280x720)")
    v.add_argument("--msaa", type=int, default=4, choices=(0, 2, 4, 8), metavar="N",
                   help="multisampling: 0, 2, 4 or 8 (default 4, capped by the driver)")
    _shader_options(v)
    sh = sub.add_parser("shader", help="run a Shadertoy-style fragment shader (window or files)",
                        description="Run FILE, a fragment shader defining mainImage(out vec4 "
                        "fragColor, in vec2 fragCoord) with Shadertoy's inputs (iResolution, "
                        "iTime, iTimeDelta, iFrame, iFrameRate, iMouse, iDate, iChannel0-3, "
                        "iChannelResolution). Without -o it opens a window that reloads the "
                        "file (and its includes) when saved.",
                        formatter_class=argparse.RawDescriptionHelpFormatter,
                        epilog="examples:\n  facet shader wave.frag\n"
                        "  facet shader wave.frag --time 1.5 -o frame.png\n"
                        "  facet shader wave.frag --time 0:4 --fps 30 -o wave.mp4\n"
                        "  facet shader image.frag --buffer-a a.frag --channel0 buffer-a\n"
                        "  facet shader --list-uniforms toon.frag")
    sh.add_argument("shader", help="fragment shader file with mainImage")
    sh.add_argument("-o", "--output", metavar="OUT",
                    help="a .png (one frame at --time), or .gif / .mp4 / frames/{:04d}.png "
                    "for a --time range")
    sh.add_argument("--time", default="0", metavar="T|A:B",
                    help="seconds for one frame, or a range start:end (default 0)")
    sh.add_argument("--fps", type=float, default=30.0, help="frames per second (default 30)")
    sh.add_argument("--size", type=_size, metavar="WxH", help="image size (default 640x360)")
    sh.add_argument("--mouse", type=lambda t: _floats(t, (2, 4), "mouse"),
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
    sub.add_parser("info", help="print the OpenGL vendor, renderer, version and limits",
                   description="Create a headless context and print what it offers.")
    return parser


def _viewer_keys() -> str:
    from .viewer_keys import help_text

    return help_text()


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    from .errors import FacetError

    try:
        if args.command == "render":
            from .render_command import run_render

            for path in run_render(args):
                if not args.quiet:
                    print(path)
        elif args.command == "view":
            from .paths import default_model
            from .render_command import user_shader
            from .viewer import view

            view(args.model or default_model(), size=args.size, msaa=args.msaa,
                 shader=user_shader(args))
        elif args.command == "shader":
            from .shader_command import run_shader

            for path in run_shader(args):
                if not args.quiet:
                    print(path)
        elif args.command == "info":
            from .gl.context import create_headless, describe

            ctx = create_headless()
            for key, value in describe(ctx).items():
                print(f"{key:22} {value}")
            ctx.release()
    except FacetError as exc:
        print(f"facet: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:  # unwritable output folder, disk full, ...
        name = f"{exc.filename}: " if exc.filename else ""
        print(f"facet: error: {name}{exc.strerror or exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        return 130
    return 0
