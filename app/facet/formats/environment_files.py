"""Environments from files (no GL): an equirectangular image (8-bit, or HDR through
facet.formats.hdr_image) resampled onto a cube, or six cube-face images; what
``Environment.from_equirect`` / ``from_faces`` and the ``environment`` option read
(facet.scene.readers)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..scene.environment import FACE_NAMES, Environment, face_directions, sky_grid
from ..scene.texture import Texture
from .hdr_image import is_hdr, read_hdr_image


def environment_from_faces(paths) -> Environment:
    """A cube map of six images (+X, -X, +Y, -Y, +Z, -Z), square and of one size."""
    if len(paths) != 6:
        raise InputError(f"a cube map needs 6 face images (+X -X +Y -Y +Z -Z), got "
                         f"{len(paths)}")
    faces = [Texture.load(p).pixels[..., :3] for p in paths]
    sizes = {f.shape[:2] for f in faces}
    if len(sizes) != 1 or faces[0].shape[0] != faces[0].shape[1]:
        listing = ", ".join(f"{Path(p).name} {f.shape[1]}x{f.shape[0]}"
                            for p, f in zip(paths, faces, strict=True))
        raise InputError(f"cube map faces must be square and all the same size: {listing}")
    return Environment(np.stack(faces) / 255.0, "cube map")


def environment_from_image(path, size: int = 256) -> Environment:
    """An equirectangular image resampled onto a cube of ``size`` texels a side (HDR files
    keep their linear radiance; 8-bit images are values in [0, 1])."""
    if is_hdr(path):
        img, scale = read_hdr_image(path), 1.0
    else:
        img, scale = Texture.load(path).pixels, 1.0 / 255.0
    d = face_directions(size)
    u = 0.5 + np.arctan2(d[..., 0], -d[..., 2]) / (2 * np.pi)
    v = np.arccos(np.clip(d[..., 1], -1, 1)) / np.pi  # 0 at the zenith (image top)
    h, w = img.shape[:2]
    x = np.clip((u * w).astype(int), 0, w - 1)
    y = np.clip((v * h).astype(int), 0, h - 1)
    grid = sky_grid(img) * np.float32(scale)  # lights at full resolution (or area mean)
    env = Environment(img[y, x, :3].astype(np.float32) * scale, Path(path).name, grid)
    env.linear = is_hdr(path)
    return env


_LOADED: dict = {}  # (path, size, mtime) -> Environment: the last few image files read
_KEEP = 2  # a 2K HDR sky is about 40 MB with its cube and light grid


def resolve(value):
    """``value`` as an Environment: an option's ``EnvironmentFile`` read (load_environment),
    anything else as it is (an Environment, None)."""
    from ..options.values import EnvironmentFile

    if isinstance(value, EnvironmentFile):
        return load_environment(value.spec, value.base)
    return value


def load_environment(spec: str, base: Path | None = None) -> Environment:
    """``sky``, an equirectangular image file, or a folder with px/nx/py/ny/pz/nz images.

    An image file read before and unchanged since (same size and modification time) is
    the same Environment again: a turntable or a series of renders under one sky reads and
    resamples it once, and the engines' textures made from it (keyed by the object) stay.
    Its arrays are read-only."""
    if spec == "sky":
        return Environment.sky()
    from ..guard import check_confined

    path = Path(base or ".") / spec
    check_confined(path, "environment file")
    if path.is_dir():
        faces = []
        for name in FACE_NAMES:
            found = sorted(path.glob(f"{name}.*"))
            if not found:
                raise InputError(f"{path}: no {name}.* face image (a cube map folder holds "
                                 f"{', '.join(FACE_NAMES)})")
            faces.append(found[0])
        return environment_from_faces(faces)
    try:
        stat = path.stat()
    except OSError:
        return environment_from_image(path)  # (the reader names what is wrong)
    key = (str(path.resolve()), stat.st_size, stat.st_mtime_ns)
    env = _LOADED.pop(key, None)
    if env is None:
        env = environment_from_image(path)
        for array in (env.faces, env.equirect):
            if array is not None:
                array.flags.writeable = False
    _LOADED[key] = env  # (the most recent last)
    while len(_LOADED) > _KEEP:
        del _LOADED[next(iter(_LOADED))]
    return env
