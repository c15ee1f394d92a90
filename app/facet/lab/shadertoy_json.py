"""Shadertoy JSON exports (the format its API and its "export" tools write) read into a
facet.lab.project.Project, every value type-checked on the way: a wrong type anywhere
(a channel given as a string or null, a renderpass entry that is a string, code that is a
number, a buffer id nobody writes, channel 7) is one line naming the key's path, like
``export.json: renderpass[1].inputs[0].channel: expected 0 to 3, got 7``.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

from ..errors import FacetWarning, InputError
from .project import PASS_NAMES, UNSUPPORTED, Pass, Project, channel, pass_key

# Shadertoy's fixed ids of the buffer outputs, for exports whose inputs name only the id.
OUTPUT_IDS = {"4dXGR8": "a", "XsXGR8": "b", "4sXGR8": "c", "XdfGR8": "d", "4dX3Rr": "cube",
              "257": "a", "258": "b", "259": "c", "260": "d", "41": "cube"}


def load_shadertoy_json(path, media: Path | None = None) -> Project:
    """A Shadertoy export (``{"Shader": {...}}``, a bare shader object, or a list of them,
    of which the first is read): its passes' code, inputs (channel, type, sampler) and
    outputs. Textures are looked up by file name in ``media`` (default: beside the
    export); a missing one is an error naming it; audio and video inputs are black, with
    one warning line."""
    from ..guard import parse_json, read_bytes, regular_file

    path = regular_file(path, "Shadertoy export")
    try:
        data = parse_json(read_bytes(path, "Shadertoy export"), path.name)
    except InputError as exc:
        raise InputError(f"{exc}; is it a Shadertoy JSON export?") from None
    name = path.name
    if isinstance(data, list):
        if not data:
            raise InputError(f"{name}: an empty list; a Shadertoy export holds a shader")
        data, name = data[0], f"{name}: [0]"
    shader = _object(data, name)
    if "Shader" in shader:
        name = f"{name}.Shader"
        shader = _object(shader["Shader"], name)
    if "renderpass" not in shader:
        raise InputError(f"{name}: not a Shadertoy JSON export (no \"renderpass\" list)")
    passes_at = f"{name}.renderpass"
    renderpasses = [_object(rp, f"{passes_at}[{i}]")
                    for i, rp in enumerate(_list(shader["renderpass"], passes_at))]
    if not renderpasses:
        raise InputError(f"{passes_at}: an empty list; the export has no passes")
    media = Path(media) if media else path.parent
    keys = [_pass_key(rp, f"{passes_at}[{i}]") for i, rp in enumerate(renderpasses)]
    writers = {}  # which pass writes which output id
    for i, (rp, key) in enumerate(zip(renderpasses, keys, strict=True)):
        for j, out in enumerate(_list(rp.get("outputs", []), f"{passes_at}[{i}].outputs")):
            out_id = _id(_object(out, f"{passes_at}[{i}].outputs[{j}]").get("id"),
                         f"{passes_at}[{i}].outputs[{j}].id")
            if key not in ("common", "sound"):
                writers[out_id] = key
    passes, common_code, skipped = {}, None, set()
    for i, (rp, key) in enumerate(zip(renderpasses, keys, strict=True)):
        at = f"{passes_at}[{i}]"
        # (newlines as a file read as text has them: an old Mac export's bare CRs too)
        code = _text(rp.get("code", ""), f"{at}.code").replace("\r\n", "\n")
        code = code.replace("\r", "\n")
        if key == "common":
            common_code = code
            continue
        if key == "sound":
            skipped.add("not supported, left out: the Sound pass")
            continue
        where = f"{path.name}: {PASS_NAMES[key]}"
        chans = {}
        for j, inp in enumerate(_list(rp.get("inputs", []), f"{at}.inputs")):
            n, ch, what = _input(_object(inp, f"{at}.inputs[{j}]"), f"{at}.inputs[{j}]",
                                 where, writers, media)
            if n in chans:
                raise InputError(f"{at}.inputs[{j}].channel: channel {n} is given twice")
            if what is not None:
                skipped.add(what if " " in what else f"not supported, left out: {what} "
                            f"inputs ({PASS_NAMES[key]} channel {n}: black)")
            chans[n] = ch
        passes[key] = Pass(key, path.with_name(f"{path.name}[{PASS_NAMES[key]}]"), code,
                           chans)
    if "image" not in passes:
        raise InputError(f"{path.name}: the export has no Image pass")
    for what in sorted(skipped):
        warnings.warn(f"{path.name}: {what}", FacetWarning, stacklevel=2)
    common = path.with_name(f"{path.name}[Common]") if common_code is not None else None
    return Project(passes, common, common_code, origin=path, media=media)


def _input(inp: dict, at: str, where: str, writers: dict, media: Path):
    """(channel number, Channel, the unsupported kind it stands in for, or a warning
    line about it, or None)."""
    n = inp.get("channel", 0)
    if isinstance(n, str) and re.fullmatch(r"[0-3]", n):
        n = int(n)
    if isinstance(n, bool) or not isinstance(n, int) or not 0 <= n <= 3:
        raise InputError(f"{at}.channel: expected a channel number 0 to 3, got {n!r}")
    ctype = _text(inp.get("ctype") or inp.get("type") or "", f"{at}.ctype")
    sampler = _object(inp.get("sampler") or {}, f"{at}.sampler")
    settings = {k: _text(sampler[k], f"{at}.sampler.{k}") for k in ("filter", "wrap")
                if k in sampler}
    if "vflip" in sampler:
        flip = sampler["vflip"]
        if not isinstance(flip, (bool, str)):
            raise InputError(f"{at}.sampler.vflip: expected true or false, got {flip!r}")
        settings["vflip"] = str(flip).lower() == "true"
    src = _text(inp.get("src") or inp.get("filepath") or "", f"{at}.src")
    where = f"{where} channel {n}"
    if ctype == "buffer":
        in_id = _id(inp.get("id"), f"{at}.id")
        owner = writers.get(in_id) or OUTPUT_IDS.get(in_id)
        number = re.search(r"buffer0([0-3])", src)
        if owner is None and number:
            owner = "abcd"[int(number.group(1))]
        if owner is None:
            raise InputError(f"{at}: reads buffer {in_id!r}, which no pass of the export "
                             "writes")
        return n, channel("cube-a" if owner == "cube" else f"buffer-{owner}", where,
                          **settings), None
    if ctype == "cubemap" and ("cubemap0" in src or
                               OUTPUT_IDS.get(_id(inp.get("id"), f"{at}.id")) == "cube"):
        return n, channel("cube-a", where, **settings), None
    if ctype in ("texture", "cubemap"):
        file = _media(media, src, f"{at}.src: channel {n}")
        return n, channel(("cube:" if ctype == "cubemap" else "") + str(file), where,
                          **settings), None
    if ctype == "volume":
        from .volumes import export_volume

        try:
            source, stand_in = export_volume(src, media)
        except InputError as exc:
            raise InputError(f"{at}.src: channel {n}: {exc}") from None
        spec = source if stand_in else f"volume:{source}"
        if not stand_in:
            return n, channel(spec, where, **settings), None
        note = (f"{where.partition(': ')[2]} is Shadertoy's {source.split('-')[0]} noise "
                "volume: it reads facet's stand-in (the same size and channels, other "
                "random numbers)")
        return n, channel(spec, where, **settings), note
    if ctype == "keyboard":
        return n, channel("keyboard", where), None
    if ctype in UNSUPPORTED:
        return n, channel("none", where), ctype
    raise InputError(f"{at}.ctype: an input type {ctype!r} facet does not know")


def _pass_key(rp: dict, at: str) -> str:
    """A pass's key by its type, then (buffers) by the fixed id of its output, then by
    its name ("Buffer A", "Buf A", ...): exports carry all kinds of names."""
    kind = _text(rp.get("type", ""), f"{at}.type").lower()
    if kind in ("common", "sound", "image"):
        return kind
    if kind == "cubemap":
        return "cube"
    for j, out in enumerate(_list(rp.get("outputs", []), f"{at}.outputs")):
        key = OUTPUT_IDS.get(_id(_object(out, f"{at}.outputs[{j}]").get("id"),
                                 f"{at}.outputs[{j}].id"))
        if key is not None and key != "cube":
            return key
    return pass_key(_text(rp.get("name", ""), f"{at}.name"), at)


def _media(media: Path, src: str, at: str) -> Path:
    """A texture of the export, by file name in ``media`` (a cube map's six faces are
    ``name``, ``name_1`` ... ``name_5`` on Shadertoy: a folder named after the file, or the
    file itself, are accepted)."""
    name = Path(src).name
    if name:
        for candidate in (media / name, media / Path(name).stem):
            if candidate.exists():
                return candidate
    raise InputError(f"{at} needs the media file {name!r}, which is not in {media} "
                     "(download it there, or give --media DIR)")


def _object(value, at: str) -> dict:
    if not isinstance(value, dict):
        raise InputError(f"{at}: expected an object, got {_short(value)}")
    return value


def _list(value, at: str) -> list:
    if value is None:
        return []
    if not isinstance(value, list):
        raise InputError(f"{at}: expected a list, got {_short(value)}")
    return value


def _text(value, at: str) -> str:
    if not isinstance(value, str):
        raise InputError(f"{at}: expected a string, got {_short(value)}")
    return value


def _id(value, at: str) -> str:
    """An output or input id: Shadertoy writes them as numbers or strings."""
    if value is None:
        return ""
    if isinstance(value, bool) or not isinstance(value, (int, str)):
        raise InputError(f"{at}: expected a number or a string, got {_short(value)}")
    return str(value)


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
