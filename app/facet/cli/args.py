"""Argument types and the option groups the subcommands share (no numpy, no GL: ``--help``
stays instant). The render options (``add_render_options``) are taken as the text given,
unchecked, and become one explicit layer of facet.options.render through ``render_layer``:
a flag and a scene file's key are parsed by the same function and refused with the same
sentence."""

from __future__ import annotations

import argparse
import math

SIZE_HELP = "image size in pixels, WIDTHxHEIGHT"
# What happens to MSAA counts the GL cannot do (facet.options.render.clamp_msaa).
MSAA_POLICY = "counts above the GL's maximum are lowered to it with a warning"


def floats(text: str, n: tuple[int, ...], what: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) not in n or not all(math.isfinite(v) for v in values):
        want = " or ".join(str(k) for k in n)
        raise argparse.ArgumentTypeError(f"{what}: expected {want} comma-separated numbers, "
                                         f"got {text!r}")
    return values


MIN_FPS = 0.01  # one frame per 100 s: slower has no use, and overflows a GIF's frame time


def output_path(text: str) -> str:
    """An output file or folder named on the command line: never empty (an empty name
    would quietly fall back to the default file)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty output path; name a file, e.g. -o out.png")
    if "\0" in text:
        raise argparse.ArgumentTypeError(f"output path {text!r}: contains a NUL byte")
    return text


def vec3(text: str) -> list[float]:
    return floats(text, (3,), "vector")


def color(text: str) -> list[float]:
    values = floats(text, (3,), "colour")
    if min(values) < 0 or max(values) > 1:
        raise argparse.ArgumentTypeError(f"colour {text!r}: each channel must be in [0, 1]")
    return values


def size(text: str) -> tuple[int, int]:
    """WIDTHxHEIGHT, checked by the render options' own parser (the same sentence)."""
    from ..errors import InputError
    from ..options.values import parse_option

    try:
        return parse_option("size", text)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def light(text: str):
    """Parse a --light spec (see facet render --help) into a facet light."""
    from ..scene.light import DirectionalLight, PointLight, SpotLight

    kind, _, rest = text.partition(":")
    fields = rest.split(":") if rest else []
    shapes = {"dir": 1, "directional": 1, "point": 1, "spot": 2}
    if kind not in shapes or len(fields) < shapes[kind]:
        raise argparse.ArgumentTypeError(
            f"light {text!r}: expected dir:DX,DY,DZ, point:X,Y,Z or spot:X,Y,Z:DX,DY,DZ "
            "(optionally followed by :R,G,B:INTENSITY)")
    geo = [vec3(f) for f in fields[:shapes[kind]]]
    extra = fields[shapes[kind]:]
    if len(extra) > (3 if kind == "spot" else 2):
        raise argparse.ArgumentTypeError(f"light {text!r}: too many ':' fields")
    rgb = color(extra[0]) if extra else [1.0, 1.0, 1.0]
    intensity = floats(extra[1], (1,), f"light {text!r} intensity")[0] if len(extra) > 1 \
        else 1.0
    try:
        if kind in ("dir", "directional"):
            return DirectionalLight(direction=geo[0], color=rgb, intensity=intensity)
        if kind == "point":
            return PointLight(position=geo[0], color=rgb, intensity=intensity)
        angle = floats(extra[2], (1,), f"light {text!r} angle")[0] if len(extra) > 2 else 30.0
        return SpotLight(position=geo[0], direction=geo[1], color=rgb, intensity=intensity,
                         inner_angle=0.8 * angle, outer_angle=angle)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"light {text!r}: {exc}") from None


def add_confine_option(p) -> None:
    p.add_argument("--confine", metavar="DIR",
                   help="read files only inside DIR (symbolic links resolved): what a scene, "
                   "glTF, OBJ or shader names elsewhere is refused")


def add_shader_options(p) -> None:
    """--frag / --vert / --uniform: the model's own GLSL (docs in facet.scene.shader)."""
    p.add_argument("--frag", metavar="FILE", help="the model's own fragment shader "
                   "(see glsl/examples/, e.g. toon.frag)")
    p.add_argument("--vert", metavar="FILE", help="the model's own vertex shader")
    p.add_argument("--uniform", action="append", default=[], metavar="NAME=V[,V...]",
                   help="a uniform of --frag/--vert; repeatable")


