"""``Frame``: one render's results as numpy arrays, row 0 at the top.

    frame.color       # (H, W, 4) uint8 (float32 with float_color), straight alpha
    frame.depth       # (H, W) float32, linear depth along the camera axis, 0 = no hit
    frame.object_ids  # (H, W) int32, -1 = background
    frame.normals     # (H, W, 3) float32 world-space unit normals, 0 = no hit
    frame.position    # (H, W, 3) float32 world-space positions, 0 = no hit
    frame.uv          # (H, W, 2) float32 texture coordinates, 0 = no hit or no uvs
    frame.spp         # (H, W) int32 paths (samples) each pixel's colour is the mean of

Only colour is anti-aliased: every other channel comes from pixel centres whatever the
anti-aliasing, so values are exact and labels never blend. Outputs not asked for are None.

How they are made exact. Without MSAA or supersampling, one pass draws colour and every
channel together (multiple render targets, one sample per pixel, at its centre). Under MSAA
no sample sits at the pixel centre, and a triangle can cover a centre while covering none
of the samples (common on meshes with sub-pixel triangles), so no resolve of the samples
can give the centre's values: the channels get a single-sample pass of their own (culled
like the colour pass, computing no colour). That pass is drawn when a channel is first
read, from a snapshot of the scene taken at ``render``; a caller that uses colour only
never pays for it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np

from ..boundary import Count, FilePath, checked
from ..errors import InputError
from ..geometry.camera import Camera

CHANNELS = ("depth", "object_ids", "normals", "position", "uv")


class Frame:
    """One render's results as numpy arrays, row 0 at the top (the module docstring says
    how the exact channels are made).

    The exact channels are read back from the GPU when first used: a caller that looks only at
    ``color`` does not pay for depth and ids. Reading happens in the thread that rendered;
    ``settle()`` there before handing a frame to another thread or process.

    Parameters
    ----------
    color : (H, W, 4) uint8 or float32, or None
        Straight alpha; float32 with ``float_color`` (linear).
    depth : (H, W) float32, or None
        Linear depth along the camera axis, scene units; 0 where nothing was hit.
    object_ids : (H, W) int32, or None
        The ids ``Scene.add`` returned; -1 for the background.
    camera : Camera
        The camera rendered through.
    normals : (H, W, 3) float32, optional
        World-space unit normals; 0 where nothing was hit.
    position : (H, W, 3) float32, optional
        World-space positions; 0 where nothing was hit.
    uv : (H, W, 2) float32, optional
        Texture coordinates; 0 where nothing was hit or there are none.
    size : (int, int)
        (width, height).
    spp : (H, W) int32, optional
        The samples (paths) each pixel's colour is the mean of: fewer where adaptive
        sampling stopped a pixel early (``noise``), the count a time limit reached.
    """

    def __init__(self, color, depth, object_ids, camera: Camera, normals=None,
                 position=None, uv=None, size: tuple[int, int] = (0, 0), spp=None):
        self.color = color
        self.spp = spp
        self.camera = camera
        self.size = size
        # channel -> an array, None (not asked for), or a callable that reads it
        self._channels = dict(zip(CHANNELS, (depth, object_ids, normals, position, uv),
                                  strict=True))

    def _get(self, name: str):
        value = self._channels[name]
        if callable(value):
            value = self._channels[name] = value()
        return value

    depth = property(lambda self: self._get("depth"))
    object_ids = property(lambda self: self._get("object_ids"))
    normals = property(lambda self: self._get("normals"))
    position = property(lambda self: self._get("position"))
    uv = property(lambda self: self._get("uv"))

    @property
    def unread(self) -> bool:
        return any(callable(v) for v in self._channels.values())

    def settle(self) -> None:
        """Read every channel not read yet (the renderer calls this before it draws over
        the targets they are in)."""
        for name in CHANNELS:
            self._get(name)

    def __getstate__(self) -> dict:
        """Pickled (to a writer process) with every channel read."""
        self.settle()
        return self.__dict__

    def __repr__(self) -> str:
        shown = [n for n, v in self._channels.items() if v is not None]
        return f"Frame({self.size[0]}x{self.size[1]}, color, {', '.join(shown)})"

    def camera_normals(self) -> np.ndarray:
        """Normals in camera space.

        Returns
        -------
        (H, W, 3) float32 ndarray
            OpenGL axes: x right, y up, z towards the viewer.
        """
        if self.normals is None:
            raise InputError("this frame has no normals; render with outputs=(..., 'normals')")
        return (self.normals @ self.camera.view[:3, :3].T).astype(np.float32)

    def camera_info(self) -> dict:
        """The camera as plain data for this image size.

        Returns
        -------
        dict
            ``Camera.describe(width, height)``.
        """
        return self.camera.describe(*self.size)

    def _repr_png_(self) -> bytes | None:
        """The colour image as PNG bytes: how Jupyter and IPython show a Frame inline."""
        from ..image.png import encode_png
        from ..image.writers import to_uint8

        if self.color is None:
            return None
        rgba = to_uint8(self.color)
        if rgba.ndim == 3 and rgba.shape[2] == 4 and np.all(rgba[..., 3] == 255):
            rgba = rgba[..., :3]
        return encode_png(np.ascontiguousarray(rgba), 6)

    def _repr_html_(self) -> str:
        """The picture beside its size, channels and camera (Jupyter's rich display)."""
        import base64
        import html

        shown = [n for n, v in self._channels.items() if v is not None]
        info = self.camera_info()
        rows = [("size", f"{self.size[0]} x {self.size[1]}"),
                ("channels", ", ".join(["color", *shown] if self.color is not None
                                       else shown) or "none"),
                ("camera", "orthographic" if info.get("ortho_height") else
                 f"perspective, fov_y {info.get('fov_y', 0):.1f} deg"),
                ("eye", ", ".join(f"{v:.3g}" for v in self.camera.eye))]
        table = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
                        f"<td>{html.escape(str(v))}</td></tr>" for k, v in rows)
        png = self._repr_png_()
        image = "" if png is None else (
            "<img src='data:image/png;base64," + base64.b64encode(png).decode() + "'/>")
        return (f"<div style='display:flex;gap:1em;align-items:flex-start'>{image}"
                f"<table>{table}</table></div>")

    @checked
    def save(self, path: FilePath,
             quality: Annotated[int | None, Count(1, 100)] = None) -> Path:
        """Write the colour image, its format by the file's suffix.

        PNG (RGBA if the background is transparent), JPEG, WebP or TIFF; with float colour
        (``float_color=True``) OpenEXR or Radiance HDR keep the linear values.

        Parameters
        ----------
        path : str or Path
            The file (its folder must exist).
        quality : int, optional
            JPEG / WebP quality, 1-100.

        Returns
        -------
        Path
            The file written.
        """
        from ..image.writers import FLOAT_FORMATS, save_float_color, save_image, to_uint8

        if self.color is None:
            raise InputError("this frame has no colour output to save")
        if Path(path).suffix.lower() in FLOAT_FORMATS:
            if self.color.dtype == np.uint8:
                raise InputError(f"{path}: keeps linear float colour; render with "
                                 "float_color=True")
            return save_float_color(path, self.color)
        return save_image(path, to_uint8(self.color), quality)
