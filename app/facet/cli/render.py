"""``facet render``: from parsed command-line arguments to files on disk.

The render options come from one place (facet.options.render.options_for): the flags, then
the scene file's [render] table, then facet's defaults. Outputs are validated before any
work, and each file is written atomically; sequences (turntables) are encoded while
rendering goes on (facet.cli.sequence).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import InputError
from . import args as A

EPILOG = """\
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
  facet render bunny.obj --target -0.02,0.1,0 --eye -0.1,0.2,0.3 -o near.png
  facet render bunny.obj --outputs color,depth,normals,ids --out-dir renders/ --png16
  facet render bunny.obj -o banding.png --bits 4 --dither floyd-steinberg
  facet render scene.toml --camera top -o top.png
  facet render bunny.obj --turntable 36 -o spin.gif

Every image gets its camera as JSON beside it (K, world-to-camera, near/far, size): OUT.json
for -o OUT.png; for a sequence one JSON with every frame's camera (spin.json for spin.gif,
cameras.json beside frames/{:04d}.png); NNNN_camera.json per frame in --out-dir.
"""


def add_parser(sub) -> None:
    r = sub.add_parser("render", help="render a mesh or scene file to images and arrays",
                       description="Render MODEL (OBJ, STL, PLY, OFF, GLB/glTF or a .toml "
                       "scene file) headlessly to an image. Without MODEL, renders facet's "
                       "bundled default model.", epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("model", nargs="?", help="mesh file or .toml scene file (default: the "
                   "bundled torus knot)")
    r.add_argument("-o", "--output", type=A.output_path, metavar="OUT.png",
                   help="image to write (default: MODEL's name with .png, in the current folder)")
    r.add_argument("--eye", type=A.vec3, metavar="X,Y,Z",
                   help="camera position (default: framed to fit the model)")
    r.add_argument("--target", type=A.vec3, metavar="X,Y,Z",
                   help="point the camera looks at (default: the model's centre)")
    r.add_argument("--fov", type=float, default=40.0, metavar="DEG",
                   help="vertical field of view in degrees (default 40)")
    r.add_argument("--ortho", action="store_true",
                   help="parallel (orthographic) projection, sized to fit the model")
    r.add_argument("--light", type=A.light, action="append", default=[], metavar="KIND:...",
                   help="add a light (see below); repeatable; replaces the scene's lights")
    r.add_argument("--color", type=A.color, metavar="R,G,B",
                   help="material colour, floats in [0, 1] (default: the file's or grey)")
    r.add_argument("--texture", metavar="IMAGE|checker",
                   help="diffuse texture for the model (needs texture coordinates); "
                   "'checker' generates a checkerboard")
    A.add_render_options(r, "the scene file's, or its intrinsics camera's, else 800x600")
    A.add_model_options(r)
    A.add_confine_option(r)
    r.add_argument("--turntable", type=int, metavar="N",
                   help="render N frames orbiting the model; -o takes .gif, .mp4 or a "
                   "pattern like frames/{:04d}.png")
    r.add_argument("--fps", type=float, default=30.0,
                   help="frame rate of GIF/MP4 turntables (default 30)")
    r.add_argument("--depth", type=A.output_path, metavar="OUT.npy",
                   help="also write linear depth (float32 .npy)")
    r.add_argument("--ids", type=A.output_path, metavar="OUT.npy",
                   help="also write object ids (int32 .npy, -1 = background)")
    out = r.add_argument_group("dataset outputs and colour quantisation")
    out.add_argument("--outputs", metavar="LIST",
                     help="channels to write into --out-dir: any of color,depth,ids,normals,"
                     "position,uv,spp (spp: the samples each pixel's colour is the mean "
                     "of, spp.npy) (default: the scene file's, else color,depth,ids)")
    out.add_argument("--out-dir", type=A.output_path, metavar="DIR",
                     help="write each channel as files in DIR "
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
    out.add_argument("--scalars", metavar="NAME|x|y|z|up",
                     help="colour the model through --colormap by a per-vertex property of "
                     "its file (a PLY's quality, intensity, ...; `facet info MODEL` lists "
                     "them) or a coordinate of its vertices (world space; up: along --up)")
    out.add_argument("--colormap", default="viridis", metavar="NAME",
                     help="the colormap of --scalars: viridis (default), coolwarm, gray, or "
                     "any of matplotlib's when it is installed")
    out.add_argument("--scalar-range", metavar="LO,HI",
                     help="the values the colormap's ends stand for (default: the values' "
                     "own range)")
    out.add_argument("--colorbar", action="store_true",
                     help="draw the colormap's bar, its ends labelled, at the picture's right")
    out.add_argument("--quality", type=int, metavar="Q",
                     help="JPEG and WebP quality, 1-100 (default 95)")
    r.add_argument("-q", "--quiet", action="store_true",
                   help="print nothing on success, and no progress line")
    r.add_argument("--keep-partial", action="store_true",
                   help="when SIGINT or SIGTERM stops a sum of samples, write the picture "
                   "reached so far (default: write nothing)")
    A.add_shader_options(r)


def _targets(args):
    """Validate where things go: (image path or sequence path, depth, ids), before any work."""
    from ..image.sequence import check_sequence_path
    from ..image.writers import check_image_path

    if args.out_dir:
        if args.output or args.depth or args.ids:
            raise InputError("--out-dir writes every output itself; leave out -o, --depth "
                             "and --ids (or drop --out-dir)")
        out = Path(args.out_dir)
        if out.exists() and not out.is_dir():
            raise InputError(f"--out-dir {out}: exists and is not a directory")
        return None, None, None
    if args.outputs:
        raise InputError("--outputs needs --out-dir to know where to write the channels")
    model = Path(args.model) if args.model else None
    sequence = bool(args.turntable) or A.time_range(args)[1] is not None
    default = (model.stem if model else "default") + (".gif" if sequence else ".png")
    image = Path(args.output) if args.output else Path(default)
    if sequence:
        check_sequence_path(args.output or default)
        if args.depth or args.ids:
            raise InputError("a turntable writes depth and ids with --outputs and --out-dir")
    else:
        check_image_path(image)
    extra = []
    for flag, value in (("--depth", args.depth), ("--ids", args.ids)):
        if value is not None and Path(value).suffix.lower() != ".npy":
            raise InputError(f"{flag} {value}: arrays are written as .npy; change the extension")
        extra.append(Path(value) if value else None)
    for path in (image, *extra):
        if path is not None and path.is_dir():
            raise InputError(f"{path}: is a directory; give a file name for the output")
    return (args.output or default) if sequence else image, *extra


def _camera(args, scene, opts):
    """--eye / --target / --ortho frame a camera; otherwise the scene's, else framed
    around the options' up axis."""
    import numpy as np

    from ..geometry.camera import Camera

    bounds, (w, h), up = scene.bounds, opts.size, opts.up
    if args.camera is not None and not scene.cameras:
        raise InputError(f"--camera {args.camera}: this scene has no named cameras")
    if args.eye is None and args.target is None and not args.ortho and scene.cameras:
        camera = scene.camera(opts.camera)
        if camera is not None:  # else a model file's scene: framed below
            return camera
    target = np.asarray(args.target if args.target else bounds.mean(axis=0))
    if args.eye is None:
        direction = None if args.target is None else \
            target - Camera.frame(bounds, up=up, aspect=w / h).eye
        return Camera.frame(bounds, direction, up, fov_y=args.fov, aspect=w / h,
                            ortho=args.ortho)
    direction = target - np.asarray(args.eye)
    if not np.linalg.norm(direction) > 0:
        raise InputError("--eye and --target are the same point")
    height = Camera.frame(bounds, direction, up, fov_y=args.fov, aspect=w / h,
                          ortho=True).ortho_height if args.ortho else None
    return Camera.looking_at_bounds(args.eye, target, up, bounds, fov_y=args.fov,
                                    ortho_height=height)


