"""Writing every channel of a render to disk, as `facet render --outputs ... --out-dir` does.

File names inside the output folder (``prefix`` goes before each):

  color.png       colour: 8-bit (RGBA if the background is transparent), 16-bit with
                  ``bits=(16,)``, reduced bit depth / dithered / palette when asked
  depth.npy       linear depth, float32 (exact);  depth.png  colourised preview
  depth_mm.png    with ``png16``: depth in millimetres, 16-bit grey, 0 = no hit
  ids.npy         object ids, int32, -1 = background;  ids.png  colourised preview
  normals.npy     unit normals, float32 (H, W, 3), world or camera space;
  normals.png     n * 0.5 + 0.5, 8-bit (16-bit with ``png16``), black = no hit
  position.npy    world positions, float32 (H, W, 3)
  uv.npy          texture coordinates, float32 (H, W, 2);  uv.png  (u, v, 0) preview
  camera.json     the camera (``Camera.describe``): K, world-to-camera, near/far, size

Each file is written atomically (temporary name, then rename).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from . import preview, quantize
from .writers import save_array, save_image, save_indexed, save_png16, to_uint8, write_atomic

MM_PER_UNIT = 1000.0  # depth_mm.png assumes scene units are metres


@dataclass
class ColorOptions:
    """How colour is quantised on output."""

    bits: tuple[int, ...] = (8,)
    dither: str = "none"
    palette: int | None = None
    palette_method: str = "median-cut"

    @property
    def needs_float(self) -> bool:
        """Whether the render should keep float colour (16-bit, dithering, reduced bits)."""
        return self.bits != (8,) or self.dither != "none" or self.palette is not None


def encode_color(color: np.ndarray, options: ColorOptions):
    """The colour image to write: (kind, array) with kind 'png8' or 'png16'."""
    if options.bits == (16,):
        rgb = np.clip(np.asarray(color, dtype=np.float64)[..., :3], 0, 1)
        return "png16", np.rint(rgb * 65535).astype(np.uint16)
    if options.palette is not None:
        return "png8", quantize.palette(_float_rgb(color), options.palette,
                                        options.palette_method, options.dither)
    if options.bits != (8,) or options.dither != "none":
        return "png8", quantize.reduce_bits(_float_rgb(color), options.bits, options.dither,
                                            grey=quantize.is_grey(options.bits))
    return "png8", to_uint8(color)


def _float_rgb(color: np.ndarray) -> np.ndarray:
    c = np.asarray(color)[..., :3]
    return c / 255.0 if c.dtype == np.uint8 else c


def save_color(path, color: np.ndarray, options: ColorOptions, quality: int | None = None
               ) -> Path:
    """Write a render's colour: float formats (facet.image.writers.FLOAT_FORMATS) keep
    its linear float values, the others take the quantised 8-bit (or 16-bit PNG)
    picture."""
    from .writers import FLOAT_FORMATS, save_float_color

    suffix = Path(path).suffix.lower()
    if suffix in FLOAT_FORMATS:
        if np.asarray(color).dtype == np.uint8:
            raise InputError(f"{path}: {suffix} keeps linear float colour; render with "
                             "float_color=True")
        return save_float_color(path, color)
    kind, image = encode_color(color, options)
    if kind == "png16" and suffix != ".png":
        raise InputError(f"{path}: 16-bit colour is written as PNG (or a float format: "
                         ".exr, .hdr)")
    return save_png16(path, image) if kind == "png16" else save_image(path, image, quality)


def write_outputs(frame, out_dir, channels, options: ColorOptions | None = None, *,
                  png16: bool = False, normals_space: str = "world",
                  prefix: str = "") -> list[Path]:
    """Write the requested ``channels`` of ``frame`` into ``out_dir``; returns the paths."""
    options = options or ColorOptions()
    if normals_space not in ("world", "camera"):
        raise InputError(f"normals space must be 'world' or 'camera', got {normals_space!r}")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a directory")
    name = lambda stem: out / f"{prefix}{stem}"  # noqa: E731
    written: list[Path] = []
    if "color" in channels:
        written.append(save_color(name("color.png"), frame.color, options))
    if "depth" in channels:
        written.append(save_array(name("depth.npy"), frame.depth))
        written.append(save_indexed(name("depth.png"), *preview.depth_indexed(frame.depth)))
        if png16:
            mm = np.clip(np.rint(frame.depth * MM_PER_UNIT), 0, 65535).astype(np.uint16)
            written.append(save_png16(name("depth_mm.png"), mm))
    if "ids" in channels:
        written.append(save_array(name("ids.npy"), frame.object_ids))
        indexed = preview.ids_indexed(frame.object_ids)
        written.append(save_indexed(name("ids.png"), *indexed) if indexed is not None else
                       save_image(name("ids.png"), preview.ids_preview(frame.object_ids)))
    if "normals" in channels:
        normals = frame.normals if normals_space == "world" else frame.camera_normals()
        written.append(save_array(name("normals.npy"), normals))
        if png16:
            hit = np.any(normals != 0, axis=-1)
            n16 = np.rint((np.clip(normals, -1, 1) * 0.5 + 0.5) * 65535).astype(np.uint16)
            n16[~hit] = 0
            written.append(save_png16(name("normals.png"), n16))
        else:
            written.append(save_image(name("normals.png"), preview.normals_preview(normals)))
    if "position" in channels:
        written.append(save_array(name("position.npy"), frame.position))
    if "uv" in channels:
        written.append(save_array(name("uv.npy"), frame.uv))
        uv8 = np.zeros(frame.uv.shape[:2] + (3,), np.uint8)
        uv8[..., :2] = np.rint(np.clip(frame.uv, 0, 1) * 255)
        written.append(save_image(name("uv.png"), uv8))
    if "spp" in channels:
        written.append(save_array(name("spp.npy"), frame.spp))
    written.append(write_camera_json(name("camera.json"), frame.camera_info()))
    return written


def write_camera_json(path, info: dict) -> Path:
    p = Path(path)
    with write_atomic(p) as tmp:
        tmp.write_text(json.dumps(info, indent=2) + "\n")
    return p
