"""A Shadertoy-style project assembled and checked before any GL (facet.lab.shadertoy):
from ShaderToy's keyword arguments (``from_arguments``: every file checked, channels given
for every pass or per pass), with a glslViewer file's buffers as passes
(``with_glslviewer_buffers``), and every channel's buffer and image present
(``check_channels``).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError, ShaderError
from ..gl.glsl_source import display_path
from . import project as P
from .dialect import GLSLVIEWER, prepare
from .glslviewer import with_buffers


def with_glslviewer_buffers(project: P.Project) -> P.Project:
    """A single glslViewer file that tests BUFFER_N / DOUBLE_BUFFER_N: its buffers as
    passes (facet.lab.glslviewer)."""
    if set(project.passes) != {"image"}:
        return project
    image = project.passes["image"]
    if image.code is not None:
        text = image.code
    else:
        from ..guard import read_text

        try:
            text = read_text(image.path, "shader file")
        except UnicodeDecodeError:
            return project  # _compile says so
    try:
        kind = prepare(text, display_path(image.path)).kind
    except ShaderError:
        return project  # _compile says why, with the rest of the errors
    return with_buffers(project, text) if kind == GLSLVIEWER else project


def from_arguments(image, buffers, common, cube, channels, pass_channels) -> P.Project:
    """A Project from ShaderToy's keyword arguments (every file checked)."""
    if image is None:
        raise InputError("ShaderToy needs an image shader (or a project)")
    passes = {"image": P.Pass("image", existing(image, "shader"))}
    for key, path in (buffers or {}).items():
        if key not in P.BUFFERS:
            raise InputError(f"buffer {key!r}: buffers are a, b, c and d")
        passes[key] = P.Pass(key, existing(path, f"buffer {key}"))
    if cube is not None:
        passes["cube"] = P.Pass("cube", existing(cube, "Cube A shader"))
    shared = {}
    for index, spec in channels.items():
        if index not in range(4):
            raise InputError(f"channel {index}: channels are 0 to 3")
        shared[index] = P.channel(spec, f"--channel{index}")
    for p in passes.values():
        p.channels = dict(shared)
    for name, chans in pass_channels.items():
        key = P.pass_key(name, "pass_channels")
        if key not in passes:
            raise InputError(f"channels given for the {P.PASS_NAMES[key]} pass, which has no "
                             "shader")
        for index, spec in chans.items():
            if index not in range(4):
                raise InputError(f"{P.PASS_NAMES[key]} channel {index}: channels are 0 to 3")
            passes[key].channels[index] = P.channel(spec, f"{P.PASS_NAMES[key]} channel "
                                                          f"{index}")
    return P.Project(passes, existing(common, "common file") if common else None)


def check_channels(project: P.Project) -> None:
    """Every buffer a channel reads has a pass; every image exists."""
    for p in project.ordered():
        for n, ch in p.channels.items():
            if ch.kind == "buffer" and ch.source not in project.passes:
                src = "cube-a" if ch.source == "cube" else f"buffer-{ch.source}"
                flag = "--cube-a" if ch.source == "cube" else f"--buffer-{ch.source}"
                raise InputError(f"{p.name} channel {n} reads {src}, but no {src} was given "
                                 f"({flag} FILE)")
            if ch.kind in ("texture", "cube", "volume") and isinstance(ch.source, Path):
                from ..guard import check_confined

                check_confined(ch.source, "texture file")  # before asking whether it exists
                if ch.kind in ("texture", "volume") and not ch.source.is_file():
                    raise InputError(f"{ch.source}: no such {ch.kind} file ({p.name} channel "
                                     f"{n})")


def existing(path, what: str) -> Path:
    from ..guard import regular_file

    return regular_file(path, what)