def add_render_options(p, size_default: str) -> None:
    """The render options of ``facet render`` and ``facet view``. Each one left out takes
    the scene file's [render] value, else facet's default."""
    from ..options.render import (
        ENGINES,
        MSAA_CHOICES,
        PCF_CHOICES,
        SHADING,
    )
    from ..render.capabilities import CAPABILITIES

    g = p.add_argument_group("render options (a flag overrides the scene file's [render] "
                             "value, which overrides the default)")
    g.add_argument("--size", metavar="WxH",
                   help=f"{SIZE_HELP} (default: {size_default})")
    g.add_argument("--shading", metavar="MODEL",
                   help=f"shading model: {', '.join(SHADING)} (default auto: pbr for "
                   "glTF's metallic-roughness materials, phong for the others)")
    g.add_argument("--msaa", metavar="N",
                   help=f"multisample anti-aliasing for colour: "
                   f"{', '.join(map(str, MSAA_CHOICES))} (default 4; {MSAA_POLICY})")
    g.add_argument("--aa", metavar="MODE",
                   help="anti-aliasing: none, msaa:N, or supersampling ssaa:PATTERN:N (also "
                   "PATTERN:N) with PATTERN grid, random, poisson or jittered, e.g. "
                   "--aa jittered:16 (colour only; depth and ids stay exact)")
    g.add_argument("--engine", metavar="ENGINE",
                   help=f"{' or '.join(ENGINES)}. raster: the rasterizer (default); trace: "
                   "the GPU ray tracer (shadow rays, reflection and refraction rays, exact "
                   "shapes); path: the path tracer (light bounced between surfaces, "
                   "emitting surfaces, glass; linear radiance)")
    g.add_argument("--max-depth", metavar="N",
                   help="the tracers' bounces: the ray tracer's reflection/refraction "
                   f"depth (default {CAPABILITIES['trace'].max_depth}; 1 is one reflection "
                   "and one transmission ray), the path tracer's bounces after the eye ray "
                   f"(default {CAPABILITIES['path'].max_depth})")
    g.add_argument("--seed", metavar="N",
                   help="the random stream (path tracer, jittered patterns): the same seed "
                   "gives the same picture (default 0)")
    g.add_argument("--denoise", action=argparse.BooleanOptionalAction,
                   help="the path tracer's picture through Intel Open Image Denoise "
                   "(fed albedo and normals; pip install 'facet-render[denoise]'); the exact "
                   "channels stay as traced (default: off)")
    g.add_argument("--spp", metavar="N",
                   help="samples per pixel, jittered (the same as --aa jittered:N); with "
                   "--noise or --time-limit the most a pixel takes")
    g.add_argument("--noise", metavar="T",
                   help="adaptive sampling (path tracer): a pixel stops once the estimated "
                   "relative error of its mean is below T (e.g. 0.01), after 16 paths; at "
                   "most --spp (default 4096)")
    g.add_argument("--time-limit", metavar="S",
                   help="the picture reached in S seconds of sampling (at most --spp; the "
                   "path tracer takes up to 4096 paths per pixel when --spp is not given)")
    g.add_argument("--shadows", action=argparse.BooleanOptionalAction,
                   help="shadows from every light: shadow maps when rasterizing (default "
                   "off), shadow rays when tracing (default on)")
    g.add_argument("--pcf", metavar="R",
                   help="shadow filter kernel radius in texels: "
                   f"{', '.join(map(str, PCF_CHOICES))}: 0 (one tap), 1 (3x3, default), 2 "
                   "(5x5)")
    g.add_argument("--srgb", action=argparse.BooleanOptionalAction,
                   help="colour management: treat input colours and textures as sRGB, light "
                   "in linear space, write sRGB (default: the shading value as is)")
    g.add_argument("--background", metavar="R,G,B[,A]",
                   help="background colour; A=0 for transparent (default: the scene's, "
                   "else 0,0,0)")
    _add_view_options(g)


