"""Shadertoy's volume channels (``sampler3D``): its ``.bin`` volume files, read through the
guard, and facet's stand-ins for its two built-in volumes, "Grey Noise3D" and "RGBA
Noise3D" (32 x 32 x 32 random bytes, one and four channels, the same every run).

A ``.bin`` file is a 20-byte little-endian header, then the texels x fastest: ``BIN\\0``,
the size in x, y and z (uint32 each), the channels (uint8: 1 to 4), the layout (uint8:
0) and the format (uint16: 0 for bytes, 10 for float32).
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from ..errors import InputError

NOISE_VOLUME_SIZE = 32  # texels a side of Shadertoy's noise volumes
NOISE_SEEDS = {"grey": 1, "rgba": 2}  # (not the 2D noise's seed: different numbers)
# Shadertoy's media ids of its two volumes, as exports name them.
SHADERTOY_VOLUMES = {
    "27012b4eadd0c3ce12498b867058e4f717ce79e5c91b6b2b1f3a2c0c1c6e8a9": "grey",
    "aea6b99da1d53055107966b59ac5444fc8bc7b3ce2d0bbb6a4a3cbae1d97f3aa": "rgba",
}
HEADER = struct.Struct("<4sIIIBBH")
FORMATS = {0: np.uint8, 10: np.float32}
MAX_SIDE = 1024  # texels a side (GL's 3D limit on most devices is 2048; this is plenty)


def noise_volume(kind: str) -> np.ndarray:
    """(32, 32, 32, C) uint8 random texels (z, y, x, channel), C = 1 for ``grey``, 4 for
    ``rgba``."""
    channels = 1 if kind == "grey" else 4
    rng = np.random.default_rng(NOISE_SEEDS[kind])
    n = NOISE_VOLUME_SIZE
    return rng.integers(0, 256, (n, n, n, channels), np.uint8)


def read_volume(path) -> np.ndarray:
    """The texels of a Shadertoy ``.bin`` volume file: (Z, Y, X, C) uint8 or float32."""
    from ..guard import read_bytes

    path = Path(path)
    data = read_bytes(path, "volume file")
    if len(data) < HEADER.size:
        raise InputError(f"{path}: {len(data)} bytes, shorter than a volume file's "
                         f"{HEADER.size}-byte header")
    magic, x, y, z, channels, layout, fmt = HEADER.unpack_from(data)
    if magic != b"BIN\0":
        raise InputError(f"{path}: not a Shadertoy volume file (it starts with {magic!r}, "
                         "not BIN)")
    if fmt not in FORMATS or not 1 <= channels <= 4 or layout != 0:
        raise InputError(f"{path}: a volume of {channels} channels, layout {layout}, format "
                         f"{fmt}; facet reads 1 to 4 channels of bytes (0) or floats (10), "
                         "layout 0")
    if not all(1 <= s <= MAX_SIDE for s in (x, y, z)):
        raise InputError(f"{path}: a volume of {x} x {y} x {z} texels; each side must be 1 "
                         f"to {MAX_SIDE}")
    dtype = np.dtype(FORMATS[fmt])
    want = x * y * z * channels * dtype.itemsize
    if len(data) - HEADER.size != want:
        raise InputError(f"{path}: its header says {x} x {y} x {z} x {channels} texels "
                         f"({want:,} bytes) but it holds {len(data) - HEADER.size:,}")
    return np.frombuffer(data, dtype, offset=HEADER.size).reshape(z, y, x, channels)


def export_volume(src: str, media: Path) -> tuple[object, bool]:
    """(the channel source, whether it is facet's stand-in) of an export's volume input
    ``src``: the file in ``media`` when it is there, else Shadertoy's built-in volume its
    media id names (facet's noise of the same size and channels)."""
    name = Path(src).name
    if name and (media / name).is_file():
        return media / name, False
    kind = SHADERTOY_VOLUMES.get(Path(name).stem)
    if kind is None:
        raise InputError(f"a volume input needs the media file {name!r}, which is not in "
                         f"{media} (download it there, or give --media DIR)")
    return f"{kind}-noise3d", True


def write_volume(path, texels: np.ndarray) -> None:
    """Write (Z, Y, X, C) uint8 or float32 texels as a ``.bin`` volume (tests, tools)."""
    z, y, x, channels = texels.shape
    fmt = {np.dtype(np.uint8): 0, np.dtype(np.float32): 10}[texels.dtype]
    Path(path).write_bytes(HEADER.pack(b"BIN\0", x, y, z, channels, 0, fmt) +
                           np.ascontiguousarray(texels).tobytes())
