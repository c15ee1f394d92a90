"""Physically based materials: glTF 2.0's metallic-roughness model (no GL).

The colours here are *linear* (glTF's factors are; its base-colour and emissive images are
sRGB-encoded and decoded when sampled). The renderer shades them with the glTF spec's BRDF
(glsl/lib/pbr.glsl, ``shading = "pbr"``, chosen for these materials unless the user asks
for another model). Where a Phong-only path meets one (``shading = "phong"``, the ray
tracer), the Phong properties below stand in, mapped as documented on each.

A light of intensity I gives irradiance pi I (so a white Lambertian surface facing it shows
I, as a Phong surface with k_d = 1 does); an environment of radiance L lights a white
Lambertian surface to L.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field

import numpy as np

from ..boundary import finite, reals
from ..errors import InputError
from .material import as_color
from .texture_slot import FILTERS, WRAP_MODES, TextureSlot, texture_transform  # noqa: F401

ALPHA_MODES = ("OPAQUE", "MASK", "BLEND")


SLOTS = ("base_color", "metallic_roughness", "normal", "occlusion", "emissive",
         # the KHR extensions' (each multiplies its factor; channels as the extension says)
         "specular", "specular_color", "transmission", "thickness", "clearcoat",
         "clearcoat_roughness", "clearcoat_normal", "sheen_color", "sheen_roughness",
         "iridescence", "iridescence_thickness", "anisotropy", "diffuse_transmission",
         "diffuse_transmission_color")
COLOR_SLOTS = ("base_color", "emissive", "specular_color", "sheen_color",
               "diffuse_transmission_color")  # sRGB images


@dataclass
class PbrMaterial:
    """glTF's metallic-roughness material, with the KHR material extensions.

    The dielectric's specular lobe (KHR_materials_ior and _specular) reflects
    ((ior - 1) / (ior + 1))^2 at normal incidence (0.04 at ior 1.5) times ``specular_color``,
    clipped to 1, times ``specular``; ``specular`` 0 leaves a Lambertian surface.
    ``transmission`` is the share of the dielectric's diffuse part that passes through,
    tinted by the base colour (smooth: Snell's refraction; rough: GGX transmission);
    ``thickness`` 0 is thin-walled, above 0 the mesh bounds a volume of index ``ior`` that
    absorbs by Beer-Lambert (``attenuation_color`` is what is left after
    ``attenuation_distance``). ``clearcoat`` is a clear layer (ior 1.5) on top, a second GGX
    lobe; ``sheen_color`` the soft back-scattering of cloth; ``iridescence`` a thin film
    (KHR_materials_iridescence: index ``iridescence_ior``, ``iridescence_thickness_max``
    nanometres thick, or between the minimum and the maximum by its thickness texture's G)
    whose interference (Belcour and Barla 2017, as the extension gives it) replaces the
    specular Fresnel term by that share; ``anisotropy`` stretches the specular lobe along
    the surface's tangent turned by ``anisotropy_rotation`` (KHR_materials_anisotropy:
    roughness alpha along it mixed towards 1 by anisotropy^2); ``diffuse_transmission`` the
    share of the diffuse part that goes through the surface as a Lambertian lobe of colour
    ``diffuse_transmission_color`` (KHR_materials_diffuse_transmission: leaves, paper,
    wax; ``transmission`` overrides it); ``dispersion`` spreads a transmitting volume's
    index over the colours (KHR_materials_dispersion: 20 / Abbe number; red, green and blue
    refract at ior -+ (ior - 1) 0.025 dispersion, as the Khronos Sample Viewer spreads it).
    Vertex colours multiply the base colour. Each
    extension's texture multiplies its factor.

    Parameters
    ----------
    base_color : (4,) float
        Linear RGBA.
    metallic, roughness : float
        In [0, 1].
    emissive : (3,) float
        Linear emitted radiance, times ``emissive_strength``.
    emissive_strength : float
        KHR_materials_emissive_strength.
    base_color_texture : TextureSlot, optional
        sRGB RGBA, multiplies ``base_color``.
    metallic_roughness_texture : TextureSlot, optional
        B: metallic, G: roughness.
    normal_texture : TextureSlot, optional
        Tangent-space normals; x and y scaled by ``normal_scale``.
    normal_scale : float
        See ``normal_texture``.
    occlusion_texture : TextureSlot, optional
        R, mixed in by ``occlusion_strength``.
    occlusion_strength : float
        See ``occlusion_texture``.
    emissive_texture : TextureSlot, optional
        sRGB, multiplies ``emissive``.
    alpha_mode : str
        ``OPAQUE`` (alpha ignored), ``MASK`` (drawn where alpha >= ``alpha_cutoff``) or
        ``BLEND`` (transparent).
    alpha_cutoff : float
        See ``alpha_mode``.
    double_sided : bool
        False culls back faces.
    unlit : bool
        Shows the base colour only (KHR_materials_unlit).
    name : str
        Label used in messages.
    ior : float
        Index of refraction (KHR_materials_ior).
    specular : float
        KHR_materials_specular's factor (``specular_texture``: A).
    specular_color : (3,) float
        Linear (``specular_color_texture``: sRGB RGB).
    transmission : float
        KHR_materials_transmission (``transmission_texture``: R).
    thickness : float
        KHR_materials_volume (``thickness_texture``: G).
    attenuation_color : (3,) float
        What is left after ``attenuation_distance`` inside the volume.
    attenuation_distance : float
        Scene units (inf: clear).
    clearcoat, clearcoat_roughness : float
        KHR_materials_clearcoat (``clearcoat_texture``: R, ``clearcoat_roughness_texture``:
        G, ``clearcoat_normal_texture`` scaled by ``clearcoat_normal_scale``).
    sheen_color : (3,) float
        KHR_materials_sheen, linear (``sheen_color_texture``: sRGB RGB).
    sheen_roughness : float
        KHR_materials_sheen (``sheen_roughness_texture``: A).
    specular_texture, specular_color_texture : TextureSlot, optional
        KHR_materials_specular's textures (above).
    transmission_texture, thickness_texture : TextureSlot, optional
        KHR_materials_transmission's and _volume's (above).
    clearcoat_texture, clearcoat_roughness_texture : TextureSlot, optional
        The clear coat's factors' textures.
    clearcoat_normal_texture : TextureSlot, optional
        The coat's own tangent-space normals.
    clearcoat_normal_scale : float
        See ``clearcoat_normal_texture``.
    sheen_color_texture, sheen_roughness_texture : TextureSlot, optional
        The sheen's textures.
    iridescence : float
        KHR_materials_iridescence's factor in [0, 1] (``iridescence_texture``: R).
    iridescence_ior : float
        The film's index of refraction (>= 1).
    iridescence_thickness_min, iridescence_thickness_max : float
        The film's thickness in nanometres: the maximum without a thickness texture, else
        mixed between them by ``iridescence_thickness_texture``'s G.
    iridescence_texture, iridescence_thickness_texture : TextureSlot, optional
        The film's textures.
    anisotropy : float
        KHR_materials_anisotropy's strength in [0, 1] (``anisotropy_texture``: B).
    anisotropy_rotation : float
        Radians from the tangent towards the bitangent.
    anisotropy_texture : TextureSlot, optional
        RG: the direction in the tangent frame ([0, 1] for [-1, 1]), B: strength.
    diffuse_transmission : float
        In [0, 1] (``diffuse_transmission_texture``: A).
    diffuse_transmission_color : (3,) float
        Linear (``diffuse_transmission_color_texture``: sRGB RGB).
    diffuse_transmission_texture, diffuse_transmission_color_texture : TextureSlot, optional
        Their textures.
    dispersion : float
        KHR_materials_dispersion (>= 0; 0: none).
    """

    base_color: np.ndarray = field(default_factory=lambda: np.ones(4))
    metallic: float = 1.0
    roughness: float = 1.0
    emissive: np.ndarray = field(default_factory=lambda: np.zeros(3))
    emissive_strength: float = 1.0
    base_color_texture: TextureSlot | None = None
    metallic_roughness_texture: TextureSlot | None = None
    normal_texture: TextureSlot | None = None
    normal_scale: float = 1.0
    occlusion_texture: TextureSlot | None = None
    occlusion_strength: float = 1.0
    emissive_texture: TextureSlot | None = None
    alpha_mode: str = "OPAQUE"
    alpha_cutoff: float = 0.5
    double_sided: bool = False
    unlit: bool = False
    name: str = ""
    ior: float = 1.5
    specular: float = 1.0
    specular_color: np.ndarray = field(default_factory=lambda: np.ones(3))
    transmission: float = 0.0
    thickness: float = 0.0
    attenuation_color: np.ndarray = field(default_factory=lambda: np.ones(3))
    attenuation_distance: float = float("inf")
    clearcoat: float = 0.0
    clearcoat_roughness: float = 0.0
    sheen_color: np.ndarray = field(default_factory=lambda: np.zeros(3))
    sheen_roughness: float = 0.0
    specular_texture: TextureSlot | None = None
    specular_color_texture: TextureSlot | None = None
    transmission_texture: TextureSlot | None = None
    thickness_texture: TextureSlot | None = None
    clearcoat_texture: TextureSlot | None = None
    clearcoat_roughness_texture: TextureSlot | None = None
    clearcoat_normal_texture: TextureSlot | None = None
    clearcoat_normal_scale: float = 1.0
    sheen_color_texture: TextureSlot | None = None
    sheen_roughness_texture: TextureSlot | None = None
    iridescence: float = 0.0
    iridescence_ior: float = 1.3
    iridescence_thickness_min: float = 100.0
    iridescence_thickness_max: float = 400.0
    iridescence_texture: TextureSlot | None = None
    iridescence_thickness_texture: TextureSlot | None = None
    anisotropy: float = 0.0
    anisotropy_rotation: float = 0.0
    anisotropy_texture: TextureSlot | None = None
    diffuse_transmission: float = 0.0
    diffuse_transmission_color: np.ndarray = field(default_factory=lambda: np.ones(3))
    diffuse_transmission_texture: TextureSlot | None = None
    diffuse_transmission_color_texture: TextureSlot | None = None
    dispersion: float = 0.0

    # Not used by this model; present so that every material answers the same questions.
    shader = None
    reflectivity = 0.0
    gloss = 0.0
    mirror = False
    ka = 1.0

    def __post_init__(self):
        base = reals(self.base_color, "material base_color", most=4)
        self.base_color = as_color(base, "material base_color", channels=(4,)) \
            if base.size == 4 else np.append(as_color(base, "material base_color"), 1.0)
        self.emissive = as_color(self.emissive, "emissive")
        for key in ("metallic", "roughness", "occlusion_strength", "alpha_cutoff", "specular",
                    "transmission", "clearcoat", "clearcoat_roughness", "sheen_roughness",
                    "iridescence", "anisotropy", "diffuse_transmission"):
            v = getattr(self, key)
            if not (finite(v) and 0.0 <= v <= 1.0):
                raise InputError(f"material {key} must be a number in [0, 1], got {v!r}")
            setattr(self, key, float(v))
        c = reals(self.specular_color, "material specular_color", most=3).reshape(-1)
        if c.shape != (3,) or not np.all(np.isfinite(c)) or c.min() < 0:
            raise InputError(f"material specular_color must be 3 numbers >= 0, got "
                             f"{self.specular_color!r}")
        self.specular_color = c
        v = self.ior
        if not (finite(v) and
                (v == 0 or v >= 1)):
            raise InputError(f"material ior must be a number >= 1 (or 0: a perfect "
                             f"reflector, as glTF allows), got {v!r}")
        self.ior = float(v)
        self.attenuation_color = as_color(self.attenuation_color, "attenuation color")
        self.sheen_color = as_color(self.sheen_color, "sheen color")
        self.diffuse_transmission_color = as_color(self.diffuse_transmission_color,
                                                   "diffuse transmission color")
        d = self.attenuation_distance
        if not (isinstance(d, numbers.Real) and not isinstance(d, bool) and d > 0):
            raise InputError(f"material attenuation_distance must be a number > 0 (inf: "
                             f"clear), got {d!r}")
        self.attenuation_distance = float(d)
        v = self.iridescence_ior
        if not (finite(v) and v >= 1):
            raise InputError(f"material iridescence_ior must be a number >= 1, got {v!r}")
        self.iridescence_ior = float(v)
        v = self.anisotropy_rotation
        if not (finite(v)):
            raise InputError(f"material anisotropy_rotation must be a number (radians), "
                             f"got {v!r}")
        self.anisotropy_rotation = float(v)
        for key in ("emissive_strength", "normal_scale", "thickness", "clearcoat_normal_scale",
                    "iridescence_thickness_min", "iridescence_thickness_max", "dispersion"):
            v = getattr(self, key)
            if not (finite(v) and v >= 0):
                raise InputError(f"material {key} must be a number >= 0, got {v!r}")
            setattr(self, key, float(v))
        if self.alpha_mode not in ALPHA_MODES:
            raise InputError(f"material alpha_mode must be one of {', '.join(ALPHA_MODES)}, "
                             f"got {self.alpha_mode!r}")
        for slot in SLOTS:
            value = getattr(self, f"{slot}_texture")
            if value is not None and not isinstance(value, TextureSlot):
                raise InputError(f"material {slot}_texture must be a TextureSlot, got "
                                 f"{type(value).__name__}")

    @property
    def dielectric_f0(self) -> np.ndarray:
        """(3,) the dielectric's reflectance at normal incidence (see the class)."""
        return np.minimum(self.ior_f0 * self.specular_color, 1.0) * self.specular

    @property
    def ior_f0(self) -> float:
        """((ior - 1) / (ior + 1))^2: normal incidence on the bare interface (1 for ior 0).
        The shaders take it and ``specular_color`` apart, as the textures multiply them
        before the clip to 1."""
        return ((self.ior - 1) / (self.ior + 1)) ** 2 if self.ior > 0 else 1.0

    @property
    def absorption(self) -> np.ndarray:
        """(3,) sigma_a per unit length inside the volume: -ln(attenuation_color) /
        attenuation_distance (0: clear)."""
        if not np.isfinite(self.attenuation_distance):
            return np.zeros(3)
        return -np.log(np.maximum(self.attenuation_color, 1e-6)) / self.attenuation_distance

    @property
    def normal_mapped(self) -> bool:
        """Whether the material needs tangent frames: a normal map (the surface's or the
        clear coat's) or an anisotropic lobe (turned from the tangent)."""
        return self.normal_texture is not None or self.clearcoat_normal_texture is not None \
            or self.anisotropy > 0

    @property
    def transparent(self) -> bool:
        """Drawn in the transparent pass (order-independent, facet.render.raster.transparency)."""
        return self.alpha_mode == "BLEND"

    @property
    def slots(self) -> dict[str, TextureSlot]:
        """The texture slots in use, by name (SLOTS order)."""
        return {s: getattr(self, f"{s}_texture") for s in SLOTS
                if getattr(self, f"{s}_texture") is not None}

    # -- the Phong stand-ins (for shading = "phong" and the ray tracer) -------------------
    @property
    def color(self) -> np.ndarray:
        """C: the base colour, linear (the renderer encodes it for non-sRGB output)."""
        return self.base_color[:3]

    @property
    def opacity(self) -> float:
        return float(self.base_color[3]) if self.alpha_mode == "BLEND" else 1.0

    @property
    def kd(self) -> float:
        return 1.0 - self.metallic  # metals have no diffuse part

    @property
    def ks(self) -> float:
        # Metals reflect their colour strongly; dielectrics about 4% at normal incidence,
        # which a Phong highlight shows brighter as the surface gets smoother.
        return float(np.clip(self.metallic + (1 - self.metallic) * 0.5 * (1 - self.roughness),
                             0.0, 1.0))

    @property
    def shininess(self) -> float:
        """n = 2 / alpha^2 - 2, alpha = roughness^2: the Blinn-Phong exponent of a GGX lobe
        of that roughness, clamped to [1, 512]."""
        alpha = max(self.roughness ** 2, 0.05)
        return float(np.clip(2.0 / alpha ** 2 - 2.0, 1.0, 512.0))

    @property
    def texture(self):
        """The base-colour image (the texture a Phong path multiplies C by)."""
        slot = self.base_color_texture
        return None if slot is None else slot.texture


def as_phong(material):
    """A Phong ``Material`` standing in for ``material`` (itself if it is one): for a
    user's own shader, which takes the Phong uniforms. Colours encoded for display, as a
    Phong material's are."""
    from ..srgb import linear_to_srgb
    from .material import Material

    if not isinstance(material, PbrMaterial):
        return material
    m = material
    return Material(color=linear_to_srgb(m.color), ka=1.0, kd=m.kd, ks=m.ks,
                    shininess=m.shininess, name=m.name, texture=m.texture, opacity=m.opacity)
