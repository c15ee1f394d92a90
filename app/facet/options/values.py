"""Every render option's values: the vocabularies, and one parser per key (``PARSERS``)
that turns a raw value (a Python keyword's, a scene file's, a manifest's, or a command-line
flag's text through ``text_value``) into its typed value, or raises one InputError whose
sentence is the same whichever front the value came from (no GL).

facet.options.render builds ``RenderOptions`` from layers of these values.
"""

from __future__ import annotations

import difflib
import math
import numbers
import warnings
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from ..errors import FacetWarning, InputError
from ..scene.constants import DEFAULT_CREASE  # noqa: F401 - the crease option's default

# This module imports numpy and the sampling patterns only inside its parsers: the command
# line builds its --help from the vocabularies below without loading either.

# The channels a render can return (Frame attributes: color, depth, object_ids, ...).
OUTPUTS = ("color", "depth", "ids", "normals", "position", "uv", "spp")
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
ENGINES = ("raster", "trace", "path")  # rasterizer, ray tracer, path tracer (facet.render.engine)
CULL = ("auto", "on", "off")  # back-face culling (facet.render.raster.culling)
DEFAULT_AA = "msaa:4"

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
            if n > MAX_SAMPLES:  # an error, not a silent substitution
                raise InputError(f"aa {text!r}: {n:,} samples per pixel; facet draws at "
                                 f"most {MAX_SAMPLES:,} (for more, average renders of "
                                 "different --seed values)")
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
    if isinstance(samples, bool) or not isinstance(samples, numbers.Integral) or \
            samples not in MSAA_CHOICES:
        shown = repr(samples) if len(repr(samples)) <= 40 else repr(samples)[:37] + "..."
        raise InputError(f"{where}msaa must be one of {', '.join(map(str, MSAA_CHOICES))}, "
                         f"got {shown}")
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
        if not isinstance(value, str) or value not in choices:
            close = difflib.get_close_matches(str(value), choices, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            shown = repr(value) if len(repr(value)) <= 40 else repr(value)[:37] + "..."
            raise InputError(f"{key}: unknown {what} {shown}{hint}; choose one of "
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


def _int_text(text: str):
    """A command line's integer as an int; other text stays text (its parser says why)."""
    try:
        return int(text.strip())
    except ValueError:
        return text


def _float_text(text: str):
    try:
        return float(text.strip())
    except ValueError:
        return text


def _number(minimum=None, above=None):
    def parse(value, key):
        problem = number_problem(value, minimum, above)
        if problem:
            raise InputError(f"{key}: {problem}, got {value!r}")
        return float(value)
    parse.from_text = _float_text
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

    given = value
    if isinstance(value, str):  # ASCII digits only: int() would read "١٢" and " 12 "
        parts = value.lower().split("x")
        value = tuple(int(p) for p in parts) if all(
            p.isascii() and p.isdigit() for p in parts) else ()
    values = tuple(value) if isinstance(value, (tuple, list, np.ndarray)) else ()
    if len(values) != 2 or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool)
                                   for v in values):
        raise InputError(f"{key}: expected two integers [width, height] in pixels "
                         f"(WIDTHxHEIGHT), got {given!r}")
    if min(values) < 1:
        raise InputError(f"{key}: width and height must be >= 1, got {values[0]}x{values[1]}")
    from ..budgets import check_pixels

    check_pixels(int(values[0]), int(values[1]), key)
    return int(values[0]), int(values[1])


def _background(value, key):
    import numpy as np

    if isinstance(value, str):  # "R,G,B[,A]" or a grey level, as a command line gives it
        value = [_float_text(t) for t in value.split(",")]
    given = value
    if np.size(value) > 4 if hasattr(value, "dtype") else \
            isinstance(value, (list, tuple)) and len(value) > 4:
        value = [np.nan]  # (a broadcast view of trillions is not copied)
    a = np.asarray(value, dtype=object).reshape(-1)
    try:
        a = a.astype(np.float64)
    except (TypeError, ValueError):
        a = np.array([np.nan])
    if a.size == 1:
        a = np.repeat(a, 3)
    if a.size not in (3, 4) or not np.all(np.isfinite(a)) or a.min() < 0 or a.max() > 1:
        shown = f"shape {np.shape(given)}" if hasattr(given, "dtype") else repr(given)
        raise InputError(f"{key}: expected a grey level or 3 or 4 floats in [0, 1] (alpha 0: "
                         f"transparent), got {shown[:60]}")
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
    parse.from_text = _int_text
    return parse