def _scene(args):
    """The scene to render: a scene file, or one mesh (the bundled default without MODEL),
    with --color / --texture / --frag on its material and --light replacing its lights."""
    from ..formats.source import is_scene_file, open_scene
    from ..paths import default_model
    from ..scene.points import resize_scene

    shader = user_shader(args)
    model = args.model or default_model()
    if is_scene_file(model) and (args.color is not None or args.texture is not None or
                                 shader is not None):
        raise InputError("--color, --texture and --frag apply to a single model; set "
                         "materials in the scene file instead")
    texture = _texture(args.texture) if args.texture else None
    scene = open_scene(model, crease=args.crease, **A.stage_options(args))
    if scene.splats and (args.color is not None or texture is not None or shader is not None):
        raise InputError("--color, --texture and --frag apply to meshes; Gaussian splats "
                         "carry their own colours (their SH): leave them out")
    resize_scene(scene, A.sprite_sizes(args))
    if not is_scene_file(model) and (args.color is not None or texture is not None or
                                     shader is not None):
        for obj in scene.objects:  # every part of the model
            if texture is not None and obj.mesh.uvs is None:
                raise InputError(f"--texture: {obj.mesh.name} has no texture coordinates to "
                                 "map an image with")
            obj.material = _override(obj.material, args.color, texture, shader)
    if args.light:
        scene.lights = []
        for light in args.light:
            scene.add_light(light)
    return scene


