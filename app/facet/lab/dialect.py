"""Which convention a pasted fragment shader follows, and its text made ready to include
(no GL): Shadertoy (``mainImage``) or glslViewer / The Book of Shaders (its own ``main()``
writing ``gl_FragColor`` and reading ``u_time``, ``u_resolution``, ``u_mouse``).

The entry points are looked for after the preprocessor (facet.lab.preprocess), with
Shadertoy's defines (``SHADERTOY_DEFINES``): a ``main()`` in a branch Shadertoy never takes
(``#ifdef GRIMOIRE``) is not there, and a ``mainImage`` made by a macro (code golf's
``#define mainImage(O,u) ...``) is.

The dialect of KDE's shader wallpaper (many shaders shared as Shadertoy ones come from it):
a ``void mainImage()`` without arguments that reads the global ``fragCoord`` and writes the
global ``fragColor`` (facet declares both and fills the first), and its desktop inputs
(``iWindowCount``, ``iWindowRects``, ``iMousePrev``, ...: DESKTOP_INPUTS), declared where a
shader uses one it does not declare, with a desktop of no windows, one screen and one
virtual desktop.

Accepted and handled: a UTF-8 byte-order mark (dropped), a ``#version`` line (blanked: the
wrapper brings its own, and lines keep their numbers), ``#extension`` lines for WebGL 1's
extensions that GLSL 3.3 has built in (blanked: Mesa refuses an ``#extension`` after the
wrapper's declarations, where other compilers take it), ``precision`` lines and ``#ifdef
GL_ES`` blocks (valid GLSL 3.3), and a ``main()`` beside ``mainImage`` (renamed, as
Shadertoy's wrapper renames it: exported buffer passes have one). Refused with a sentence
of their own: an empty file, invisible characters pasted from web pages (no-break and
zero-width spaces), and a file that follows neither convention.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..errors import ShaderError
from .preprocess import preprocess

SHADERTOY, GLSLVIEWER = "shadertoy", "glslviewer"
# What Shadertoy's WebGL 2 compiler defines (GLSL ES 3.00) and its own HW_PERFORMANCE.
SHADERTOY_DEFINES = {"GL_ES": 1, "__VERSION__": 300, "HW_PERFORMANCE": 1}
_COMMENTS = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)
_MAIN_IMAGE = re.compile(r"\bvoid\s+mainImage\s*\(")
_MAIN_IMAGE_GLOBALS = re.compile(r"\bvoid\s+mainImage\s*\(\s*(void\s*)?\)")
# KDE shader wallpaper's inputs beyond Shadertoy's (glsl/shadertoy/host.frag declares each
# under FACET_DECLARE_<name>): what facet sets them to headless, the rest zero.
DESKTOP_INPUTS = ("iMousePrev", "iWindowCount", "iWindowRects", "iWindowRectsPrev",
                  "iWindowVelocities", "iScreenOffset", "iScreenIndex", "iScreenCount",
                  "iVirtualDesktop", "iVirtualDesktopCount", "iVirtualDesktopAnim")
_MAIN_CUBEMAP = re.compile(r"\bvoid\s+mainCubemap\s*\(")
_MAIN = re.compile(r"\bvoid\s+main\s*\(\s*(void\s*)?\)")
_VIEWER_NAMES = re.compile(r"\b(gl_FragColor|u_time|u_resolution|u_mouse)\b")
_VERSION = re.compile(r"^\s*#\s*version\b.*$", re.M)
# WebGL 1 / GLSL ES 1.00 extensions whose functions GLSL 3.30 has in core: their
# #extension lines are blanked (module docstring).
CORE_EXTENSIONS = ("GL_OES_standard_derivatives", "GL_EXT_shader_texture_lod",
                   "GL_EXT_frag_depth", "GL_EXT_draw_buffers", "GL_OES_texture_3D",
                   "GL_EXT_shadow_samplers", "GL_OES_texture_float",
                   "GL_OES_texture_float_linear", "GL_OES_texture_half_float",
                   "GL_OES_texture_half_float_linear", "GL_OES_element_index_uint",
                   "GL_EXT_color_buffer_float")
_CORE_EXTENSION = re.compile(rf"^[ \t]*#[ \t]*extension[ \t]+(?:{'|'.join(CORE_EXTENSIONS)})"
                             r"\b[^\n]*$", re.M)
INVISIBLE = {"\u00a0": "a no-break space (U+00A0)", "\u200b": "a zero-width space (U+200B)",
             "\u2009": "a thin space (U+2009)", "\ufeff": "a byte-order mark (U+FEFF)",
             "\u202f": "a narrow no-break space (U+202F)"}


@dataclass(frozen=True)
class Prepared:
    """``kind``: SHADERTOY or GLSLVIEWER; ``text``: what the wrapper includes;
    ``frag_color``: a glslViewer file writes gl_FragColor (else its own ``out``);
    ``defines``: the wrapper's defines it needs (the KDE dialect's, module docstring)."""

    kind: str
    text: str
    frag_color: bool = False
    defines: tuple[str, ...] = ()
    rename_main: bool = False  # a main() beside mainImage: renamed, as Shadertoy's wrapper does


def declared_inputs(code: str) -> set[str]:
    """The DESKTOP_INPUTS that ``code`` declares itself (as uniforms)."""
    code = _COMMENTS.sub(" ", code)
    return {name for name in DESKTOP_INPUTS
            if re.search(rf"\buniform\b[^;]*\b{name}\b", code)}


def desktop_defines(code: str) -> tuple[str, ...]:
    """The wrapper's defines for the KDE dialect in ``code`` (preprocessed, comments kept
    out): its desktop inputs used and not declared, and FACET_GLOBAL_FRAG for a
    ``mainImage()`` without arguments (FACET_GLOBAL_MAIN: the only one there is)."""
    code = _COMMENTS.sub(" ", code)
    out = [f"FACET_DECLARE_{name}" for name in DESKTOP_INPUTS
           if re.search(rf"\b{name}\b", code) and name not in declared_inputs(code)]
    if _MAIN_IMAGE_GLOBALS.search(code):
        out.append("FACET_GLOBAL_FRAG")
        if len(_MAIN_IMAGE.findall(code)) == len(_MAIN_IMAGE_GLOBALS.findall(code)):
            out.append("FACET_GLOBAL_MAIN")
    return tuple(out)


def prepare(text: str, name: str, cube: bool = False, common: bool = False) -> Prepared:
    """Check and clean one user file (module docstring); ShaderError with a sentence for
    what cannot run. ``cube``: a Cube A pass (needs mainCubemap); ``common``: the common
    file (no entry point needed)."""
    text = text.removeprefix("\ufeff")
    text = _VERSION.sub("", text)  # the line stays, empty: numbers keep their meaning
    text = _CORE_EXTENSION.sub("", text)
    for number, line in enumerate(text.splitlines(), start=1):
        for char, what in INVISIBLE.items():
            if char in line:
                col = line.index(char) + 1
                raise ShaderError(
                    f"{name}:{number}:{col}: error: {what}, invisible in an editor and "
                    "often pasted from web pages; GLSL allows only plain spaces: replace it",
                    [(name, number, col, "error", what)])
    if common:
        return Prepared(SHADERTOY, text, defines=desktop_defines(text))
    raw = _COMMENTS.sub(" ", text)
    pre = preprocess(text, SHADERTOY_DEFINES)
    code = pre.text
    defines = desktop_defines(code)
    if not raw.strip():
        raise ShaderError(f"{name}: error: the file is empty (no code to run); a Shadertoy "
                          "shader defines mainImage(out vec4 fragColor, in vec2 fragCoord)")
    if cube:
        if not _MAIN_CUBEMAP.search(code) and "mainCubemap" not in pre.macros:
            raise ShaderError(f"{name}: error: a Cube A pass defines mainCubemap(out vec4 "
                              "fragColor, in vec2 fragCoord, in vec3 rayOri, in vec3 rayDir)")
        return Prepared(SHADERTOY, text, defines=defines)
    has_image = bool(_MAIN_IMAGE.search(code)) or "mainImage" in pre.macros
    has_main = bool(_MAIN.search(code))
    if has_image and has_main:  # Shadertoy's wrapper renames the file's own main(): so here
        return Prepared(SHADERTOY, text, defines=defines, rename_main=True)
    if has_image:
        return Prepared(SHADERTOY, text, defines=defines)
    if has_main and _VIEWER_NAMES.search(code):
        return Prepared(GLSLVIEWER, text, "gl_FragColor" in code)
    if re.search(r"^\s*#\s*include\b", raw, re.M):
        return Prepared(SHADERTOY, text, defines=defines)  # (mainImage from an include)
    if has_main:
        raise ShaderError(f"{name}: error: has its own main() but neither gl_FragColor nor "
                          "u_time / u_resolution / u_mouse: facet runs Shadertoy shaders "
                          "(mainImage) and glslViewer / Book of Shaders ones (main() writing "
                          "gl_FragColor)")
    raise ShaderError(f"{name}: error: no mainImage(...) and no main(): is this a Shadertoy "
                      "or a glslViewer shader? (Shadertoy: void mainImage(out vec4 "
                      "fragColor, in vec2 fragCoord); glslViewer: void main() writing "
                      "gl_FragColor)")


def blame_user(exc: ShaderError, name: str, text: str) -> ShaderError:
    """An error the compiler reports inside facet's wrapper is caused by the user's file
    (the wrapper compiles on its own): say so at the end of that file, with the likely
    cause (an unclosed bracket), never pointing into facet's files."""
    host = [d for d in exc.diagnostics if d[0].startswith("glsl/shadertoy/")]
    if not host or any(d[3] == "error" and not d[0].startswith("glsl/shadertoy/")
                       for d in exc.diagnostics):
        return exc
    code = re.sub(r"//[^\n]*|/\*.*?\*/", " ", text, flags=re.S)
    unclosed = [f"{code.count(o) - code.count(c)} unclosed '{o}'"
                for o, c in (("{", "}"), ("(", ")"), ("[", "]")) if code.count(o) > code.count(c)]
    if "/*" in code:  # (complete comments are gone: this one never closes)
        unclosed.insert(0, "a /* comment with no */")
    cause = ("; it ends early: " + ", ".join(unclosed)) if unclosed else \
        " (a #define in it that renames something Shadertoy declares, like iTime?)"
    last = max(len(text.splitlines()), 1)
    message = host[0][4]
    return ShaderError(f"{name}:{last}: error: {message} where facet's wrapper continues after "
                       f"your file{cause}", [(name, last, 0, "error", message)])