@dataclass(frozen=True)
class EnvironmentFile:
    """An environment named by its file: an image or a folder of cube faces, ``spec``
    relative to ``base`` (the folder of the file that names it). Options read no file: it
    is read where a scene or a render takes it (facet.formats.environment_files.resolve)."""

    spec: str
    base: Path | None = None


def _environment(value, key, base=None):
    """'sky', an image or a folder of cube faces (a relative path: from ``base``, the
    folder of the file that names it: an ``EnvironmentFile``), or ``{color = [r, g, b]}``:
    a constant radiance."""
    from ..scene.environment import Environment

    if isinstance(value, Environment):
        return value
    if isinstance(value, dict):
        if set(value) != {"color"}:
            raise InputError(f"{key}: a constant environment is {{color = [r, g, b]}}, got "
                             f"the keys {', '.join(map(str, value)) or 'none'}")
        return Environment.constant(value["color"])
    if not isinstance(value, str):
        raise InputError(f"{key}: expected 'sky', an image, a folder of cube faces or "
                         f"{{color = [r, g, b]}}, got {value!r}")
    if value == "sky":
        return Environment.sky()
    return EnvironmentFile(value, None if base is None else Path(base))


def _msaa(value, key):
    return msaa_mode(value)


def _spp(value, key):
    try:
        return spp_mode(value)
    except InputError as exc:
        raise InputError(f"{key}: {exc}") from None


_msaa.from_text = _spp.from_text = _int_text


def _text(value, key):
    if not isinstance(value, str) or not value:
        raise InputError(f"{key}: expected a name, got {value!r}")
    return value


def _animation(value, key):
    """An animation's name, or its index in the file (0, 1, ...)."""
    if isinstance(value, bool) or not isinstance(value, (int, str)) or value == "" or (
            isinstance(value, int) and value < 0):
        raise InputError(f"{key}: expected an animation's name or its index (0, 1, ...), "
                         f"got {value!r}")
    return value


PARSERS = {
    "size": _size,
    "background": _background,
    "shading": _choice(SHADING, "shading model"),
    "aa": lambda v, key: parse_aa(v),
    "msaa": _msaa,
    "spp": _spp,
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
    "time": _number(minimum=0),
    "animation": _animation,
    "variant": _text,
    "shutter": _number(minimum=0),
    "engine": _choice(ENGINES, "engine"),
    "max_depth": _integer(minimum=0, maximum=MAX_RAY_DEPTH),
    "seed": _integer(minimum=0, maximum=2 ** 31 - 1),
    "up": _up,
    "cull": _choice(CULL, "culling mode"),
    "denoise": _bool,
    "noise": _number(above=0),
    "time_limit": _number(above=0),
}


PATH_KEYS = ("environment",)  # values that may name a file, relative to the naming file


def check_key(key: str) -> None:
    """InputError, with a did-you-mean, unless ``key`` is a render option."""
    if key not in PARSERS:
        close = difflib.get_close_matches(key, list(PARSERS), n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise InputError(f"unknown render option {key!r}{hint} (options: "
                         f"{', '.join(PARSERS)})")


def parse_option(key: str, value, base=None):
    """The typed value of option ``key`` (``msaa`` and ``spp`` give an ``aa``); InputError
    otherwise. ``base``: the folder relative file names are read from (a scene file's or
    a manifest's; default the working folder)."""
    check_key(key)
    if key in PATH_KEYS:
        return PARSERS[key](value, key, base)
    return PARSERS[key](value, key)


def text_value(key: str, text: str):
    """The raw value of option ``key`` as a command line gives it (text): a number where
    the key takes one, else the text itself. Nothing is checked here: the key's parser
    checks every front's values alike, with one sentence."""
    check_key(key)
    from_text = getattr(PARSERS[key], "from_text", None)
    return from_text(text) if from_text is not None and isinstance(text, str) else text

