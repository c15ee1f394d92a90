"""Every knob of a render in one typed object, parsed and merged in one place (no GL).

``RenderOptions`` is what the render passes read. ``RenderOptions.build(*layers)`` makes it
from layers of raw values, a later layer overriding an earlier one:

    facet's defaults  <  the scene file's [render] table (``Scene.options``)
                      <  explicit arguments (a Renderer's own, then render()'s keywords;
                         or the command line's flags)

That precedence is written here and nowhere else. Each key is parsed by one function
(``parse_option``), so a scene file, a CLI flag and a Python keyword accept and reject the
same values with the same message. ``msaa=N`` is sugar for ``aa="msaa:N"``; one layer may
not give both. A key whose value is None counts as not given.

MSAA above what the GL offers is clamped with a one-line warning naming the maximum
(``clamp_msaa``, applied where a context is known); every front shares that policy.
"""

from __future__ import annotations

import difflib
import math
import numbers
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from functools import lru_cache

from ..errors import FacetWarning, InputError

# This module imports numpy and the sampling patterns only inside its parsers: the command
# line builds its --help from the vocabularies below without loading either.

# The channels a render can return (Frame attributes: color, depth, object_ids, ...).
OUTPUTS = ("color", "depth", "ids", "normals", "position", "uv")
DEFAULT_OUTPUTS = ("color", "depth", "ids")
# Shading models (facet.render.shading maps each to its GLSL program).
# "auto": glTF's metallic-roughness materials (PbrMaterial) by "pbr", the others by "phong".
SHADING = ("auto", "phong", "pbr", "blinn", "gouraud", "flat", "unlit", "normals")
MSAA_CHOICES = (0, 2, 4, 8)
PCF_CHOICES = (0, 1, 2)  # shadow filter kernel radius: one tap, 3 x 3, 5 x 5
# Which lights shine: "auto" the scene's own, or the default key + fill rig following the
# camera when it has none; "scene" only its own (none: only ambient); "camera" the rig even
# when the scene has lights.
LIGHTS = ("auto", "scene", "camera")
ENGINES = ("raster", "trace")  # the rasterizer, the ray tracer (facet.render.trace)
CULL = ("auto", "on", "off")  # back-face culling (facet.render.culling)
DEFAULT_MAX_DEPTH = 5  # reflection/refraction bounces of the ray tracer
DEFAULT_AA = "msaa:4"
# Files without normals: vertices split where faces meet at more than this many degrees
# (facet.scene.normals; 180: all smooth).
DEFAULT_CREASE = 60.0
# Depth of field, motion blur, area-light shadows and gloss are sums over samples: a render
# with any of them supersamples with this unless its aa already supersamples.
DISTRIBUTED_AA = "ssaa:jittered:16"
MAX_RAY_DEPTH = 16


@dataclass(frozen=True)
class AntiAliasing:
    """``none``, ``msaa:N`` (the GPU's multisampling) or ``ssaa:PATTERN:N`` (supersampling by
    accumulation over a pattern of facet.geometry.sampling)."""

    kind: str  # "none", "msaa", "ssaa"
    samples: int = 1
    pattern: str = ""

    @property
    def msaa(self) -> int:
        """Multisample count for the targets (0 unless kind is msaa)."""
        return self.samples if self.kind == "msaa" else 0

    @property
    def supersampled(self) -> bool:
        return self.kind == "ssaa"

    def __str__(self) -> str:
        return {"none": "none", "msaa": f"msaa:{self.samples}"}.get(
            self.kind, f"ssaa:{self.pattern}:{self.samples}")


