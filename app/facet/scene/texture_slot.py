"""A texture slot: one image a material samples, with glTF's textureInfo settings (its
coordinate set, KHR_texture_transform's matrix, wrap and filter modes) (no GL)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..boundary import reals
from ..errors import InputError

WRAP_MODES = ("repeat", "clamp", "mirror")
FILTERS = ("nearest", "linear")


@dataclass
class TextureSlot:
    """One image a material samples, as glTF's textureInfo describes it.

    Parameters
    ----------
    texture : Texture
        The image.
    texcoord : int
        Which coordinate set: 0 ``Mesh.uvs``, 1 ``Mesh.uvs1``.
    transform : (3, 3) float
        Applied to (u, v, 1) before sampling (KHR_texture_transform; identity without).
    wrap : (str, str)
        (s, t), each of WRAP_MODES (``repeat``, ``clamp``, ``mirror``).
    filter : (str, str)
        (minification, magnification), each of FILTERS.
    mipmaps : bool
        Whether minification blends mip levels.
    """

    texture: object  # facet.scene.texture.Texture
    texcoord: int = 0
    transform: np.ndarray = field(default_factory=lambda: np.eye(3))
    wrap: tuple[str, str] = ("repeat", "repeat")
    filter: tuple[str, str] = ("linear", "linear")
    mipmaps: bool = True

    def __post_init__(self):
        from .texture import Texture

        if not isinstance(self.texture, Texture):
            raise InputError(f"texture slot: expected a facet Texture, got "
                             f"{type(self.texture).__name__}")
        if self.texcoord not in (0, 1):
            raise InputError(f"texture slot: texcoord must be 0 or 1, got {self.texcoord!r}")
        t = reals(self.transform, "texture slot: transform", most=9)
        if t.shape != (3, 3) or not np.all(np.isfinite(t)):
            raise InputError("texture slot: transform must be a finite 3x3 matrix")
        self.transform = t
        for value, allowed, what in ((self.wrap, WRAP_MODES, "wrap"),
                                     (self.filter, FILTERS, "filter")):
            if isinstance(value, str) or not isinstance(value, (tuple, list)) or \
                    len(value) != 2 or any(not isinstance(v, str) or v not in allowed
                                           for v in value):
                raise InputError(f"texture slot: {what} must be two of {', '.join(allowed)}, "
                                 f"got {value!r}")
        self.wrap, self.filter = tuple(self.wrap), tuple(self.filter)


def texture_transform(offset=(0.0, 0.0), rotation: float = 0.0, scale=(1.0, 1.0)) -> np.ndarray:
    """KHR_texture_transform's matrix T(offset) R(rotation) S(scale), (3, 3) on (u, v, 1).
    The rotation turns uv counter-clockwise seen with v down, as the extension defines."""
    c, s = np.cos(rotation), np.sin(rotation)
    t = np.array([[1.0, 0.0, offset[0]], [0.0, 1.0, offset[1]], [0.0, 0.0, 1.0]])
    r = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    return t @ r @ np.diag([scale[0], scale[1], 1.0])
