"""``facet render``: from parsed command-line arguments to files on disk.

Precedence for every setting: the command line, then the scene file's [render] table, then
facet's defaults. Outputs are validated before any work, and each file is written atomically;
sequences (turntables) are encoded on a background thread while rendering goes on.
"""

from __future__ import annotations

from pathlib import Path

from .errors import InputError


def _targets(args):
    """Validate where things go: (image path or sequence path, depth, ids), before any work."""
    from .image.sequence import check_sequence_path
    from .image.writers import check_image_path

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
    default = (model.stem if model else "default") + (".gif" if args.turntable else ".png")
    image = Path(args.output) if args.output else Path(default)
    if args.turntable:
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
    return (args.output or default) if args.turntable else image, *extra


def _camera(args, bounds, size):
    import numpy as np

    from .geometry.camera import DEFAULT_DIRECTION, Camera

    w, h = size
    target = np.asarray(args.target if args.target else bounds.mean(axis=0))
    if args.eye is None:
        direction = DEFAULT_DIRECTION if args.target is None else \
            target - Camera.frame(bounds, aspect=w / h).eye
        return Camera.frame(bounds, direction, args.up, fov_y=args.fov, aspect=w / h,
                            ortho=args.ortho)
    direction = target - np.asarray(args.eye)
    if not np.linalg.norm(direction) > 0:
        raise InputError("--eye and --target are the same point")
    height = Camera.frame(bounds, direction, args.up, fov_y=args.fov, aspect=w / h,
                          ortho=True).ortho_height if args.ortho else None
    return Camera.looking_at_bounds(args.eye, target, args.up, bounds, fov_y=args.fov,
                                    ortho_height=height)


def _scene(args):
    """The scene to render: a scene file, or one mesh (the bundled default without MODEL)."""
    from .paths import default_model
    from .scene.material import Material
    from .scene.mesh import Mesh
    from .scene.scene import Scene

    shader = user_shader(args)
    if args.model and Path(args.model).suffix.lower() == ".toml":
        from .scene.scenefile import load_scene  # tomllib and the validators: scenes only

        if args.color is not None or args.texture is not None or shader is not None:
            raise InputError("--color, --texture and --frag apply to a single model; set "
                             "materials in the scene file instead")
        return load_scene(args.model)
    texture = _texture(args.texture) if args.texture else None
    mesh = Mesh.load(args.model or default_model())
    if texture is not None and mesh.uvs is None:
        raise InputError(f"--texture: {mesh.name} has no texture coordinates to map an image "
                         "with")
    scene = Scene()
    m = mesh.material or Material()
    material = Material(m.color if args.color is None else args.color, m.ka, m.kd, m.ks,
                        m.shininess, m.name, texture or m.texture, shader)
    scene.add(mesh, material)
    return scene


def user_shader(args):
    """The UserShader of --frag/--vert/--uniform, or None."""
    from .scene.shader import UserShader
    from .shader_command import parse_uniform

    if not getattr(args, "frag", None):
        if getattr(args, "vert", None) or getattr(args, "uniform", None):
            raise InputError("--vert and --uniform need --frag (the model's own shader)")
        return None
    return UserShader(args.frag, args.vert, dict(parse_uniform(u) for u in args.uniform))


def _texture(value: str):
    from .scene.texture import Texture

    return Texture.checker() if value == "checker" else Texture.load(value)


