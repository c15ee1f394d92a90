"""What a Shadertoy-style program is made of, without GL: passes (Image, Buffer A-D, Cube
A), each with its own source and its own four channels, every channel with Shadertoy's
sampler settings; read from keyword arguments, the command line's compact form, a small
TOML project file, or a Shadertoy JSON export (the format its API returns).

Channel sources: ``buffer-a`` ... ``buffer-d``, ``cube-a`` (the Cube A pass), ``keyboard``,
an image file, a cube map (a folder of six faces ``px nx py ny pz nz`` or an image of an
environment, with ``cube:`` in front), a volume (a Shadertoy ``.bin`` file with
``volume:`` in front, or ``grey-noise3d`` / ``rgba-noise3d``: facet's stand-ins for its
built-in noise volumes, facet.lab.volumes), ``noise`` (facet's stand-in for Shadertoy's
"RGBA Noise Medium": 256 x 256 random bytes, the same every run), or ``none`` (black). A channel
nobody gave that a shader reads gets the noise, with one warning line (most pasted shaders
that read an unset iChannel want a noise texture; ``none`` asks for black). Sampler
settings follow Shadertoy's defaults: images and noise mipmapped, repeating and flipped so
that v = 0 is their bottom row; buffers linear and clamped; cube maps linear; volumes
mipmapped and repeating.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..errors import InputError

PASSES = ("a", "b", "c", "d", "cube", "image")  # the order they run in each frame
BUFFERS = PASSES[:4]  # Buffer A-D
PASS_NAMES = {"a": "Buffer A", "b": "Buffer B", "c": "Buffer C", "d": "Buffer D",
              "cube": "Cube A", "image": "Image"}
BUFFER_SOURCES = {"buffer-a": "a", "buffer-b": "b", "buffer-c": "c", "buffer-d": "d",
                  "cube-a": "cube"}
FILTERS = ("nearest", "linear", "mipmap")
WRAPS = ("clamp", "repeat")
UNSUPPORTED = ("music", "musicstream", "mic", "webcam", "video")


@dataclass(frozen=True)
class Channel:
    """One iChannel input. ``kind``: "buffer" (``source`` a pass key), "texture" or "cube"
    (``source`` a path), "volume" (a path, or "grey" / "rgba" for the noise volumes),
    "keyboard", "noise", "black-cube" or "none" (black)."""

    kind: str = "none"
    source: object = None
    filter: str = "linear"
    wrap: str = "clamp"
    vflip: bool = True

    @property
    def is_cube(self) -> bool:
        return self.kind in ("cube", "black-cube") or \
            (self.kind == "buffer" and self.source == "cube")

    @property
    def sampler_type(self) -> str:
        """The GLSL type the pass samples it through."""
        if self.is_cube:
            return "samplerCube"
        return "sampler3D" if self.kind == "volume" else "sampler2D"


NOISE = Channel("noise", None, "mipmap", "repeat", True)  # also what an unset channel reads


@dataclass
class Pass:
    """One pass: ``key`` in PASSES, its source (``path`` on disk, or ``code`` text named
    ``path`` in messages), and its channels 0-3; ``defines`` it is compiled with and
    ``samplers`` ({uniform name: Channel}) it reads by name (glslViewer's buffers,
    facet.lab.glslviewer); ``label``: its name in messages, if not Shadertoy's."""

    key: str
    path: Path
    code: str | None = None
    channels: dict[int, Channel] = field(default_factory=dict)
    defines: dict = field(default_factory=dict)
    samplers: dict[str, Channel] = field(default_factory=dict)
    label: str | None = None

    @property
    def name(self) -> str:
        return self.label or PASS_NAMES[self.key]

    def inputs(self) -> dict:
        """Every input it reads: {channel number or sampler name: Channel}."""
        return {**self.channels, **self.samplers}


