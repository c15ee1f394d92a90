"""High-dynamic-range images for environments (no GL): linear radiance as float32.

- Radiance RGBE (``.hdr``, ``.pic``): read here (Pillow does not read it): the header, then
  flat or run-length-encoded scanlines (the "new" RLE: four channel runs per line);
  RGBE -> RGB is mantissa x 2^(exponent - 136).
- OpenEXR (``.exr``): through the OpenEXR package (``pip install facet-render[exr]``).

``write_hdr`` writes flat RGBE files (tests and tools).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError

HDR_SUFFIXES = (".hdr", ".pic", ".exr")
# The brightest radiance an environment may hold: beyond any sun (about 1e9 in absolute
# units, 1e5-1e6 in HDR maps), and far enough below float32's 3.4e38 that lighting sums
# of it stay finite in a float picture.
MAX_RADIANCE = 1e18


def is_hdr(path) -> bool:
    return Path(path).suffix.lower() in HDR_SUFFIXES


def read_hdr_image(path) -> np.ndarray:
    """(H, W, 3) float32 linear radiance of a .hdr/.pic or .exr file; InputError (one
    line, naming the file) when it cannot be read."""
    from ..guard import read_bytes, regular_file

    # Through the guard: a FIFO, a device, a file outside --confine or beyond the file
    # budget is refused before it is opened.
    p = regular_file(path, "environment file")
    rgb = _read_exr(p) if p.suffix.lower() == ".exr" else \
        _read_rgbe(p, read_bytes(p, "environment file"))
    peak = float(rgb.max()) if rgb.size else 0.0
    if not np.isfinite(rgb).all() or peak > MAX_RADIANCE:
        raise InputError(f"{p}: holds radiance that is not finite or beyond {MAX_RADIANCE:g} "
                         f"(up to {peak:.3g}); facet's float pictures would overflow to inf")
    return rgb


def _read_rgbe(p: Path, data: bytes) -> np.ndarray:
    try:
        return _decode_rgbe(data, p.name)
    except InputError:  # beyond a budget: its own line
        raise
    except (ValueError, IndexError) as exc:
        raise InputError(f"{p}: not a readable Radiance HDR file ({exc})") from None


def _decode_rgbe(data: bytes, name: str = "HDR image") -> np.ndarray:
    from ..budgets import check_pixels

    if not (data.startswith(b"#?RADIANCE") or data.startswith(b"#?RGBE")):
        raise ValueError("no #?RADIANCE header")
    end = data.find(b"\n\n")
    if end < 0:
        raise ValueError("the header does not end")
    header = data[:end].decode("ascii", "replace")
    if "FORMAT=" in header and "32-bit_rle_rgbe" not in header:
        raise ValueError("only 32-bit_rle_rgbe is supported (not XYZE)")
    line_end = data.find(b"\n", end + 2)
    if line_end < 0:
        raise ValueError("no pixel data (the size line has no end)")
    size = data[end + 2:line_end].decode("ascii", "replace").split()
    if len(size) != 4 or size[0] != "-Y" or size[2] != "+X":
        raise ValueError(f"unsupported orientation {' '.join(size)!r} (expected -Y H +X W)")
    if not (size[1].isdigit() and size[3].isdigit()):
        raise ValueError(f"image size {size[3]!r} x {size[1]!r}")
    height, width = int(size[1]), int(size[3])
    if not (0 < width <= 1 << 15 and 0 < height <= 1 << 15):
        raise ValueError(f"image size {width}x{height}")
    check_pixels(width, height, name)  # before anything is allocated
    body = np.frombuffer(data, np.uint8, offset=line_end + 1)
    least = height * (4 if width >= 8 else 4 * width)  # a scanline's start, or a flat one
    if len(body) < least:
        raise ValueError(f"{len(body)} bytes of pixel data for {width}x{height} pixels; "
                         "is it truncated?")
    out = np.empty((height, width, 4), np.uint8)
    pos = 0
    for y in range(height):  # per scanline, and per run within one: never per pixel
        head = body[pos:pos + 4]
        if width < 8 or width > 0x7FFF or head[0] != 2 or head[1] != 2 or head[2] & 0x80:
            out[y] = body[pos:pos + 4 * width].reshape(width, 4)  # flat
            pos += 4 * width
            continue
        pos += 4
        for c in range(4):
            x = 0
            while x < width:
                n = int(body[pos])
                if n > 128:
                    out[y, x:x + n - 128, c] = body[pos + 1]
                    x, pos = x + n - 128, pos + 2
                else:
                    if n == 0:
                        raise ValueError("a run of length 0")
                    out[y, x:x + n, c] = body[pos + 1:pos + 1 + n]
                    x, pos = x + n, pos + 1 + n
            if x != width:
                raise ValueError(f"scanline {y} overruns its width")
    # RGBE -> RGB in float32 by a table of the 256 exponents (no float64 image).
    table = np.where(np.arange(256) > 0, np.ldexp(1.0, np.arange(256) - 136), 0.0).astype(
        np.float32)
    return out[..., :3] * table[out[..., 3]][..., None]


def _read_exr(p: Path) -> np.ndarray:
    try:
        import OpenEXR
    except ImportError:
        raise InputError(f"{p}: reading OpenEXR needs the OpenEXR package (pip install "
                         "'facet-render[exr]')") from None
    from ..guard import opened_name

    try:
        with opened_name(p, "environment file") as name, \
                OpenEXR.File(name, header_only=True) as f:  # the size, before any pixel
            (x0, y0), (x1, y1) = (np.asarray(c).tolist() for c in
                                  f.header()["dataWindow"])
    except InputError:  # the guard's refusal: its own line
        raise
    except Exception as exc:  # OpenEXR raises plain exceptions on bad files
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"{p}: not a readable OpenEXR file ({first})") from None
    from ..budgets import check_pixels

    check_pixels(x1 - x0 + 1, y1 - y0 + 1, p.name)
    try:
        with opened_name(p, "environment file") as name, OpenEXR.File(name) as f:
            channels = f.channels()
            if "RGB" in channels:
                rgb = np.asarray(channels["RGB"].pixels, dtype=np.float32)
            else:
                rgb = np.stack([np.asarray(channels[c].pixels, dtype=np.float32)
                                for c in "RGB"], -1)
    except InputError:
        raise
    except Exception as exc:  # OpenEXR raises plain exceptions on bad files
        raise InputError(f"{p}: not a readable OpenEXR file with R, G, B channels "
                         f"({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})"
                         ) from None
    return np.ascontiguousarray(rgb[..., :3], dtype=np.float32)


def write_hdr(path, rgb: np.ndarray) -> None:
    """Write (H, W, 3) linear radiance as a flat Radiance RGBE file."""
    rgb = np.maximum(np.asarray(rgb, dtype=np.float64), 0.0)
    peak = rgb.max(axis=-1)
    mantissa, exponent = np.frexp(peak)
    scale = np.where(peak > 1e-32, mantissa * 256.0 / np.where(peak > 0, peak, 1), 0.0)
    rgbe = np.zeros(rgb.shape[:2] + (4,), np.uint8)
    rgbe[..., :3] = np.clip(rgb * scale[..., None], 0, 255).astype(np.uint8)
    rgbe[..., 3] = np.where(peak > 1e-32, exponent + 128, 0).astype(np.uint8)
    h, w = rgb.shape[:2]
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode()
    Path(path).write_bytes(header + rgbe.tobytes())
