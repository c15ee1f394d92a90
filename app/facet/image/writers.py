"""Writing render results to disk, never leaving a half-written file behind.

Each writer renders into a temporary file in the destination directory and renames it over
the target only when complete, so a failure (or Ctrl-C) leaves no output file.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..guard import check_output

IMAGE_FORMATS = {".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG", ".webp": "WEBP",
                 ".tif": "TIFF", ".tiff": "TIFF", ".exr": "EXR", ".hdr": "HDR"}
FLOAT_FORMATS = (".exr", ".hdr")  # linear float colour (the render keeps float colour)
DEFAULT_QUALITY = 95  # JPEG / WebP quality when none is given (Pillow's own is 75)
HDR_HINT = "pip install 'facet-render[hdr]' (OpenCV for imageio)"


@contextlib.contextmanager
def write_atomic(path):
    """Yield a temporary path next to ``path``; on success rename it to ``path``."""
    target = check_output(path)  # not a FIFO, device or folder; inside the output folder
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        tmp = temp_beside(target, ".tmp")
    except OSError as exc:  # name the user's path, not a temporary one
        raise OSError(exc.errno, f"cannot write there ({exc.strerror})", str(target)) \
            from None
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; outputs get the usual mode
        os.replace(tmp, target)
    except OSError as exc:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise OSError(exc.errno, exc.strerror, str(target)) from None
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


_SWEPT: set[str] = set()  # folders this process has cleared of dead runs' left-overs


def temp_beside(target: Path, suffix: str) -> str:
    """A new empty temporary file next to ``target`` whose name says whose it is:
    ``.NAME.facet-PID-XXXX`` + suffix. Left-overs of runs that were killed outright (no
    chance to clean up: a process that no longer exists) are removed from a folder the
    first time this process writes there (once, not per file: a dataset folder holds
    many thousands of files)."""
    prefix = f".{target.name}.facet-"
    folder = os.path.abspath(target.parent)
    if folder not in _SWEPT:
        _SWEPT.add(folder)
        with contextlib.suppress(OSError):
            for entry in os.scandir(folder):
                name = entry.name
                if name.startswith(".") and ".facet-" in name:
                    pid = name.rsplit(".facet-", 1)[1].split("-", 1)[0]
                    if pid.isascii() and pid.isdigit() and not _alive(int(pid)):
                        with contextlib.suppress(OSError):
                            os.unlink(entry.path)
    fd, tmp = tempfile.mkstemp(prefix=f"{prefix}{os.getpid()}-", suffix=suffix,
                               dir=target.parent)
    os.close(fd)
    return tmp


def remove_temporaries(folder, pids) -> None:
    """Remove, anywhere under ``folder`` (links not followed), the temporary files of the
    processes ``pids`` (writers that were stopped mid-file and had no chance to clean up:
    a batch's workers after SIGTERM)."""
    marks = tuple(f".facet-{pid}-" for pid in pids)
    if not marks:
        return
    for root, _dirs, files in os.walk(folder):
        for name in files:
            if name.startswith(".") and any(m in name for m in marks):
                with contextlib.suppress(OSError):
                    os.unlink(os.path.join(root, name))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's process: not ours to clean up after
        return True
    return True


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


# The largest side each format can hold (WebP's own limit; Pillow refuses beyond it).
MAX_SIDE = {"WEBP": 16383, "JPEG": 65535, "GIF": 65535}


def check_image_path(path, size: tuple[int, int] | None = None) -> Path:
    """``path`` when facet writes its format; with ``size`` (width, height), also when the
    format can hold a picture that size: said before anything is rendered."""
    p = Path(path)
    if p.suffix.lower() not in IMAGE_FORMATS:
        raise InputError(f"{p}: unsupported image format '{p.suffix or '(none)'}'; "
                         f"use {', '.join(IMAGE_FORMATS)}")
    kind = IMAGE_FORMATS[p.suffix.lower()]
    if size is not None and max(size) > MAX_SIDE.get(kind, 1 << 31):
        raise InputError(f"{p}: {size[0]}x{size[1]} is larger than {kind} can hold (at most "
                         f"{MAX_SIDE[kind]:,} pixels a side); render smaller, or write PNG")
    return p


# zlib level for PNGs: level 1 files are at most about 25% larger than the default level 6
# on rendered images (measured on facet's own renders) and encode several times faster,
# which keeps dataset writing off the critical path of a turntable.
PNG_COMPRESS_LEVEL = 1
PNG16_COMPRESS_LEVEL = 6  # 16-bit files (an option for exact values, not the default path)


def save_image(path, rgba: np.ndarray, quality: int | None = None) -> Path:
    """Write (H, W) grey or (H, W, 3|4) uint8 to PNG (facet.image.png), or through Pillow
    to JPEG (no alpha: written opaque, with one warning when the picture has some), WebP or
    TIFF; ``quality`` (1-100) for JPEG and WebP (default DEFAULT_QUALITY). An all-opaque
    RGBA image is stored as RGB."""
    from .png import encode_png

    if quality is not None and (isinstance(quality, bool) or not isinstance(quality, int)
                                or not 1 <= quality <= 100):
        raise InputError(f"quality: expected a whole number from 1 to 100, got {quality!r}")
    a = np.asarray(rgba)
    p = check_image_path(path, a.shape[1::-1] if a.ndim >= 2 else None)
    kind = IMAGE_FORMATS[p.suffix.lower()]
    if kind in ("EXR", "HDR"):
        raise InputError(f"{p}: {kind} holds linear float colour; render with "
                         "float_color=True and write it with save_float_color")
    a = np.asarray(rgba)
    if a.dtype != np.uint8 or not (a.ndim == 2 or (a.ndim == 3 and a.shape[2] in (3, 4))):
        raise InputError(f"save_image expects (H, W) or (H, W, 3|4) uint8, got {a.shape} "
                         f"{a.dtype}")
    if a.ndim == 3 and a.shape[2] == 4 and np.all(a[..., 3] == 255):
        a = a[..., :3]
    if kind == "PNG":
        data = encode_png(a, PNG_COMPRESS_LEVEL)
    else:
        data = _pillow_bytes(p, a, kind, quality)
    with write_atomic(p) as tmp:
        tmp.write_bytes(data)
    return p


def _pillow_bytes(p: Path, a: np.ndarray, kind: str, quality: int | None) -> bytes:
    import io
    import warnings

    from PIL import Image

    from ..errors import FacetWarning

    if kind == "JPEG" and a.ndim == 3 and a.shape[2] == 4:
        warnings.warn(f"{p.name}: JPEG has no alpha; the transparent background is written "
                      "opaque (use PNG, WebP or TIFF to keep it)", FacetWarning, stacklevel=4)
        a = a[..., :3]
    out = io.BytesIO()
    options = {"quality": quality or DEFAULT_QUALITY} if kind in ("JPEG", "WEBP") else \
        {"compression": "tiff_deflate"}
    Image.fromarray(np.ascontiguousarray(a)).save(out, kind, **options)
    return out.getvalue()


def save_float_color(path, color: np.ndarray) -> Path:
    """Write linear float colour (H, W, 3|4) as OpenEXR (RGB, A kept; float32, lossless)
    or Radiance HDR (RGB, through imageio and OpenCV)."""
    p = check_image_path(path)
    a = np.asarray(color, dtype=np.float32)
    if a.ndim != 3 or a.shape[2] not in (3, 4):
        raise InputError(f"{p}: colour must be (H, W, 3|4) floats, got {a.shape}")
    bad = ~np.isfinite(a)
    if bad.any():  # a float picture stays finite: said, and clamped
        import warnings

        from ..errors import FacetWarning

        warnings.warn(f"{p}: {int(bad.any(axis=2).sum()):,} pixels were not finite (inf or "
                      "NaN); written as the largest float (inf) and 0 (NaN)", FacetWarning,
                      stacklevel=2)
        a = np.nan_to_num(a, nan=0.0, posinf=np.finfo(np.float32).max,
                          neginf=-np.finfo(np.float32).max)
    if p.suffix.lower() == ".exr":
        return _save_exr_rgba(p, a)
    try:
        import cv2  # noqa: F401 - imageio's backend for Radiance HDR
    except ImportError:
        raise InputError(f"{p}: writing Radiance HDR needs {HDR_HINT}; or write .exr "
                         "(OpenEXR)") from None
    import imageio.v3 as iio

    data = iio.imwrite("<bytes>", np.ascontiguousarray(a[..., :3]), extension=".hdr",
                       plugin="opencv")
    with write_atomic(p) as tmp:
        tmp.write_bytes(data)
    return p


def _save_exr_rgba(p: Path, a: np.ndarray) -> Path:
    try:
        import OpenEXR
    except ImportError:
        raise InputError(f"{p}: writing EXR needs {EXR_HINT}") from None
    channels = {n: np.ascontiguousarray(a[..., k]) for k, n in enumerate("RGBA"[:a.shape[2]])}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with write_atomic(p) as tmp:
        OpenEXR.File(header, channels).write(str(tmp))
    return p


def save_indexed(path, index: np.ndarray, palette: np.ndarray) -> Path:
    """Write (H, W) uint8 palette indices with a (<= 256, 3) uint8 palette as an indexed PNG."""
    from .png import encode_png

    p = check_image_path(path)
    index = np.asarray(index, dtype=np.uint8)
    palette = np.asarray(palette, np.uint8).reshape(-1, 3)
    if index.size and int(index.max()) >= len(palette):  # black for indices past its end
        palette = np.concatenate([palette, np.zeros((256 - len(palette), 3), np.uint8)])
    data = encode_png(index, PNG_COMPRESS_LEVEL, palette=palette)
    with write_atomic(p) as tmp:
        tmp.write_bytes(data)
    return p


def to_uint8(color: np.ndarray) -> np.ndarray:
    """8-bit colour: uint8 passes through, floats in [0, 1] are rounded."""
    a = np.asarray(color)
    if a.dtype == np.uint8:
        return a
    return np.rint(np.clip(a, 0.0, 1.0) * 255.0).astype(np.uint8)


def save_png16(path, image: np.ndarray) -> Path:
    """Write a (H, W) or (H, W, 3) uint16 image as a 16-bit PNG."""
    from .png import encode_png

    p = check_image_path(path)
    data = encode_png(image, PNG16_COMPRESS_LEVEL)
    with write_atomic(p) as tmp:
        tmp.write_bytes(data)
    return p


def save_array(path, array: np.ndarray) -> Path:
    """Write an array exactly to ``.npy``."""
    p = Path(path)
    if p.suffix.lower() != ".npy":
        raise InputError(f"{p}: arrays are written as .npy; change the extension")
    with write_atomic(p) as tmp, open(tmp, "wb") as fh:
        np.save(fh, array)
    return p


EXR_HINT = "pip install 'facet-render[exr]' (the OpenEXR package)"


def exr_available() -> bool:
    try:
        import OpenEXR  # noqa: F401
    except ImportError:
        return False
    return True


def save_exr(path, array: np.ndarray) -> Path:
    """Write a float channel exactly (float32, lossless ZIP) as OpenEXR: (H, W) as the
    grey channel Y (read as a grey float image by OpenCV's IMREAD_ANYDEPTH, imageio and
    viewers), (H, W, 2) as R, G and (H, W, 3) as R, G, B. Needs the optional OpenEXR."""
    try:
        import OpenEXR
    except ImportError:
        raise InputError(f"{path}: writing EXR needs {EXR_HINT}") from None
    p = Path(path)
    a = np.asarray(array, dtype=np.float32)
    if a.ndim == 2:
        channels = {"Y": np.ascontiguousarray(a)}
    elif a.ndim == 3 and a.shape[2] in (2, 3):
        channels = {n: np.ascontiguousarray(a[..., k]) for k, n in enumerate("RGB"[:a.shape[2]])}
    else:
        raise InputError(f"{p}: EXR holds (H, W), (H, W, 2) or (H, W, 3) floats, got {a.shape}")
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with write_atomic(p) as tmp:
        OpenEXR.File(header, channels).write(str(tmp))
    return p
