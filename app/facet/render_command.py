"""``facet render``: from parsed command-line arguments to files on disk.

Outputs are validated before any work, rendered in one pass, and each written atomically.
"""

from __future__ import annotations

from pathlib import Path

from .errors import InputError


def _output_paths(args) -> tuple[Path | None, Path | None, Path | None]:
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
    image = Path(args.output) if args.output else Path((model.stem if model else "default")
                                                       + ".png")
    check_image_path(image)
    extra = []
    for flag, value in (("--depth", args.depth), ("--ids", args.ids)):
        if value is not None and Path(value).suffix.lower() != ".npy":
            raise InputError(f"{flag} {value}: arrays are written as .npy; change the extension")
        extra.append(Path(value) if value else None)
    for path in (image, *extra):
        if path is not None and path.is_dir():
            raise InputError(f"{path}: is a directory; give a file name for the output")
    return image, *extra


def _camera(args, bounds):
    import numpy as np

    from .geometry.camera import DEFAULT_DIRECTION, Camera

    w, h = args.size
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


def run_render(args) -> list[Path]:
    """Render as the arguments say; returns the paths written."""
    from .image.outputs import ColorOptions, parse_channels, save_color, write_camera_json
    from .image.quantize import parse_bits
    from .paths import default_model
    from .scene.light import camera_rig
    from .scene.material import Material
    from .scene.mesh import Mesh
    from .scene.scene import Scene

    if not 1 <= args.fov < 180:
        raise InputError(f"--fov must be in [1, 180) degrees, got {args.fov:g}")
    image_path, depth_path, ids_path = _output_paths(args)
    channels = parse_channels(args.outputs) if args.outputs else ("color",)
    color_options = ColorOptions(parse_bits(args.bits), args.dither, args.palette,
                                 args.palette_method)
    if color_options.palette is not None and not 2 <= color_options.palette <= 256:
        raise InputError(f"--palette {color_options.palette}: choose 2..256 colours")
    mesh = Mesh.load(args.model or default_model())
    scene = Scene(background=args.background)
    material = mesh.material or Material()
    if args.color is not None:
        material = Material(args.color, material.ka, material.kd, material.ks,
                            material.shininess, material.name)
    scene.add(mesh, material)
    camera = _camera(args, scene.bounds)
    for light in args.light or camera_rig(camera.view):
        scene.add_light(light)

    from .render.renderer import Renderer  # GL is loaded only once the inputs are good

    outputs = set(channels) | ({"depth"} if depth_path else set()) | (
        {"ids"} if ids_path else set())
    with Renderer(*args.size, msaa=args.msaa, shading=args.shading,
                  float_color=color_options.needs_float) as renderer:
        frame = renderer.render(scene, camera, outputs=tuple(outputs))
    from .image.outputs import write_outputs
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