@dataclass
class Project:
    """The passes (by key), the common code, and where the project came from (watched)."""

    passes: dict[str, Pass]
    common: Path | None = None
    common_code: str | None = None
    origin: Path | None = None  # a TOML project or a JSON export
    media: Path | None = None  # where a JSON export's textures are (read again with it)

    def ordered(self) -> list[Pass]:
        return [self.passes[k] for k in PASSES if k in self.passes]


def channel(spec, where: str, base: Path | None = None, **settings) -> Channel:
    """A Channel from a source text (``buffer-a``, ``cube:sky/``, ``keyboard``, an image
    path), with Shadertoy's default sampler for its kind, then ``settings`` over it."""
    if isinstance(spec, Channel):
        return replace(spec, **settings)
    text = str(spec).strip()
    if text in BUFFER_SOURCES:
        ch = Channel("buffer", BUFFER_SOURCES[text], "linear", "clamp", True)
    elif text == "keyboard":
        ch = Channel("keyboard", None, "nearest", "clamp", False)
    elif text in ("", "none", "black"):
        ch = Channel()
    elif text == "noise":
        ch = NOISE
    elif text.startswith("cube:"):
        ch = Channel("cube", _resolve(text[5:], base), "linear", "clamp", False)
    elif text in ("grey-noise3d", "rgba-noise3d", "noise3d"):
        ch = Channel("volume", "grey" if text.startswith("grey") else "rgba", "mipmap",
                     "repeat", False)
    elif text.startswith("volume:"):
        ch = Channel("volume", _resolve(text[7:], base), "mipmap", "repeat", False)
    else:
        from ..scene.texture import Texture

        ch = Channel("texture", spec if isinstance(spec, Texture) else _resolve(text, base),
                     "mipmap", "repeat", True)
    for key, value in settings.items():
        allowed = {"filter": FILTERS, "wrap": WRAPS}.get(key)
        if allowed is not None and value not in allowed:
            raise InputError(f"{where}: {key} must be one of {', '.join(allowed)}, got "
                             f"{value!r}")
    return replace(ch, **settings)


def _resolve(text: str, base: Path | None) -> Path:
    try:
        p = Path(text).expanduser()
    except RuntimeError:  # ~name of a user this machine does not have: the path as given
        p = Path(text)
    return p if p.is_absolute() or base is None else base / p


def parse_compact(text: str, where: str) -> tuple[str | None, int, Channel]:
    """The command line's compact form ``[PASS:]N=SOURCE[:OPTION...]`` (OPTION: nearest,
    linear, mipmap, clamp, repeat, vflip, noflip), e.g. ``a:0=buffer-a:nearest`` or
    ``image:1=cube:sky/:mipmap`` -> (pass key or None for every pass, channel, Channel)."""
    head, eq, rest = text.partition("=")
    target, _, number = head.rpartition(":")
    if not eq or not re.fullmatch(r"[0-3]", number):
        raise InputError(f"{where} {text!r}: expected [PASS:]N=SOURCE[:OPTIONS] with N in "
                         "0-3, e.g. a:0=buffer-a or image:1=wood.png:nearest:clamp")
    key = pass_key(target, where) if target else None
    parts = rest.split(":")
    source = parts.pop(0)
    if source in ("cube", "volume") and parts:  # cube:PATH keeps its own colon
        source = f"{source}:{parts.pop(0)}"
    settings = {}
    for opt in parts:
        if opt in FILTERS:
            settings["filter"] = opt
        elif opt in WRAPS:
            settings["wrap"] = opt
        elif opt in ("vflip", "noflip"):
            settings["vflip"] = opt == "vflip"
        else:
            raise InputError(f"{where} {text!r}: unknown option {opt!r} (filters "
                             f"{', '.join(FILTERS)}; wraps {', '.join(WRAPS)}; vflip, noflip)")
    return key, int(number), channel(source, where, **settings)


