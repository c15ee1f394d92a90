"""What a Shadertoy-style program is made of, without GL: passes (Image, Buffer A-D, Cube
A), each with its own source and its own four channels, every channel with Shadertoy's
sampler settings; read from keyword arguments, the command line's compact form, a small
TOML project file, or a Shadertoy JSON export (the format its API returns).

Channel sources: ``buffer-a`` ... ``buffer-d``, ``cube-a`` (the Cube A pass), ``keyboard``,
an image file, a cube map (a folder of six faces ``px nx py ny pz nz`` or an image of an
environment, with ``cube:`` in front), ``noise`` (facet's stand-in for Shadertoy's "RGBA
Noise Medium": 256 x 256 random bytes, the same every run), or ``none`` (black). A channel
nobody gave that a shader reads gets the noise, with one warning line (most pasted shaders
that read an unset iChannel want a noise texture; ``none`` asks for black). Sampler
settings follow Shadertoy's defaults: images and noise mipmapped, repeating and flipped so
that v = 0 is their bottom row; buffers linear and clamped; cube maps linear.
"""

from __future__ import annotations

import difflib
import json
import re
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..errors import FacetWarning, InputError

PASSES = ("a", "b", "c", "d", "cube", "image")  # the order they run in each frame
BUFFERS = PASSES[:4]  # Buffer A-D
PASS_NAMES = {"a": "Buffer A", "b": "Buffer B", "c": "Buffer C", "d": "Buffer D",
              "cube": "Cube A", "image": "Image"}
BUFFER_SOURCES = {"buffer-a": "a", "buffer-b": "b", "buffer-c": "c", "buffer-d": "d",
                  "cube-a": "cube"}
FILTERS = ("nearest", "linear", "mipmap")
WRAPS = ("clamp", "repeat")
UNSUPPORTED = ("music", "musicstream", "mic", "webcam", "video", "volume")


@dataclass(frozen=True)
class Channel:
    """One iChannel input. ``kind``: "buffer" (``source`` a pass key), "texture" or "cube"
    (``source`` a path), "keyboard", or "none" (black)."""

    kind: str = "none"
    source: object = None
    filter: str = "linear"
    wrap: str = "clamp"
    vflip: bool = True

    @property
    def is_cube(self) -> bool:
        return self.kind == "cube" or (self.kind == "buffer" and self.source == "cube")


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
    p = Path(text).expanduser()
    return p if p.is_absolute() or base is None else base / p


def parse_compact(text: str, where: str) -> tuple[str | None, int, Channel]:
    """The command line's compact form ``[PASS:]N=SOURCE[:OPTION...]`` (OPTION: nearest,
    linear, mipmap, clamp, repeat, vflip, noflip), e.g. ``a:0=buffer-a:nearest`` or
    ``image:1=cube:sky/:mipmap`` -> (pass key or None for every pass, channel, Channel)."""
    head, eq, rest = text.partition("=")
    target, _, number = head.rpartition(":")
    if not eq or not number.isdigit() or int(number) > 3:
        raise InputError(f"{where} {text!r}: expected [PASS:]N=SOURCE[:OPTIONS] with N in "
                         "0-3, e.g. a:0=buffer-a or image:1=wood.png:nearest:clamp")
    key = pass_key(target, where) if target else None
    parts = rest.split(":")
    source = parts.pop(0)
    if source == "cube" and parts:  # cube:PATH keeps its own colon
        source = f"cube:{parts.pop(0)}"
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
    from ..guard import parse_toml, regular_file

    path = regular_file(path, "project file")
    try:
        data = parse_toml(path.read_text(encoding="utf-8"), path.name)
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
        for n, spec in (t.get("channels") or {}).items():
            at = f"{where} channels.{n}"
            if not (str(n).isdigit() and int(n) <= 3):
                raise InputError(f"{at}: channels are 0 to 3")
            if isinstance(spec, dict):
                _known(spec, CHANNEL_KEYS, at)
                settings = {k: v for k, v in spec.items() if k != "source"}
                chans[int(n)] = channel(spec.get("source", "none"), at, base, **settings)
            else:
                chans[int(n)] = channel(spec, at, base)
        passes[key] = Pass(key, _resolve(t["shader"], base), channels=chans)
    common = _resolve(data["common"], base) if "common" in data else None
    return Project(passes, common, origin=path)