def run_render(args) -> list[Path]:
    """Render as the arguments say; returns the paths written."""
    import numpy as np

    from .image.outputs import ColorOptions, parse_channels
    from .image.quantize import parse_bits
    from .scene.light import camera_rig

    if not 1 <= args.fov < 180:
        raise InputError(f"--fov must be in [1, 180) degrees, got {args.fov:g}")
    if args.turntable is not None and not 1 <= args.turntable <= 100_000:
        raise InputError(f"--turntable needs 1..100000 frames, got {args.turntable}")
    if not 0 < args.fps <= 240:
        raise InputError(f"--fps must be in (0, 240], got {args.fps:g}")
    target, depth_path, ids_path = _targets(args)
    color_options = ColorOptions(parse_bits(args.bits), args.dither, args.palette,
                                 args.palette_method)
    if color_options.palette is not None and not 2 <= color_options.palette <= 256:
        raise InputError(f"--palette {color_options.palette}: choose 2..256 colours")
    if args.turntable and not args.out_dir and color_options.bits == (16,):
        raise InputError("16-bit colour cannot go into a GIF, MP4 or 8-bit PNG sequence; "
                         "use --out-dir for 16-bit frames")
    scene = _scene(args)
    settings = scene.settings
    if args.background is not None:
        scene.background = np.append(args.background, 1.0)[:4] if len(args.background) == 3 \
            else np.asarray(args.background)
    size = args.size or settings.size
    channels = parse_channels(args.outputs) if args.outputs else (
        settings.outputs if args.out_dir else ("color",))
    if args.eye is not None or args.ortho or args.target is not None or not scene.cameras:
        if args.camera is not None and not scene.cameras:
            raise InputError(f"--camera {args.camera}: this scene has no named cameras")
        camera = _camera(args, scene.bounds, size)
    else:
        camera = scene.camera(args.camera)
        if camera.intrinsics is not None and args.size is None:
            size = (camera.intrinsics.width, camera.intrinsics.height)  # its own image size
    if args.aperture or args.focus is not None:
        camera = _with_lens(camera, args.aperture, args.focus)
    if args.env:
        from .scene.environment import load_environment

        scene.environment = load_environment(args.env)
    headlights = not args.light and not scene.lights
    if args.light:
        scene.lights = []
        for light in args.light:
            scene.add_light(light)
    elif headlights:  # the default rig is placed relative to the camera, frame by frame
        for light in camera_rig(camera.view):
            scene.add_light(light)

    from .render.renderer import Renderer  # GL is loaded only once the inputs are good

    outputs = set(channels) | ({"depth"} if depth_path else set()) | (
        {"ids"} if ids_path else set())
    aa = _anti_aliasing(args, settings)
    with Renderer(*size, msaa=aa.samples if aa.kind == "msaa" else 0,
                  shading=args.shading or settings.shading,
                  float_color=color_options.needs_float,
                  srgb=args.srgb or settings.srgb) as renderer:
        if args.turntable:
            from .render_sequence import render_turntable

            return render_turntable(renderer, scene, camera, args, channels, target,
                                    color_options, tuple(outputs), headlights, str(aa))
        frame = renderer.render(scene, camera, outputs=tuple(outputs), aa=str(aa),
                                shadows=args.shadows or settings.shadows, pcf=args.pcf)
    return _write_single(frame, args, channels, target, depth_path, ids_path, color_options)


def _with_lens(camera, aperture: float, focus):
    """A copy of ``camera`` with a thin lens (validated like the Python API)."""
    import copy

    from .geometry.lens import check_lens

    lens = copy.copy(camera)
    lens.aperture, lens.focus_distance = aperture, focus
    if aperture == 0 and focus is not None:
        raise InputError("--focus needs --aperture (a lens diameter > 0)")
    check_lens(lens)
    return lens


def _anti_aliasing(args, settings):
    """--aa, else --msaa, else the scene file's [render] aa / msaa."""
    from .render.antialias import parse_aa

    if args.aa is not None and args.msaa is not None:
        raise InputError("give either --aa or --msaa (--msaa N means --aa msaa:N)")
    if args.aa is not None:
        return parse_aa(args.aa)
    if args.msaa is not None:
        return parse_aa(f"msaa:{args.msaa}")
    return parse_aa(settings.aa or f"msaa:{settings.msaa}")


def _write_single(frame, args, channels, image_path, depth_path, ids_path, color_options):
    from .image.outputs import save_color, write_camera_json, write_outputs
    from .image.writers import save_array

    if args.out_dir:
        return write_outputs(frame, args.out_dir, channels, color_options, png16=args.png16,
                             normals_space=args.normals_space)
    written = [save_color(image_path, frame.color, color_options)]
    if depth_path:
        written.append(save_array(depth_path, frame.depth))
    if ids_path:
        written.append(save_array(ids_path, frame.object_ids))
    written.append(write_camera_json(image_path.with_suffix(".json"), frame.camera_info()))
    return written