def pass_key(name: str, where: str) -> str:
    """``image``, ``a``/``buffer-a``/``Buffer A``/``Buf A``, ``cube``/``cube-a``/``Cube A``
    -> key."""
    text = str(name).strip().lower().replace(" ", "-")
    key = {"image": "image", "cube": "cube", "cube-a": "cube", "cubemap": "cube"}.get(text)
    letter = re.sub(r"^(buffer|buf)-?", "", text)
    if key is None and letter in ("a", "b", "c", "d"):
        key = letter
    if key is None:
        raise InputError(f"{where}: unknown pass {name!r}; passes are image, buffer-a ... "
                         "buffer-d and cube-a")
    return key


# -- TOML project files ----------------------------------------------------------------------
PROJECT_KEYS = ("common", "image", "buffer-a", "buffer-b", "buffer-c", "buffer-d", "cube-a")
PASS_KEYS = ("shader", "channels")
CHANNEL_KEYS = ("source", "filter", "wrap", "vflip")


def load_project(path) -> Project:
    """A TOML project::

        common = "common.glsl"
        [buffer-a]
        shader = "a.glsl"
        channels = { 0 = "buffer-a" }
        [image]
        shader = "image.glsl"
        channels = { 0 = "buffer-a", 1 = { source = "wood.png", filter = "nearest" } }
    """
    from ..guard import parse_toml, read_text, regular_file

    path = regular_file(path, "project file")
    try:
        data = parse_toml(read_text(path, "project file"), path.name)
    except UnicodeDecodeError:
        raise InputError(f"{path.name}: not a text file (TOML must be UTF-8)") from None
    base = path.parent
    _known(data, PROJECT_KEYS, path.name)
    if "image" not in data:
        raise InputError(f"{path.name}: needs an [image] table with shader = \"FILE\"")
    passes = {}
    for name in PROJECT_KEYS[1:]:
        if name not in data:
            continue
        t, where = data[name], f"{path.name}: [{name}]"
        if not isinstance(t, dict) or "shader" not in t:
            raise InputError(f"{where}: needs shader = \"FILE\"")
        _known(t, PASS_KEYS, where)
        key = pass_key(name, where)
        chans = {}
        table = t.get("channels", {})
        if not isinstance(table, dict):
            raise InputError(f"{where} channels: expected a table like {{ 0 = \"buffer-a\" }}, "
                             f"got {table!r}")
        for n, spec in table.items():
            at = f"{where} channels.{n}"
            if not re.fullmatch(r"[0-3]", str(n)):
                raise InputError(f"{at}: channels are 0 to 3")
            if isinstance(spec, dict):
                _known(spec, CHANNEL_KEYS, at)
                settings = {k: v for k, v in spec.items() if k != "source"}
                for k in ("filter", "wrap"):
                    if k in settings:
                        text(settings[k], f"{at}.{k}")
                if "vflip" in settings and not isinstance(settings["vflip"], bool):
                    raise InputError(f"{at}.vflip: expected true or false, got "
                                     f"{settings['vflip']!r}")
                source = text(spec.get("source", "none"), f"{at}.source")
                chans[int(n)] = channel(source, at, base, **settings)
            else:
                chans[int(n)] = channel(text(spec, at), at, base)
        shader = text(t["shader"], f"{where} shader")
        passes[key] = Pass(key, _resolve(shader, base), channels=chans)
    common = _resolve(text(data["common"], f"{path.name}: common"), base) \
        if "common" in data else None
    return Project(passes, common, origin=path)


def text(value, where: str) -> str:
    """``value`` when it is a string; otherwise one line naming the key and the value."""
    if not isinstance(value, str):
        raise InputError(f"{where}: expected a string, got {value!r}")
    if "\0" in value:
        raise InputError(f"{where}: contains a NUL byte")
    return value


def _known(table: dict, keys, where: str) -> None:
    for k in table:
        if k not in keys:
            close = difflib.get_close_matches(str(k), keys, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise InputError(f"{where}: unknown key {k!r}{hint}; expected {', '.join(keys)}")
