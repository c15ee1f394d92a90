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

IMAGE_FORMATS = {".png": "PNG"}


@contextlib.contextmanager
def write_atomic(path):
    """Yield a temporary path next to ``path``; on success rename it to ``path``."""
    target = Path(path)
    if target.is_dir():
        raise InputError(f"{target}: is a directory; give a file name for the output")
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; outputs get the usual mode
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_image_path(path) -> Path:
    p = Path(path)
    if p.suffix.lower() not in IMAGE_FORMATS:
        raise InputError(f"{p}: unsupported image format '{p.suffix or '(none)'}'; "
                         f"use {', '.join(IMAGE_FORMATS)}")
    return p


def save_image(path, rgba: np.ndarray) -> Path:
    """Write (H, W, 3|4) uint8 to a PNG. An all-opaque RGBA image is stored as RGB."""
    from PIL import Image  # Pillow is imported only by commands that write images

    p = check_image_path(path)
    a = np.asarray(rgba)
    if a.ndim != 3 or a.shape[2] not in (3, 4) or a.dtype != np.uint8:
        raise InputError(f"save_image expects (H, W, 3|4) uint8, got {a.shape} {a.dtype}")
    if a.shape[2] == 4 and np.all(a[..., 3] == 255):
        a = a[..., :3]
    with write_atomic(p) as tmp:
        Image.fromarray(np.ascontiguousarray(a)).save(tmp, format=IMAGE_FORMATS[p.suffix.lower()])
    return p


def save_array(path, array: np.ndarray) -> Path:
    """Write an array exactly to ``.npy``."""
    p = Path(path)
    if p.suffix.lower() != ".npy":
        raise InputError(f"{p}: arrays are written as .npy; change the extension")
    with write_atomic(p) as tmp, open(tmp, "wb") as fh:
        np.save(fh, array)
    return p
