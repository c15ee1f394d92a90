"""Textures as images in memory (no GL): what a material's diffuse colour is multiplied by.

``Texture.pixels`` is (H, W, 4) uint8, row 0 at the top, values as stored in the image file
(sRGB-encoded for ordinary images). Texture coordinates follow OpenGL: (0, 0) is the
bottom-left corner of the image, (1, 1) the top-right. How the bytes become colours is the
renderer's colour mode (see facet.render.colors).
"""

from __future__ import annotations

from typing import Annotated

import numpy as np

from ..boundary import Array, ArrayLike, FilePath, checked
from ..errors import InputError
from .readers import reader  # facet.formats.images reads the file


class Texture:
    """An RGBA8 image to sample (row 0 is the top, v = 1).

    Parameters
    ----------
    pixels : (H, W, 3) or (H, W, 4) uint8
        The image (alpha 255 is added to RGB).
    name : str
        Label used in messages.
    """

    @checked
    def __init__(self, pixels: Annotated[ArrayLike, Array("H,W,3", "H,W,4", budget="pixels",
                                                          unit=3)],
                 name: str = "texture"):
        a = np.asarray(pixels)
        if a.dtype != np.uint8 or a.ndim != 3 or a.shape[2] not in (3, 4) or min(a.shape[:2]) < 1:
            raise InputError(f"texture {name}: expected (H, W, 3|4) uint8 pixels, got "
                             f"{a.shape} {a.dtype}")
        if a.shape[2] == 3:
            a = np.concatenate([a, np.full(a.shape[:2] + (1,), 255, np.uint8)], axis=2)
        self.pixels = np.ascontiguousarray(a)
        self.pixels.setflags(write=False)
        self.name = name

    @classmethod
    def from_pil(cls, image, name: str = "texture") -> Texture:
        """A texture of a Pillow image.

        Parameters
        ----------
        image : PIL.Image.Image
            Any mode (converted to RGBA).
        name : str
            Label used in messages.

        Returns
        -------
        Texture
            The texture.
        """
        return cls(np.asarray(image.convert("RGBA")), name)

    @classmethod
    @checked
    def load(cls, path: FilePath) -> Texture:
        """Read an image file through Pillow.

        Parameters
        ----------
        path : str or Path
            The file.

        Returns
        -------
        Texture
            The texture, named after the file.

        Raises
        ------
        facet.InputError
            When it cannot be read, or is beyond facet's pixel budget (facet.guard).
        """
        return reader("texture")(path)

    @classmethod
    def checker(cls, squares: int = 8, size: int = 512,
                colors=((0.85, 0.85, 0.85), (0.25, 0.25, 0.25))) -> Texture:
        """A checkerboard, for models with texture coordinates but no image.

        Parameters
        ----------
        squares : int
            Squares along each side.
        size : int
            Pixels along each side (squares <= size <= 8192).
        colors : two (3,) float
            The squares' colours in [0, 1]; the bottom-left square has the first.

        Returns
        -------
        Texture
            The texture.
        """
        if not (1 <= squares <= size and 1 <= size <= 8192):
            raise InputError(f"checker: need 1 <= squares <= size <= 8192, got {squares}, "
                             f"{size}")
        c = np.rint(np.asarray(colors, dtype=np.float64) * 255).astype(np.uint8)
        idx = np.arange(size) * squares // size
        # Row 0 is the top of the image, i.e. v = 1: count squares from the bottom row.
        rows = (squares - 1 - idx)[:, None]
        pattern = (rows + idx[None, :]) % 2
        return cls(c[pattern], f"checker{squares}")

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) in pixels."""
        return self.pixels.shape[1], self.pixels.shape[0]

    def __repr__(self) -> str:
        return f"Texture({self.name!r}, {self.size[0]}x{self.size[1]})"
