"""Pictures for the wire: JPEG while the view moves (simplejpeg when installed, else
Pillow), PNG once it is still (lossless)."""

from __future__ import annotations

import io

import numpy as np

QUALITY = 80  # JPEG quality while the view moves


def jpeg(picture: np.ndarray, quality: int = QUALITY) -> bytes:
    """``picture``: (H, W, 3) uint8 -> JPEG bytes."""
    picture = np.ascontiguousarray(picture)
    try:
        import simplejpeg
    except ImportError:
        from PIL import Image

        out = io.BytesIO()
        Image.fromarray(picture).save(out, "JPEG", quality=quality)
        return out.getvalue()
    return simplejpeg.encode_jpeg(picture, quality=quality, colorspace="RGB")


def png(picture: np.ndarray) -> bytes:
    """``picture``: (H, W, 3) uint8 -> PNG bytes (fast compression: it is sent once)."""
    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(picture)).save(out, "PNG", compress_level=1)
    return out.getvalue()
