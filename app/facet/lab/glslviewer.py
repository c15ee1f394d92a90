"""glslViewer's multi-buffer convention, as passes of a facet.lab.project.Project (no GL).

One file holds every pass: glslViewer compiles it once per ``BUFFER_N`` (a pass drawn into
the texture ``u_bufferN``) and ``DOUBLE_BUFFER_N`` (a ping-pong pair, ``u_doubleBufferN``,
that reads its own previous frame) it tests in a preprocessor condition, and once more
without either for the picture. Each frame they run in that order (buffers by number,
then double buffers, then the picture), so a pass reading an earlier buffer sees this
frame's result and a buffer reading itself its last one: Shadertoy's rules, so they map
onto Buffer A-D (four at most).
"""

from __future__ import annotations

import re
from dataclasses import replace

from ..errors import InputError
from . import project as P

_CONDITION = re.compile(r"^\s*#\s*(?:if|ifdef|ifndef|elif)\b(.*)$", re.M)
_BUFFER = re.compile(r"\b(DOUBLE_)?BUFFER_(\d+)\b")


def buffer_names(text: str) -> list[tuple[str, str]]:
    """[(define, sampler uniform)] of the buffers ``text`` tests, in glslViewer's order."""
    found = {(bool(m.group(1)), int(m.group(2)))
             for line in _CONDITION.findall(text) for m in _BUFFER.finditer(line)}
    return [(f"{'DOUBLE_' if double else ''}BUFFER_{n}",
             f"u_{'doubleBuffer' if double else 'buffer'}{n}")
            for double, n in sorted(found)]


def with_buffers(project: P.Project, text: str) -> P.Project:
    """``project`` (one glslViewer image pass whose source is ``text``) with a pass per
    buffer the file tests, every pass reading them through their sampler uniforms."""
    names = buffer_names(text)
    if not names:
        return project
    image = project.passes["image"]
    if len(names) > len(P.BUFFERS):
        raise InputError(f"{image.path}: {len(names)} glslViewer buffers "
                         f"({', '.join(d for d, _ in names)}); facet runs at most "
                         f"{len(P.BUFFERS)}")
    samplers = {uniform: P.channel(f"buffer-{slot}", uniform, filter="linear", wrap="clamp")
                for (_, uniform), slot in zip(names, P.BUFFERS, strict=False)}
    passes = {slot: replace(image, key=slot, defines={define: None}, samplers=samplers,
                            label=define)
              for (define, _), slot in zip(names, P.BUFFERS, strict=False)}
    passes["image"] = replace(image, samplers=samplers)
    return replace(project, passes=passes)
