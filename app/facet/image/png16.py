"""A minimal 16-bit PNG encoder (grey or RGB), because Pillow writes 16-bit PNG only for
single-channel images. Rows are stored unfiltered and zlib-compressed; the format is the one
of the PNG specification (signature, IHDR, IDAT, IEND, each chunk with its CRC)."""

from __future__ import annotations

import struct
import zlib

import numpy as np


def _chunk(kind: bytes, data: bytes) -> bytes:
    return (struct.pack(">I", len(data)) + kind + data
            + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))


def encode_png16(image: np.ndarray) -> bytes:
    """PNG bytes of a uint16 image, (H, W) grey or (H, W, 3) RGB."""
    a = np.asarray(image)
    if a.dtype != np.uint16 or a.ndim not in (2, 3) or (a.ndim == 3 and a.shape[2] != 3):
        raise ValueError(f"encode_png16 expects (H, W) or (H, W, 3) uint16, got {a.shape} "
                         f"{a.dtype}")
    h, w = a.shape[:2]
    color_type = 0 if a.ndim == 2 else 2
    rows = a.astype(">u2").reshape(h, -1).view(np.uint8)
    raw = np.hstack([np.zeros((h, 1), np.uint8), rows])  # filter type 0 per row
    header = struct.pack(">IIBBBBB", w, h, 16, color_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", header)
            + _chunk(b"IDAT", zlib.compress(raw.tobytes(), 6)) + _chunk(b"IEND", b""))


def decode_png16(data: bytes) -> np.ndarray:
    """Inverse of ``encode_png16`` for files it wrote (unfiltered rows); used by tests."""
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    w, h, depth, color_type = header[:4]
    channels = 1 if color_type == 0 else 3
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + w * channels * 2)
    values = raw[:, 1:].copy().view(">u2").astype(np.uint16)
    return values.reshape(h, w) if channels == 1 else values.reshape(h, w, 3)