def _override(m, color, texture, shader):
    """``m`` with --color / --texture / --frag applied (a glTF material stays one: its
    base colour and base-colour texture change; --frag makes it a Phong material)."""
    from dataclasses import replace

    from ..scene.material import Material
    from ..scene.pbr import PbrMaterial, TextureSlot, as_phong

    if isinstance(m, PbrMaterial) and shader is None:
        changes = {}
        if color is not None:
            changes["base_color"] = (*color, m.base_color[3])
        if texture is not None:
            changes["base_color_texture"] = TextureSlot(texture)
        return replace(m, **changes)
    m = as_phong(m)
    return Material(m.color if color is None else color, m.ka, m.kd, m.ks, m.shininess,
                    m.name, texture or m.texture, shader)


def user_shader(args):
    """The UserShader of --frag/--vert/--uniform, or None."""
    from ..scene.shader import UserShader
    from .shader import parse_uniform

    if not getattr(args, "frag", None):
        if getattr(args, "vert", None) or getattr(args, "uniform", None):
            raise InputError("--vert and --uniform need --frag (the model's own shader)")
        return None
    return UserShader(args.frag, args.vert, dict(parse_uniform(u) for u in args.uniform))


def _texture(value: str):
    from ..scene.texture import Texture

    return Texture.checker() if value == "checker" else Texture.load(value)


def run(args) -> list[Path]:
    """Render as the arguments say; returns the paths written."""
    from ..image.outputs import ColorOptions
    from ..image.quantize import parse_bits
    from ..options.render import MAX_FRAMES

    if not 1 <= args.fov < 180:
        raise InputError(f"--fov must be in [1, 180) degrees, got {args.fov:g}")
    if args.turntable is not None and not 1 <= args.turntable <= MAX_FRAMES:
        raise InputError(f"--turntable needs 1..{MAX_FRAMES} frames, got {args.turntable}")
    if not A.MIN_FPS <= args.fps <= 240:  # below, a frame's GIF duration overflows
        raise InputError(f"--fps must be in [{A.MIN_FPS:g}, 240], got {args.fps:g}")
    start, end = A.time_range(args)
    if end is not None:
        from ..render.turntable import animation_times

        # The frame count, checked before any work.
        animation_times(float(start), end, args.fps, args.turntable)
    target, depth_path, ids_path = _targets(args)
    color_options = ColorOptions(parse_bits(args.bits), args.dither, args.palette,
                                 args.palette_method)
    if color_options.palette is not None and not 2 <= color_options.palette <= 256:
        raise InputError(f"--palette {color_options.palette}: choose 2..256 colours")
    if args.turntable and not args.out_dir and color_options.bits == (16,):
        raise InputError("16-bit colour cannot go into a GIF, MP4 or 8-bit PNG sequence; "
                         "use --out-dir for 16-bit frames")
    if args.turntable and args.out_dir:  # its files go to a writer process: start it now,
        from ..image.sequence import prestart_writer  # while the scene loads

        prestart_writer()
    from ..image.writers import FLOAT_FORMATS

    if args.colorbar and args.scalars is None:
        raise InputError("--colorbar shows the colormap of --scalars; give --scalars")
    if args.colorbar and args.turntable:
        raise InputError("--colorbar is drawn on single pictures; leave out --turntable")
    if args.quality is not None and not 1 <= args.quality <= 100:
        raise InputError(f"--quality must be in 1..100, got {args.quality}")
    # .exr / .hdr keep linear float colour: the render keeps it too.
    floats = Path(str(target).format(0) if "{" in str(target) else str(target)).suffix.lower() \
        in FLOAT_FORMATS and not args.out_dir
    from .progress import ticker

    line = ticker(args.quiet)
    try:
        with line.stage(_loading(args)):
            scene, opts, camera = resolve(args, color_options.needs_float or floats)
        return _render(args, scene, opts, camera, end, target, depth_path, ids_path,
                       color_options, line)
    finally:
        line.close()


