"""Image output: writing colour, depth and ids to files (PNG, .npy), atomically."""

from .writers import save_array, save_image, save_png16, to_uint8, write_atomic

__all__ = ["save_array", "save_image", "save_png16", "to_uint8", "write_atomic"]