def parse_aa(text) -> AntiAliasing:
    """``none``, ``msaa:4``, ``ssaa:jittered:16`` or ``jittered:16`` (an AntiAliasing passes)."""
    from ..geometry.sampling import MAX_SAMPLES, PATTERNS, pattern

    if isinstance(text, AntiAliasing):
        return text
    parts = str(text).strip().lower().split(":")
    try:
        if parts == ["none"]:
            return AntiAliasing("none")
        if parts[0] == "msaa" and len(parts) == 2:
            return msaa_mode(int(parts[1]), f"aa {text!r}: ")
        if parts[0] == "ssaa":
            parts = parts[1:]
        if len(parts) == 2 and parts[0] in PATTERNS:
            n = int(parts[1])
            if n < 1:
                raise InputError(f"aa {text!r}: the sample count must be >= 1")
            if n > MAX_SAMPLES:
                warnings.warn(f"aa {text!r}: {n} samples capped to {MAX_SAMPLES}",
                              FacetWarning, stacklevel=2)
                n = MAX_SAMPLES
            pattern(parts[0], n)  # validates (a grid needs a square number)
            return AntiAliasing("ssaa", n, parts[0])
    except InputError:
        raise
    except ValueError:  # int() of something that is not a number
        pass
    raise InputError(f"aa {text!r}: expected none, msaa:N or ssaa:PATTERN:N with PATTERN one "
                     f"of {', '.join(PATTERNS)} (e.g. ssaa:jittered:16)")


def msaa_mode(samples, where: str = "") -> AntiAliasing:
    """The AntiAliasing of ``msaa=samples`` (0: none)."""
    if isinstance(samples, bool) or samples not in MSAA_CHOICES:
        raise InputError(f"{where}msaa must be one of {', '.join(map(str, MSAA_CHOICES))}, "
                         f"got {samples!r}")
    return AntiAliasing("msaa", int(samples)) if samples else AntiAliasing("none")


def spp_mode(samples) -> AntiAliasing:
    """``spp=N``: N samples per pixel over the jittered pattern (``aa="ssaa:jittered:N"``)."""
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
        raise InputError(f"spp must be an integer >= 1 (samples per pixel), got {samples!r}")
    return parse_aa(f"ssaa:jittered:{samples}")


@lru_cache(maxsize=1)
def _default_aa() -> AntiAliasing:
    """DEFAULT_AA parsed, once (frozen: shared by every RenderOptions; parsed on first use,
    which keeps numpy out of ``facet --help``)."""
    return parse_aa(DEFAULT_AA)


def clamp_msaa(aa: AntiAliasing, max_samples: int, renderer: str = "this GL") -> AntiAliasing:
    """The policy for MSAA beyond the context: clamp to its maximum, with one warning line."""
    if aa.kind != "msaa" or aa.samples <= max_samples:
        return aa
    best = max((n for n in MSAA_CHOICES if n <= max_samples), default=0)
    warnings.warn(f"msaa:{aa.samples} is more than {renderer} supports (max {max_samples} "
                  f"samples); using {msaa_mode(best)}", FacetWarning, stacklevel=3)
    return msaa_mode(best)


# -- one parser per key ----------------------------------------------------------------------
def _bool(value, key):
    if not isinstance(value, bool) and type(value).__name__ != "bool_":  # numpy's too
        raise InputError(f"{key}: expected true or false, got {value!r}")
    return bool(value)


def _choice(choices, what: str):
    def parse(value, key):
        if value not in choices:
            close = difflib.get_close_matches(str(value), choices, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise InputError(f"unknown {what} {value!r}{hint}; choose one of "
                             f"{', '.join(choices)}")
        return value
    return parse


def number_problem(value, minimum=None, above=None) -> str | None:
    """What is wrong with ``value`` as a finite number (>= ``minimum``, > ``above``), e.g.
    "expected a number >= 0"; None when it is fine. Scene files check numbers with it too."""
    ok = isinstance(value, numbers.Real) and not isinstance(value, bool) and \
        math.isfinite(value)
    if ok and minimum is not None:
        ok = value >= minimum
    if ok and above is not None:
        ok = value > above
    if ok:
        return None
    bound = f" >= {minimum:g}" if minimum is not None else \
        f" > {above:g}" if above is not None else ""
    return f"expected a number{bound}"


def _number(minimum=None, above=None):
    def parse(value, key):
        problem = number_problem(value, minimum, above)
        if problem:
            raise InputError(f"{key}: {problem}, got {value!r}")
        return float(value)
    return parse


AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def _up(value, key):
    """The world's up axis: "x", "y", "z" (or "-z"...), "X,Y,Z", or three numbers."""
    v = value
    if isinstance(v, str):
        text = v.strip().lower()
        sign = -1.0 if text.startswith("-") else 1.0
        if text.lstrip("+-") in AXES:
            return tuple(sign * c for c in AXES[text.lstrip("+-")])
        try:
            v = [float(t) for t in text.split(",")]
        except ValueError:
            v = ()
    values = list(v) if isinstance(v, (list, tuple)) else []
    if len(values) != 3 or any(number_problem(c) for c in values) or \
            not math.hypot(*values) > 0:
        raise InputError(f"{key}: expected x, y, z (or -x, -y, -z) or three numbers X,Y,Z "
                         f"not all 0, got {value!r}")
    norm = math.hypot(*values)
    return tuple(float(c) / norm for c in values)


def _size(value, key):
    import numpy as np

    if isinstance(value, str):
        parts = value.lower().split("x")
        try:
            value = tuple(int(p) for p in parts)
        except ValueError:
            value = ()
    values = tuple(value) if isinstance(value, (tuple, list, np.ndarray)) else ()
    if len(values) != 2 or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool)
                                   for v in values):
        raise InputError(f"{key}: expected two integers [width, height] in pixels "
                         f"(WIDTHxHEIGHT), got {value!r}")
    if min(values) < 1:
        raise InputError(f"{key}: width and height must be >= 1, got {values[0]}x{values[1]}")
    return int(values[0]), int(values[1])


