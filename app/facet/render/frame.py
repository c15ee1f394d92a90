"""``Frame``: one render's results as numpy arrays, row 0 at the top.

    frame.color       # (H, W, 4) uint8 (float32 with float_color), straight alpha
    frame.depth       # (H, W) float32, linear depth along the camera axis, 0 = no hit
    frame.object_ids  # (H, W) int32, -1 = background
    frame.normals     # (H, W, 3) float32 world-space unit normals, 0 = no hit
    frame.position    # (H, W, 3) float32 world-space positions, 0 = no hit
    frame.uv          # (H, W, 2) float32 texture coordinates, 0 = no hit or no uvs

Only colour is anti-aliased: every other channel comes from pixel centres whatever the
anti-aliasing, so values are exact and labels never blend. Outputs not asked for are None.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry.camera import Camera


@dataclass
class Frame:
    """One render's results (see the module docstring)."""

    color: np.ndarray | None
    depth: np.ndarray | None
    object_ids: np.ndarray | None
    camera: Camera
    normals: np.ndarray | None = None
    position: np.ndarray | None = None
    uv: np.ndarray | None = None
    size: tuple[int, int] = (0, 0)  # (width, height)

    def camera_normals(self) -> np.ndarray:
        """Normals in camera space (OpenGL axes: x right, y up, z towards the viewer)."""
        if self.normals is None:
            raise InputError("this frame has no normals; render with outputs=(..., 'normals')")
        return (self.normals @ self.camera.view[:3, :3].T).astype(np.float32)

    def camera_info(self) -> dict:
        """The camera as plain data (see ``Camera.describe``) for this image size."""
        return self.camera.describe(*self.size)

    def save(self, path):
        """Write the colour image (PNG; RGBA if the background is transparent)."""
        from ..image.writers import save_image, to_uint8

        if self.color is None:
            raise InputError("this frame has no colour output to save")
        return save_image(path, to_uint8(self.color))
