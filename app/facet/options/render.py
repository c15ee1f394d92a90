"""Every knob of a render in one typed object, parsed and merged in one place (no GL).

``RenderOptions`` is what the render passes read. ``options_for(scene, *layers)`` makes it
from layers of raw values, a later layer overriding an earlier one:

    facet's defaults  <  the front's own defaults (FRONT_DEFAULTS: a dataset's image size
                         and channels, a window's size)
                      <  the scene's own (its background and environment, then its
                         options: a scene file's [render] table)
                      <  explicit arguments (a Renderer's own, then render()'s keywords;
                         or the command line's flags; a manifest's defaults, then a job's;
                         the viewer's keys)

That precedence is written here and nowhere else, and every front (Python keywords, scene
files, command-line flags, the viewer's keys, dataset manifests) hands its raw values to it:
each key is parsed by one function (facet.options.values), so every front accepts and
rejects the same values with the same sentence. A parsed layer (``ParsedLayer``) is never
parsed again. ``msaa=N`` is sugar for ``aa="msaa:N"`` and ``spp=N`` for
``aa="ssaa:jittered:N"``; one layer may give only one of the three. A key whose value is
None counts as not given.

MSAA above what the GL offers is clamped with a one-line warning naming the maximum
(``clamp_msaa``, applied where a context is known); every front shares that policy.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace

from ..errors import InputError
from .values import (  # noqa: F401 - the vocabularies, importable from here
    CULL,
    DEFAULT_AA,
    DEFAULT_CREASE,
    DEFAULT_OUTPUTS,
    DISTRIBUTED_AA,
    ENGINES,
    LIGHTS,
    MAX_RAY_DEPTH,
    MSAA_CHOICES,
    OUTPUTS,
    PARSERS,
    PATH_KEYS,
    PCF_CHOICES,
    SHADING,
    AntiAliasing,
    _default_aa,
    clamp_msaa,
    parse_aa,
    parse_option,
    text_value,
)

# The defaults of the fronts whose use differs from a single picture's; a scene file's
# [render] table and every explicit value override them (options_for).
FRONT_DEFAULTS = {
    "view": {"size": (1280, 720)},  # a window
    "batch": {"size": (256, 256), "outputs": ("color", "depth", "normals")},  # datasets
}
AA_KEYS = ("aa", "msaa", "spp")  # one layer gives one of them
MAX_FRAMES = 100_000  # the most frames of any sequence: turntables, shader sequences, views


@dataclass(frozen=True)
class RenderOptions:
    """How to render: every knob of a render, parsed and typed (the module docstring says
    where each value comes from: facet's defaults < a front's < the scene's < explicit
    layers). Build one with ``RenderOptions.build``; ``Renderer.render(**options)`` takes the
    same names as raw values.

    Parameters
    ----------
    size : (int, int)
        (width, height), pixels.
    background : (4,) float, optional
        RGBA in [0, 1]; None: the scene's.
    shading : str
        One of SHADING (``auto`` picks by material).
    aa : AntiAliasing
        ``none``, ``msaa:N`` or ``ssaa:PATTERN:N`` (raw: ``aa``, ``msaa=N``, ``spp=N``).
    shadows : bool, optional
        Shadow maps / shadow rays; None: the engine's default (the tracers cast them).
    pcf : int, optional
        Percentage-closer filtering radius of shadow maps, texels; None: 1.
    srgb : bool
        Colour management (linear lighting, sRGB output; facet.image.colorspace).
    float_color : bool
        Float32 linear colour out (for EXR / HDR).
    outputs : tuple of str
        Channels to return (OUTPUTS: color, depth, ids, normals, position, uv).
    camera : str, optional
        A scene camera's name.
    aperture, focus : float, optional
        A thin lens over the camera: depth of field.
    environment : Environment, optional
        Background and reflection source (default: the scene's).
    lights : str
        LIGHTS: ``auto`` (the scene's, else a rig following the camera), ``scene``,
        ``camera``.
    wireframe : bool
        Overlay the triangle edges.
    time : float
        Seconds: where the scene's animations stand, and users' shaders' ``u_time``.
    animation : str or int, optional
        Which animation plays (a name or an index; "all": every clip at once); None: the
        first of each model, as glTF viewers play it.
    variant : str, optional
        A glTF material variant's name (KHR_materials_variants).
    shutter : float
        Seconds the shutter stays open from ``time`` (motion blur); 0: a still.
    engine : str
        ENGINES: ``raster``, ``trace`` (Whitted) or ``path`` (physically based).
    max_depth : int, optional
        The Whitted tracer's recursion depth, the path tracer's bounces; None: the engine's
        (5 and 8; facet.render.capabilities).
    seed : int
        The random stream (the same seed, the same picture).
    up : (3,) float
        The world's up axis (framing, turntables).
    cull : str
        Back-face culling: ``auto`` (where it cannot change the picture), ``on``, ``off``.
    denoise : bool
        The path tracer's picture through Intel Open Image Denoise (the ``denoise`` extra).
    noise : float, optional
        Adaptive sampling (the path tracer): a pixel stops taking paths once the estimated
        relative error of its mean is below this (0.01: 1%), after 16 paths at least;
        ``spp`` bounds it (4096 when not given). facet.render.budget.
    time_limit : float, optional
        Seconds a sum of samples may take: the picture reached by then (``spp`` bounds it,
        4096 paths in the path tracer when not given).
    """

    size: tuple[int, int] = (800, 600)
    background: tuple[float, float, float, float] | None = None  # (options_for: the scene's)
    shading: str = "auto"
    aa: AntiAliasing = field(default_factory=_default_aa)
    shadows: bool | None = None  # None: the engine's default (rasterizer off, tracer on)
    pcf: int | None = None  # None: the rasterizer's 1
    srgb: bool = False
    float_color: bool = False
    outputs: tuple[str, ...] = DEFAULT_OUTPUTS
    camera: str | None = None
    aperture: float | None = None
    focus: float | None = None
    environment: object = None
    lights: str = "auto"
    wireframe: bool = False
    time: float = 0.0
    animation: str | int | None = None
    variant: str | None = None
    shutter: float = 0.0
    engine: str = "raster"
    max_depth: int | None = None  # None: the engine's (facet.render.capabilities)
    seed: int = 0
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    cull: str = "auto"
    denoise: bool = False
    noise: float | None = None
    time_limit: float | None = None

    @classmethod
    def build(cls, *layers, **options) -> RenderOptions:
        """Defaults, then each layer in order (a later one wins), then ``options``.

        Parameters
        ----------
        *layers : mapping of raw values, RenderOptions, or None
            Layers, lowest first.
        **options
            Raw values, the top layer: ``RenderOptions.build(aa="ssaa:jittered:16", shadows=True)``.

        Returns
        -------
        RenderOptions
            The options.

        Raises
        ------
        facet.InputError
            A value one option cannot take (one line naming it), an unknown name (with a
            did-you-mean).
        """
        values: dict = {}
        for layer in (*layers, options):
            values.update(parse_layer(layer))
        return cls(**values)

    def merged(self, *layers) -> RenderOptions:
        """These options with ``layers`` on top.

        Parameters
        ----------
        *layers : mapping of raw values, RenderOptions, or None
            Layers, lowest first.

        Returns
        -------
        RenderOptions
            The merged options (``self`` when there is nothing to merge).
        """
        values: dict = {}
        for layer in layers:
            values.update(parse_layer(layer))
        return replace(self, **values) if values else self

    def as_layer(self) -> dict:
        """Every value as a layer (what ``build`` takes).

        Returns
        -------
        dict
            ``{option: typed value}``.
        """
        return {f.name: getattr(self, f.name) for f in fields(self)}

    @property
    def width(self) -> int:
        return self.size[0]

    @property
    def height(self) -> int:
        return self.size[1]


class ParsedLayer(dict):
    """A layer already parsed ({field: typed value}): used as it is, not parsed again (a
    renderer's own options are resolved on every call)."""


def parse_layer(layer, base=None) -> ParsedLayer:
    """A layer's given values, parsed: {field: typed value}. ``base``: the folder of the
    file that gave the values (a scene file, a manifest), for relative file names."""
    if layer is None:
        return ParsedLayer()
    if isinstance(layer, ParsedLayer):
        return layer
    if isinstance(layer, RenderOptions):
        return ParsedLayer(layer.as_layer())
    if not isinstance(layer, dict | Mapping):  # (dict first: the ABC check is slow)
        raise InputError(f"render options must be a mapping or RenderOptions, got "
                         f"{type(layer).__name__}")
    given = {k: v for k, v in layer.items() if v is not None}
    check_one_aa(given)
    return ParsedLayer({("aa" if key in AA_KEYS else key): parse_option(key, value, base)
                        for key, value in given.items()})


def check_one_aa(keys) -> None:
    """InputError when ``keys`` (of one layer) hold more than one of aa, msaa and spp."""
    sugar = [k for k in AA_KEYS if k in keys]
    if len(sugar) > 1:
        raise InputError(f"give one of aa, msaa and spp, not {' and '.join(sugar)} (msaa=N "
                         "means aa='msaa:N', spp=N means aa='ssaa:jittered:N')")


def merge_raw(*layers) -> dict:
    """Raw layers folded into one, a later value replacing an earlier (one of aa, msaa and
    spp in a later layer replaces any of them in an earlier one)."""
    out: dict = {}
    for layer in layers:
        if any(k in layer for k in AA_KEYS):
            out = {k: v for k, v in out.items() if k not in AA_KEYS}
        out.update(layer)
    return out


def text_layer(values: dict) -> dict:
    """A raw layer from a command line's text values (facet.options.values.text_value:
    numbers where a key takes them, nothing checked)."""
    return {key: text_value(key, value) if isinstance(value, str) else value
            for key, value in values.items()}


def options_for(scene, *explicit, front: str | None = None) -> RenderOptions:
    """The options of a render of ``scene`` (the module docstring's precedence): facet's
    defaults < ``FRONT_DEFAULTS[front]`` < the scene's own (background, environment, then
    ``scene.options``; then the image size of the intrinsics camera it renders through)
    < each ``explicit`` layer in order. The one place where the layers meet."""
    own = ParsedLayer(background=tuple(float(c) for c in scene.background))
    # The scene's environment is parsed as the option is (an attribute a user set: an
    # Environment, 'sky', a file's name, {color = ...}; anything else is one line).
    environment = None if scene.environment is None else \
        parse_layer({"environment": scene.environment})
    front_layer = FRONT_DEFAULTS[front] if front else None
    opts = RenderOptions.build(front_layer, own, environment, scene.options, *explicit)
    sized = any(isinstance(layer, RenderOptions) or
                (isinstance(layer, dict | Mapping) and layer.get("size") is not None)
                for layer in explicit)
    camera = scene.camera(opts.camera) if scene.cameras and not sized else None
    if camera is not None and camera.intrinsics is not None:
        opts = replace(opts, size=(camera.intrinsics.width, camera.intrinsics.height))
    return opts