def _known(table: dict, keys, where: str) -> None:
    for k in table:
        if k not in keys:
            close = difflib.get_close_matches(str(k), keys, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise InputError(f"{where}: unknown key {k!r}{hint}; expected {', '.join(keys)}")


# -- Shadertoy JSON exports ------------------------------------------------------------------
# Shadertoy's fixed ids of the buffer outputs, for exports whose inputs name only the id.
OUTPUT_IDS = {"4dXGR8": "a", "XsXGR8": "b", "4sXGR8": "c", "XdfGR8": "d", "4dX3Rr": "cube",
              "257": "a", "258": "b", "259": "c", "260": "d", "41": "cube"}


def load_shadertoy_json(path, media: Path | None = None) -> Project:
    """A Shadertoy export (``{"Shader": {...}}``, a bare shader object, or a list of them):
    its passes' code, inputs (channel, type, sampler) and outputs. Textures are looked up
    by file name in ``media`` (default: beside the export); a missing one is an error
    naming it; audio and video inputs are black, with one warning line."""
    from ..guard import regular_file

    path = regular_file(path, "Shadertoy export")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except RecursionError:
        raise InputError(f"{path.name}: nested too deeply to read") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"{path.name}: not a Shadertoy JSON export ({exc})") from None
    if isinstance(data, list):
        data = data[0] if data else {}
    shader = data.get("Shader", data) if isinstance(data, dict) else {}
    renderpasses = shader.get("renderpass") if isinstance(shader, dict) else None
    if not isinstance(renderpasses, list) or not renderpasses:
        raise InputError(f"{path.name}: not a Shadertoy JSON export (no \"renderpass\" "
                         "list)")
    media = Path(media) if media else path.parent
    # Which pass writes which output id.
    writers = {}
    for rp in renderpasses:
        key = _json_pass_key(rp, path.name)
        for out in rp.get("outputs") or []:
            if key not in ("common", "sound"):
                writers[str(out.get("id"))] = key
    passes, common_code, skipped = {}, None, set()
    for rp in renderpasses:
        key = _json_pass_key(rp, path.name)
        code = rp.get("code", "")
        if key == "common":
            common_code = code
            continue
        if key == "sound":
            skipped.add("the Sound pass")
            continue
        where = f"{path.name}: {PASS_NAMES[key]}"
        chans = {}
        for inp in rp.get("inputs") or []:
            n = int(inp.get("channel", 0))
            ctype = inp.get("ctype") or inp.get("type") or ""
            sampler = inp.get("sampler") or {}
            settings = {k: sampler[k] for k in ("filter", "wrap") if k in sampler}
            if "vflip" in sampler:
                settings["vflip"] = str(sampler["vflip"]).lower() == "true"
            src = str(inp.get("src") or inp.get("filepath") or "")
            if ctype == "buffer":
                owner = writers.get(str(inp.get("id"))) or OUTPUT_IDS.get(str(inp.get("id")))
                if owner is None and "buffer0" in src:
                    owner = "abcd"[int(src.split("buffer0")[1][0])]
                if owner is None:
                    raise InputError(f"{where}: channel {n} reads a buffer the export does "
                                     "not define")
                chans[n] = channel("cube-a" if owner == "cube" else f"buffer-{owner}",
                                   where, **settings)
            elif ctype == "cubemap" and ("cubemap0" in src or
                                         OUTPUT_IDS.get(str(inp.get("id"))) == "cube"):
                chans[n] = channel("cube-a", where, **settings)
            elif ctype in ("texture", "cubemap"):
                file = _media(media, src, where, n)
                chans[n] = channel(("cube:" if ctype == "cubemap" else "") + str(file),
                                   where, **settings)
            elif ctype == "keyboard":
                chans[n] = channel("keyboard", where)
            elif ctype in UNSUPPORTED:
                skipped.add(f"{ctype} inputs ({PASS_NAMES[key]} channel {n}: black)")
                chans[n] = Channel()
            else:
                raise InputError(f"{where}: channel {n} has an input type {ctype!r} facet "
                                 "does not know")
        passes[key] = Pass(key, path.with_name(f"{path.name}[{PASS_NAMES[key]}]"), code,
                           chans)
    if "image" not in passes:
        raise InputError(f"{path.name}: the export has no Image pass")
    for what in sorted(skipped):
        warnings.warn(f"{path.name}: not supported, left out: {what}", FacetWarning,
                      stacklevel=2)
    common = path.with_name(f"{path.name}[Common]") if common_code is not None else None
    return Project(passes, common, common_code, origin=path, media=media)


def _json_pass_key(rp: dict, where: str) -> str:
    """A pass's key by its type, then (buffers) by the fixed id of its output, then by
    its name ("Buffer A", "Buf A", ...): exports carry all kinds of names."""
    kind = str(rp.get("type", "")).lower()
    if kind in ("common", "sound"):
        return kind
    if kind == "image":
        return "image"
    if kind == "cubemap":
        return "cube"
    for out in rp.get("outputs") or []:
        key = OUTPUT_IDS.get(str(out.get("id"))) if isinstance(out, dict) else None
        if key is not None and key != "cube":
            return key
    return pass_key(rp.get("name", ""), where)


def _media(media: Path, src: str, where: str, n: int) -> Path:
    """A texture of the export, by file name in ``media`` (a cube map's six faces are
    ``name``, ``name_1`` ... ``name_5`` on Shadertoy: a folder named after the file, or the
    file itself, are accepted)."""
    name = Path(src).name
    for candidate in (media / name, media / Path(name).stem):
        if candidate.exists():
            return candidate
    raise InputError(f"{where}: channel {n} needs the media file {name!r}, which is not in "
                     f"{media} (download it there, or give --media DIR)")