def _background(value, key):
    import numpy as np

    a = np.asarray(value, dtype=object).reshape(-1)
    try:
        a = a.astype(np.float64)
    except (TypeError, ValueError):
        a = np.array([np.nan])
    if a.size == 1:
        a = np.repeat(a, 3)
    if a.size not in (3, 4) or not np.all(np.isfinite(a)) or a.min() < 0 or a.max() > 1:
        raise InputError(f"{key}: expected a grey level or 3 or 4 floats in [0, 1] (alpha 0: "
                         f"transparent), got {value!r}")
    return tuple(float(c) for c in (a if a.size == 4 else np.append(a, 1.0)))


def _outputs(value, key):
    names = tuple(n.strip() for n in value.split(",")) if isinstance(value, str) else \
        tuple(value) if isinstance(value, (list, tuple)) else None
    if not names or not all(isinstance(n, str) and n for n in names):
        raise InputError(f"{key}: expected a list of channels from {', '.join(OUTPUTS)}, "
                         f"got {value!r}")
    for name in names:
        _choice(OUTPUTS, "output channel")(name, key)
    return tuple(dict.fromkeys(names))  # in the order given, each once


def _integer(choices=None, minimum=None, maximum=None):
    def parse(value, key):
        import numpy as np

        if not isinstance(value, (int, np.integer)) or isinstance(value, bool):
            raise InputError(f"{key}: expected an integer, got {value!r}")
        if choices is not None and value not in choices:
            raise InputError(f"{key}: expected one of {', '.join(map(str, choices))}, "
                             f"got {value}")
        if (minimum is not None and value < minimum) or (maximum is not None and
                                                         value > maximum):
            raise InputError(f"{key}: expected an integer in [{minimum}, {maximum}], got "
                             f"{value}")
        return int(value)
    return parse


def _environment(value, key):
    from .environment import Environment, load_environment

    if isinstance(value, Environment):
        return value
    if not isinstance(value, str):
        raise InputError(f"{key}: expected 'sky', an image or a folder of cube faces, got "
                         f"{value!r}")
    return load_environment(value)


def _text(value, key):
    if not isinstance(value, str) or not value:
        raise InputError(f"{key}: expected a name, got {value!r}")
    return value


PARSERS = {
    "size": _size,
    "background": _background,
    "shading": _choice(SHADING, "shading model"),
    "aa": lambda v, key: parse_aa(v),
    "msaa": lambda v, key: msaa_mode(v),
    "spp": lambda v, key: spp_mode(v),
    "shadows": _bool,
    "pcf": _integer(choices=PCF_CHOICES),
    "srgb": _bool,
    "float_color": _bool,
    "outputs": _outputs,
    "camera": _text,
    "aperture": _number(minimum=0),
    "focus": _number(above=0),
    "environment": _environment,
    "lights": _choice(LIGHTS, "lights mode"),
    "wireframe": _bool,
    "time": _number(),
    "engine": _choice(ENGINES, "engine"),
    "max_depth": _integer(minimum=0, maximum=MAX_RAY_DEPTH),
    "up": _up,
    "cull": _choice(CULL, "culling mode"),
}