def _loading(args) -> str:
    """The progress line's words while the model loads."""
    from ..paths import default_model

    model = Path(args.model or default_model())
    try:
        size = f" ({model.stat().st_size / 1e6:.0f} MB)" if model.stat().st_size >= 1e6 else ""
    except OSError:
        size = ""
    return f"loading {model.name}{size}"


def _render(args, scene, opts, camera, end, target, depth_path, ids_path, color_options,
            line) -> list[Path]:
    from ..image.writers import check_image_path
    from .progress import SampleProgress

    if not args.out_dir and end is None and not args.turntable:
        check_image_path(target, opts.size)  # a format too small for the size: said now
    span = None if end is None else (opts.time, end)
    if span is not None and not args.turntable and args.eye is None and \
            args.target is None and not args.ortho and scene.camera(opts.camera) is not None:
        camera = None  # the scene's own camera: it follows its node as the scene plays

    from ..render.renderer import Renderer  # GL is loaded only once the inputs are good

    with Renderer() as renderer:
        if args.turntable or span is not None:
            from .sequence import render_turntable

            return render_turntable(renderer, scene, camera, opts, args, target,
                                    color_options, span)
        triangles = sum(o.mesh.face_count for o in scene.objects)
        with SampleProgress(args.quiet, args.keep_partial, opts.time_limit, line) as watch, \
                line.stage(f"rendering {triangles:,} triangles ({opts.engine})"):
            renderer.progress = watch
            frame = renderer.render(scene, camera, opts)
            frame.settle()
    if watch.nothing_to_keep():
        raise KeyboardInterrupt
    written = _write_single(frame, args, opts.outputs, target, depth_path, ids_path,
                            color_options)
    watch.after_writing(written)
    return written


def resolve(args, float_color: bool = False):
    """(scene, render options, camera) of these arguments, before any GL: the flags are
    one raw layer over the scene's own (facet.options.render.options_for)."""
    from ..options.render import options_for

    scene = _scene(args)
    layer = A.render_layer(args)
    # What this command writes: --out-dir the chosen channels, -o colour (+ --depth, --ids).
    layer["outputs"] = args.outputs if args.out_dir else \
        ("color", *(["depth"] if args.depth else []), *(["ids"] if args.ids else []))
    layer["float_color"] = float_color
    opts = options_for(scene, layer)
    if args.scalars is not None:
        from .scalars import color_by_scalars

        color_by_scalars(scene, args, opts)
    # Framed where the animations stand at the (first) frame's time.
    return scene, opts, _camera(args, scene.at(opts.time, opts.animation), opts)


def _write_single(frame, args, channels, image_path, depth_path, ids_path, color_options):
    from ..image.outputs import save_color, write_camera_json, write_outputs
    from ..image.writers import save_array

    if args.out_dir:
        return write_outputs(frame, args.out_dir, channels, color_options, png16=args.png16,
                             normals_space=args.normals_space)
    color = frame.color
    if args.colorbar:
        from ..image.writers import to_uint8
        from ..scene.colormap import colorbar

        color = colorbar(to_uint8(color), args.colormap, args.scalar_limits)
    written = [save_color(image_path, color, color_options, args.quality)]
    if depth_path:
        written.append(save_array(depth_path, frame.depth))
    if ids_path:
        written.append(save_array(ids_path, frame.object_ids))
    written.append(write_camera_json(image_path.with_suffix(".json"), frame.camera_info()))
    return written
