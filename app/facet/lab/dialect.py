"""Which convention a pasted fragment shader follows, and its text made ready to include
(no GL): Shadertoy (``mainImage``) or glslViewer / The Book of Shaders (its own ``main()``
writing ``gl_FragColor`` and reading ``u_time``, ``u_resolution``, ``u_mouse``).

Accepted and handled: a UTF-8 byte-order mark (dropped), a ``#version`` line (blanked: the
wrapper brings its own, and lines keep their numbers), ``precision`` lines and ``#ifdef
GL_ES`` blocks (valid GLSL 3.3). Refused with a sentence of their own: an empty file,
invisible characters pasted from web pages (no-break and zero-width spaces), a file with
both ``mainImage`` and ``main()``, and a file that follows neither convention.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..errors import ShaderError

SHADERTOY, GLSLVIEWER = "shadertoy", "glslviewer"
_COMMENTS = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)
_MAIN_IMAGE = re.compile(r"\bvoid\s+mainImage\s*\(")
_MAIN_CUBEMAP = re.compile(r"\bvoid\s+mainCubemap\s*\(")
_MAIN = re.compile(r"\bvoid\s+main\s*\(\s*(void\s*)?\)")
_VIEWER_NAMES = re.compile(r"\b(gl_FragColor|u_time|u_resolution|u_mouse)\b")
_VERSION = re.compile(r"^\s*#\s*version\b.*$", re.M)
INVISIBLE = {"\u00a0": "a no-break space (U+00A0)", "\u200b": "a zero-width space (U+200B)",
             "\u2009": "a thin space (U+2009)", "\ufeff": "a byte-order mark (U+FEFF)",
             "\u202f": "a narrow no-break space (U+202F)"}


@dataclass(frozen=True)
class Prepared:
    """``kind``: SHADERTOY or GLSLVIEWER; ``text``: what the wrapper includes;
    ``frag_color``: a glslViewer file writes gl_FragColor (else its own ``out``)."""

    kind: str
    text: str
    frag_color: bool = False


def prepare(text: str, name: str, cube: bool = False, common: bool = False) -> Prepared:
    """Check and clean one user file (module docstring); ShaderError with a sentence for
    what cannot run. ``cube``: a Cube A pass (needs mainCubemap); ``common``: the common
    file (no entry point needed)."""
    text = text.removeprefix("\ufeff")
    text = _VERSION.sub("", text)  # the line stays, empty: numbers keep their meaning
    for number, line in enumerate(text.splitlines(), start=1):
        for char, what in INVISIBLE.items():
            if char in line:
                col = line.index(char) + 1
                raise ShaderError(
                    f"{name}:{number}:{col}: error: {what}, invisible in an editor and "
                    "often pasted from web pages; GLSL allows only plain spaces: replace it",
                    [(name, number, col, "error", what)])
    code = _COMMENTS.sub(" ", text)
    if common:
        return Prepared(SHADERTOY, text)
    if not code.strip():
        raise ShaderError(f"{name}: error: the file is empty (no code to run); a Shadertoy "
                          "shader defines mainImage(out vec4 fragColor, in vec2 fragCoord)")
    if cube:
        if not _MAIN_CUBEMAP.search(code):
            raise ShaderError(f"{name}: error: a Cube A pass defines mainCubemap(out vec4 "
                              "fragColor, in vec2 fragCoord, in vec3 rayOri, in vec3 rayDir)")
        return Prepared(SHADERTOY, text)
    has_image, has_main = bool(_MAIN_IMAGE.search(code)), bool(_MAIN.search(code))
    if has_image and has_main:
        line = code[:_MAIN.search(code).start()].count("\n") + 1
        raise ShaderError(f"{name}:{line}: error: defines main() as well as mainImage(): "
                          "facet supplies main() for Shadertoy shaders; remove yours (or "
                          "remove mainImage to run it glslViewer-style)")
    if has_image:
        return Prepared(SHADERTOY, text)
    if has_main and _VIEWER_NAMES.search(code):
        return Prepared(GLSLVIEWER, text, "gl_FragColor" in code)
    if re.search(r"^\s*#\s*include\b", code, re.M):
        return Prepared(SHADERTOY, text)  # mainImage may come from an include
    if has_main:
        raise ShaderError(f"{name}: error: has its own main() but neither gl_FragColor nor "
                          "u_time / u_resolution / u_mouse: facet runs Shadertoy shaders "
                          "(mainImage) and glslViewer / Book of Shaders ones (main() writing "
                          "gl_FragColor)")
    raise ShaderError(f"{name}: error: no mainImage(...) and no main(): is this a Shadertoy "
                      "or a glslViewer shader? (Shadertoy: void mainImage(out vec4 "
                      "fragColor, in vec2 fragCoord); glslViewer: void main() writing "
                      "gl_FragColor)")