def parse_option(key: str, value):
    """The typed value of option ``key`` (``msaa`` gives an ``aa``); InputError otherwise."""
    if key not in PARSERS:
        close = difflib.get_close_matches(key, list(PARSERS), n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise InputError(f"unknown render option {key!r}{hint} (options: "
                         f"{', '.join(PARSERS)})")
    return PARSERS[key](value, key)


@dataclass(frozen=True)
class RenderOptions:
    """How to render (see the module docstring for where each value comes from).

    size : (width, height) pixels            background : RGBA or None (the scene's)
    shading : one of SHADING                 aa : AntiAliasing (none / msaa:N / ssaa:P:N)
    shadows : shadow maps / rays (None: the engine's default); pcf : PCF radius
    srgb : colour management (image.colorspace)
    float_color : float32 colour out         outputs : channels to return (OUTPUTS)
    camera : a scene camera's name or None   aperture, focus : a lens over the camera's
    environment : an Environment or None (the scene's)
    lights : LIGHTS                          wireframe : overlay the triangle edges
    time : seconds (users' shaders' u_time)  engine : "raster" or "trace"
    max_depth : the ray tracer's reflection/refraction recursion (1: the notes' one
                reflection and one transmission ray; default DEFAULT_MAX_DEPTH)
    up : the world's up axis: default cameras frame the scene and turntables orbit
         around it (CAD and scanner files are often z-up)
    cull : back-face culling: "auto" (where it cannot change the picture), "on", "off"
    """

    size: tuple[int, int] = (800, 600)
    background: tuple[float, float, float, float] | None = None
    shading: str = "auto"
    aa: AntiAliasing = field(default_factory=_default_aa)
    shadows: bool | None = None  # None: the engine's default (rasterizer off, tracer on)
    pcf: int = 1
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
    engine: str = "raster"
    max_depth: int = DEFAULT_MAX_DEPTH
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    cull: str = "auto"

    @property
    def shadows_on(self) -> bool:
        """Whether this render has shadows: as asked, else the engine's default (the ray
        tracer casts shadow rays, the rasterizer draws shadow maps only when asked)."""
        return self.shadows if self.shadows is not None else self.engine == "trace"

    @classmethod
    def build(cls, *layers) -> RenderOptions:
        """Defaults, then each layer in order (a later one wins). A layer is a mapping of
        raw values, a ``RenderOptions`` (all of its values), or None."""
        values: dict = {}
        for layer in layers:
            values.update(parse_layer(layer))
        return cls(**values)

    def merged(self, *layers) -> RenderOptions:
        """These options with ``layers`` on top."""
        values: dict = {}
        for layer in layers:
            values.update(parse_layer(layer))
        return replace(self, **values) if values else self

    def as_layer(self) -> dict:
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


def parse_layer(layer) -> ParsedLayer:
    """A layer's given values, parsed: {field: typed value}."""
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
    sugar = [k for k in ("aa", "msaa", "spp") if k in given]
    if len(sugar) > 1:
        raise InputError(f"give one of aa, msaa and spp, not {' and '.join(sugar)} (msaa=N "
                         "means aa='msaa:N', spp=N means aa='ssaa:jittered:N')")
    return ParsedLayer({("aa" if key in ("msaa", "spp") else key): parse_option(key, value)
                        for key, value in given.items()})


def options_for(scene, *explicit) -> RenderOptions:
    """The options of a render of ``scene``: defaults < the scene's own (its [render] table,
    then the image size of the intrinsics camera it renders through) < each ``explicit``
    layer in order. The one place where the layers meet."""
    opts = RenderOptions.build(scene.options, *explicit)
    sized = any(isinstance(layer, RenderOptions) or
                (isinstance(layer, dict | Mapping) and layer.get("size") is not None)
                for layer in explicit)
    camera = scene.camera(opts.camera) if scene.cameras and not sized else None
    if camera is not None and camera.intrinsics is not None:
        opts = replace(opts, size=(camera.intrinsics.width, camera.intrinsics.height))
    return opts
