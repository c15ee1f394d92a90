"""Cameras from a transforms.json, as the NeRF tools write them (no GL): NeRF synthetic /
Blender (``camera_angle_x`` only, the commonest), instant-ngp and nerfstudio (``fl_x``,
``fl_y``, ``cx``, ``cy``, ``w``, ``h``, in the file or per frame). Per frame a
camera-to-world ``transform_matrix`` in OpenGL axes.

The intrinsics, per frame: ``fl_x`` (else from ``camera_angle_x``: fl_x = w / 2 /
tan(angle / 2)), ``fl_y`` (else from ``camera_angle_y``, else fl_x: square pixels), ``cx``
and ``cy`` (else the image's centre) in the pixel-corner convention these tools use (a
pixel's centre at i + 0.5; facet's OpenCV K puts it at i). The image size ``w`` x ``h``
comes from the file, else from the first frame's image (``file_path``, relative to the
file, with ``.png`` added when it has no extension, as NeRF synthetic writes it).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..errors import InputError


def read_transforms(path, bounds=None, size=None) -> list:
    """The file's cameras (facet Cameras with intrinsics) for images of ``size`` (w, h;
    default the file's: intrinsics scaled to another size; a file that gives no size,
    neither w and h nor images beside it, as a NeRF-synthetic one with only
    camera_angle_x, is taken at ``size``); near and far fitted around ``bounds`` when
    given."""
    from ..geometry.camera import Camera
    from ..geometry.framing import depth_range
    from ..geometry.intrinsics import Intrinsics

    path = Path(path)
    data = _document(path)
    frames = data.get("frames")
    if not isinstance(frames, list) or not frames:
        raise InputError(f"{path}: a transforms.json has a list of \"frames\"")
    cams = []
    for i, frame in enumerate(frames):
        where = f"{path}: frames[{i}]"
        if not isinstance(frame, dict):
            raise InputError(f"{where}: expected an object with a transform_matrix")
        fields = {**data, **frame}  # a frame's own intrinsics win
        w, h = image_size(path, data, frame, fallback=size)
        fl_x = _focal(fields, "fl_x", "camera_angle_x", w, where)
        fl_y = _focal(fields, "fl_y", "camera_angle_y", h, where, default=fl_x)
        for name, fl, extent in (("fl_x", fl_x, w), ("fl_y", fl_y, h)):
            angle = 2 * math.degrees(math.atan(extent / 2 / fl))
            if not 1e-3 <= angle <= 179:  # beyond, the projection is degenerate
                raise InputError(f"{where}.{name}: a focal length of {fl:g} pixels is a "
                                 f"{angle:.3g} degree field of view over {extent} pixels; "
                                 "expected 0.001 to 179 degrees")
        cx = _number(fields.get("cx", w / 2), f"{where}.cx")
        cy = _number(fields.get("cy", h / 2), f"{where}.cy")
        to_world = _matrix(frame.get("transform_matrix"), f"{where}.transform_matrix")
        view = np.linalg.inv(to_world)
        sx, sy = (1.0, 1.0) if size is None else (size[0] / w, size[1] / h)
        k = Intrinsics(fl_x * sx, fl_y * sy, cx * sx - 0.5, cy * sy - 0.5,
                       int(size[0]) if size else w, int(size[1]) if size else h)
        near, far = depth_range(view, bounds) if bounds is not None else (0.01, 1000.0)
        cams.append(Camera(view, intrinsics=k, near=near, far=far))
    return cams


def file_size(path) -> tuple[int, int] | None:
    """(w, h) of the images a transforms.json describes (its first frame's); None when it
    gives none (the job's size is used)."""
    path = Path(path)
    data = _document(path)
    frames = data.get("frames")
    return image_size(path, data, frames[0] if isinstance(frames, list) and frames and
                      isinstance(frames[0], dict) else None, fallback=NO_SIZE) or None


NO_SIZE = ()  # image_size's fallback meaning "say None"


def image_size(path: Path, data: dict, frame: dict | None = None,
               fallback=None) -> tuple[int, int]:
    """(w, h) of the file's (or ``frame``'s) images; ``fallback`` (w, h) where the file
    gives no size (neither w and h nor images beside it), else InputError."""
    fields = {**data, **(frame or {})}
    if "w" in fields and "h" in fields:
        w, h = fields["w"], fields["h"]
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) and v >= 1
               and float(v).is_integer() for v in (w, h)):
            from ..budgets import check_pixels

            check_pixels(int(w), int(h), f"{path}: w x h")
            return int(w), int(h)
        raise InputError(f"{path}: w and h must be whole numbers >= 1, got {w!r} x {h!r}")
    if frame is None:
        frames = data.get("frames")
        frame = frames[0] if isinstance(frames, list) and frames else {}
    first = frame.get("file_path") if isinstance(frame, dict) else None
    if isinstance(first, str) and first and "\0" not in first:
        from ..guard import check_confined, open_image, regular_file

        image = path.parent / first
        for candidate in (image, image.with_name(image.name + ".png")):
            check_confined(candidate, "frame image")
            if candidate.is_file():
                with open_image(regular_file(candidate, "frame image"), str(candidate)) as im:
                    return im.size
    if fallback is not None:
        return tuple(int(v) for v in fallback)
    raise InputError(f"{path}: no image size: give w and h, or keep the frames' images "
                     f"beside it ({first!r} not found), or give the job a size")


def _document(path: Path) -> dict:
    from ..guard import parse_json, read_bytes

    try:
        data = parse_json(read_bytes(path, "cameras file"), str(path))
    except InputError as exc:
        raise InputError(f"{exc}; is it a transforms.json?") from None
    if not isinstance(data, dict):
        raise InputError(f"{path}: not a transforms.json (expected an object)")
    return data


def _focal(fields, key, angle_key, extent, where, default=None) -> float:
    if key in fields:
        return _number(fields[key], f"{where}.{key}", positive=True)
    if angle_key in fields:
        angle = _number(fields[angle_key], f"{where}.{angle_key}", positive=True)
        if angle >= math.pi:
            raise InputError(f"{where}.{angle_key}: an angle in radians below pi, got "
                             f"{angle}")
        return extent / 2.0 / math.tan(angle / 2.0)
    if default is not None:
        return default
    raise InputError(f"{where}: no focal length: give fl_x (pixels) or camera_angle_x "
                     "(radians)")


def _number(value, where: str, positive: bool = False) -> float:
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value) and (value > 0 or not positive)
    if not ok:
        raise InputError(f"{where}: expected a {'positive ' if positive else ''}number, got "
                         f"{value!r}")
    return float(value)


def _matrix(value, where: str) -> np.ndarray:
    try:
        m = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        m = np.zeros(0)
    if m.shape != (4, 4) or not np.all(np.isfinite(m)) or abs(np.linalg.det(m[:3, :3])) < 1e-12:
        raise InputError(f"{where}: expected a 4x4 camera-to-world matrix")
    return m