def _add_view_options(g) -> None:
    """The render options about the view, the scene's lights and time (add_render_options)."""
    from ..options.render import CULL, LIGHTS

    g.add_argument("--camera", metavar="NAME",
                   help="which camera to render through: a scene file's or a model's own, "
                        "by name, 'first' or index (facet info lists them)")
    g.add_argument("--lights", metavar="MODE",
                   help=f"{', '.join(LIGHTS)}. auto: the scene's lights, or a key + fill rig "
                   "following the camera when it has none (default); scene: only its own; "
                   "camera: the rig always")
    g.add_argument("--wireframe", action=argparse.BooleanOptionalAction,
                   help="draw the triangle edges over the picture")
    g.add_argument("--aperture", metavar="A",
                   help="depth of field: lens diameter in scene units (needs a focus)")
    g.add_argument("--focus", metavar="F",
                   help="depth of field: distance along the view that stays sharp")
    g.add_argument("--cull", metavar="MODE",
                   help=f"back-face culling, {', '.join(CULL)}: auto (default: closed opaque "
                   "meshes seen from outside, where it cannot change the picture), on (every "
                   "opaque object), off")
    g.add_argument("--up", metavar="x|y|z|X,Y,Z",
                   help="the world's up axis: the default camera frames the model and "
                   "turntables orbit around it (default y; CAD and scanner files are often "
                   "z: --up z)")
    g.add_argument("--time", metavar="T|A:B",
                   help="seconds: where the model's animations stand (and users' shaders' "
                   "u_time; default 0). A:B plays them from A to B: 'facet render' writes a "
                   "sequence of (B - A) x --fps frames (GIF, MP4 or a PNG pattern), or "
                   "spreads A..B over a --turntable's frames; 'facet view' loops A..B")
    g.add_argument("--animation", metavar="NAME|INDEX",
                   help="which of the model's animations plays (default: the first, as "
                   "glTF viewers play it; 'all': every clip at once; 'facet info' lists them)")
    g.add_argument("--shutter", metavar="S",
                   help="motion blur: the shutter stays open S seconds from --time and the "
                   "animations blur as they move (supersampled; default 0)")
    g.add_argument("--variant", metavar="NAME|SET=NAME,...",
                   help="a glTF material variant (KHR_materials_variants), or an OpenUSD "
                   "stage's variant selections SET=NAME[,SET=NAME] ('facet info' lists "
                   "both; default: the file's own)")
    g.add_argument("--env", metavar="sky|IMAGE|DIR",
                   help="environment: a generated sky, an equirectangular image, or a folder "
                   "of six cube faces (px nx py ny pz nz); background and reflections")


def add_model_options(p) -> None:
    """How model files are read (facet.formats.loading)."""
    from ..options.render import DEFAULT_CREASE

    p.add_argument("--crease", type=float, metavar="DEG",
                   help="for files without normals: split vertices where neighbouring faces "
                   f"meet at more than DEG degrees (default {DEFAULT_CREASE:g}; 180 = all "
                   "smooth, 0 = faceted)")
    p.add_argument("--point-size", type=float, metavar="PX",
                   help="point clouds: discs PX pixels across (default 3)")
    p.add_argument("--point-radius", type=float, metavar="R",
                   help="point clouds: discs of radius R in scene units (they shrink with "
                   "distance), instead of --point-size")
    p.add_argument("--line-width", type=float, metavar="PX",
                   help="lines (glTF LINES, OBJ l): PX pixels wide (default 1.5)")
    p.add_argument("--no-payloads", action="store_true",
                   help="OpenUSD: compose the stage without loading its payloads")
    p.add_argument("--purpose", metavar="LIST",
                   help="OpenUSD: the purposes drawn, from default, render, proxy, guide "
                   "(default: default,render)")
    p.add_argument("--subdivide", type=int, metavar="LEVEL",
                   help="OpenUSD: refine subdivision surfaces LEVEL times (Catmull-Clark, "
                   "Loop; default 0: the control cage, as usdview draws it)")
    p.add_argument("--joints", metavar="NAME=VALUE,...",
                   help="URDF: the joint configuration (radians, metres; within the limits; "
                   "'facet info' lists the joints)")
    p.add_argument("--package-path", action="append", metavar="DIR",
                   help="URDF: where package:// names are found (repeatable; then "
                   "ROS_PACKAGE_PATH)")
    p.add_argument("--collision", action="store_true",
                   help="URDF: draw the collision geometry instead of the visual")


