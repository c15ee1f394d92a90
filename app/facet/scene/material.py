"""Phong materials: the constants of the notes' shading equation.

``I = I_a k_a C + sum_i I_i (k_d C max(N·L_i, 0) + k_s max(R_i·V, 0)^n)``; ``color`` is C
(linear floats in [0, 1]), ``shininess`` is n. The specular highlight takes the light's colour.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..boundary import finite, reals
from ..errors import InputError


def as_color(value, name: str, channels=(3,)) -> np.ndarray:
    """Validate a colour: a number (grey) or 3 (or 4, where allowed) floats in [0, 1]."""
    a = reals(value, name, most=max(channels)).reshape(-1)
    if a.size == 1:
        a = np.repeat(a, 3)
    if a.size not in channels or not np.all(np.isfinite(a)) or a.min() < 0 or a.max() > 1:
        want = " or ".join(str(c) for c in channels)
        raise InputError(f"{name} must be a grey level or {want} floats in [0, 1], got {value!r}")
    return a


@dataclass
class Material:
    """A Phong material (``PbrMaterial`` is glTF's metallic-roughness).

    The shading equation is the notes' Phong: ambient ``ka``, diffuse ``kd`` and specular
    ``ks`` terms with exponent ``shininess``. ``texture`` multiplies ``color`` at each point by
    the image at the mesh's texture coordinates; the mesh's vertex colours, if any, multiply
    it too.

    Parameters
    ----------
    color : (3,) float
        Base colour in [0, 1] (display-referred, like a picked colour).
    ka, kd, ks : float
        Ambient, diffuse and specular weights (>= 0).
    shininess : float
        The specular exponent n (>= 0).
    name : str
        Label used in messages.
    texture : Texture, optional
        An image over the mesh's uvs.
    shader : UserShader, optional
        The material's own GLSL (facet.scene.shader).
    opacity : float
        Below 1: transparent (order-independent transparency).
    reflectivity : float
        In [0, 1]: the mix towards the scene's environment (or, with ``mirror``, the
        mirrored scene).
    ior : float
        Index of refraction (> 1) for refraction with Fresnel; 0: none.
    gloss : float
        0: a sharp mirror; up to 1: reflections blurred (by supersampling).
    mirror : bool
        A planar mirror (needs a flat mesh and ``reflectivity`` > 0).
    """

    color: np.ndarray = field(default_factory=lambda: np.array([0.8, 0.8, 0.8]))
    ka: float = 1.0
    kd: float = 0.8
    ks: float = 0.3
    shininess: float = 32.0
    name: str = ""
    texture: object = None
    shader: object = None  # a facet.scene.shader.UserShader: the material's own GLSL
    opacity: float = 1.0  # < 1: transparent (order-independent, facet.render.raster.transparency)
    reflectivity: float = 0.0  # mix towards the scene's environment (reflection/refraction)
    ior: float = 0.0  # index of refraction (> 1) for refraction with Fresnel; 0: none
    gloss: float = 0.0  # 0: a sharp mirror; up to 1: reflections blurred (by supersampling)
    # A planar mirror: a flat object showing the scene mirrored in its plane, mixed in by
    # ``reflectivity`` (facet.render.raster.mirror). Needs a flat mesh and reflectivity > 0.
    mirror: bool = False

    @property
    def transparent(self) -> bool:
        """Drawn in the transparent pass (order-independent, facet.render.raster.transparency)."""
        return self.opacity < 1.0

    def __post_init__(self):
        from .texture import Texture

        self.color = as_color(self.color, "material color")
        if self.texture is not None and not isinstance(self.texture, Texture):
            raise InputError(f"material texture must be a facet Texture, got "
                             f"{type(self.texture).__name__}")
        from .shader import UserShader

        if self.shader is not None and not isinstance(self.shader, UserShader):
            raise InputError(f"material shader must be a facet UserShader, got "
                             f"{type(self.shader).__name__}")
        if not (isinstance(self.opacity, (int, float, np.floating)) and
                0.0 <= self.opacity <= 1.0):
            raise InputError(f"material opacity must be a number in [0, 1], got "
                             f"{self.opacity!r}")
        self.opacity = float(self.opacity)
        if not (isinstance(self.reflectivity, (int, float)) and 0 <= self.reflectivity <= 1):
            raise InputError(f"material reflectivity must be in [0, 1], got "
                             f"{self.reflectivity!r}")
        if not (isinstance(self.ior, (int, float)) and (self.ior == 0 or 1 <= self.ior <= 5)):
            raise InputError(f"material ior must be 0 (none) or in [1, 5], got {self.ior!r}")
        self.reflectivity, self.ior = float(self.reflectivity), float(self.ior)
        if not (isinstance(self.gloss, (int, float)) and 0 <= self.gloss <= 1):
            raise InputError(f"material gloss must be in [0, 1], got {self.gloss!r}")
        self.gloss = float(self.gloss)
        if not isinstance(self.mirror, (bool, np.bool_)):
            raise InputError(f"material mirror must be true or false, got {self.mirror!r}")
        if self.mirror and self.reflectivity == 0:
            raise InputError("a mirror material needs reflectivity > 0 (how much of the "
                             "mirrored scene it shows; 1: a perfect mirror)")
        self.mirror = bool(self.mirror)
        for key in ("ka", "kd", "ks", "shininess"):
            v = getattr(self, key)
            if not (finite(v) and v >= 0):
                raise InputError(f"material {key} must be a number >= 0, got {v!r}")
            setattr(self, key, float(v))
