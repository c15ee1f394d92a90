"""Reading X window dumps (``xwd -root``) into numpy, for the viewer's window tests."""

from __future__ import annotations

import struct

import numpy as np


def read_xwd(data: bytes) -> np.ndarray:
    """(H, W, 3) uint8 RGB of a 24/32-bit ZPixmap XWD dump."""
    fields = struct.unpack(">25I", data[:100])
    header_size, _, pixmap_format, depth, width, height = fields[:6]
    byte_order, bits_per_pixel, bytes_per_line = fields[7], fields[11], fields[12]
    red_mask, green_mask, blue_mask = fields[14:17]
    ncolors = fields[19]
    if pixmap_format != 2 or bits_per_pixel not in (24, 32) or depth < 24:
        raise ValueError(f"unsupported XWD: format {pixmap_format}, {bits_per_pixel} bpp")
    start = header_size + 12 * ncolors
    nbytes = bits_per_pixel // 8
    rows = np.frombuffer(data[start:start + bytes_per_line * height], np.uint8)
    pixels = rows.reshape(height, bytes_per_line)[:, :width * nbytes].reshape(height, width,
                                                                             nbytes)
    order = range(nbytes) if byte_order == 0 else range(nbytes - 1, -1, -1)  # LSB first?
    words = np.zeros((height, width), np.uint32)
    for i, b in enumerate(order):
        words |= pixels[..., b].astype(np.uint32) << (8 * i)

    def channel(mask):
        shift = (mask & -mask).bit_length() - 1
        return ((words & mask) >> shift).astype(np.uint8)

    return np.stack([channel(red_mask), channel(green_mask), channel(blue_mask)], axis=-1)