PURPOSES = ("default", "render", "proxy", "guide")


def stage_options(args) -> dict:
    """open_scene's OpenUSD and URDF arguments from the command line (variants given as
    SET=NAME, --no-payloads, --purpose; --joints, --package-path, --collision); empty when
    none is given."""
    from ..errors import InputError

    out: dict = {}
    variant = getattr(args, "variant", None)
    if variant and "=" in variant:
        chosen = {}
        for item in variant.split(","):
            name, eq, value = item.partition("=")
            if not eq or not name.strip() or not value.strip():
                raise InputError(f"--variant {variant!r}: expected SET=NAME[,SET=NAME] for "
                                 "an OpenUSD stage, or one glTF variant's name")
            chosen[name.strip()] = value.strip()
        out["variants"] = chosen
    if getattr(args, "no_payloads", False):
        out["payloads"] = False
    purpose = getattr(args, "purpose", None)
    if purpose:
        names = tuple(p.strip() for p in purpose.split(",") if p.strip())
        bad = [p for p in names if p not in PURPOSES]
        if bad or not names:
            raise InputError(f"--purpose {purpose!r}: expected purposes from "
                             f"{', '.join(PURPOSES)}, separated by commas")
        out["purposes"] = names
    level = getattr(args, "subdivide", None)
    if level is not None:
        from ..formats.subdivide import MAX_LEVEL

        if not 0 <= level <= MAX_LEVEL:
            raise InputError(f"--subdivide {level}: expected a level from 0 to {MAX_LEVEL}")
        if level:
            out["subdivide"] = level
    joints = getattr(args, "joints", None)
    if joints:
        values = {}
        for item in joints.split(","):
            name, eq, value = item.partition("=")
            try:
                number = float(value)
            except ValueError:
                number = None
            if not eq or not name.strip() or number is None or not math.isfinite(number):
                raise InputError(f"--joints {joints!r}: expected NAME=VALUE[,NAME=VALUE] with "
                                 "numbers (radians, metres)")
            values[name.strip()] = number
        out["joints"] = values
    if getattr(args, "package_path", None):
        out["package_path"] = tuple(args.package_path)
    if getattr(args, "collision", False):
        out["collision"] = True
    return out


def sprite_sizes(args) -> dict:
    """The point and line sizes the command line gives (facet.scene.points)."""
    return {"point_size": getattr(args, "point_size", None),
            "point_radius": getattr(args, "point_radius", None),
            "line_width": getattr(args, "line_width", None)}



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
        from ..errors import InputError

        raise InputError(f"--time {text!r}: expected seconds like 1.5 or a range like 0:4 "
                         "(start < end, both >= 0)") from None


def time_range(args) -> tuple[str | None, float | None]:
    """(--time's start as the option's raw text, or None; its end for A:B, else None)."""
    text = getattr(args, "time", None)
    if text is None or ":" not in text:
        return text, None
    start, end = parse_time(text)
    return repr(start), end


def render_layer(args) -> dict:
    """The render options the command line gives, raw (None: not given): parsed with
    every other layer by facet.options.render."""
    from ..options.render import text_layer

    return text_layer({
            "time": time_range(args)[0], "animation": args.animation,
            "variant": None if args.variant and "=" in args.variant else args.variant,
            "shutter": args.shutter,
            "size": args.size, "shading": args.shading, "msaa": args.msaa, "aa": args.aa,
            "spp": args.spp, "engine": args.engine, "max_depth": args.max_depth,
            "seed": args.seed, "denoise": args.denoise, "noise": args.noise,
            "time_limit": args.time_limit,
            "shadows": args.shadows, "pcf": args.pcf, "srgb": args.srgb,
            "background": args.background, "camera": args.camera, "lights": args.lights,
            "wireframe": args.wireframe, "aperture": args.aperture, "focus": args.focus,
            "environment": args.env, "up": args.up, "cull": args.cull})
