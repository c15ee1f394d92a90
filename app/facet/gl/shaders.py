"""Compiling GLSL programs, and turning driver logs into compiler-style errors.

Driver logs number lines of the expanded source (Mesa: ``0:12(5): error: ...``; NVIDIA:
``0(12) : error C1008: ...``, no column). Mesa's columns are 1-based but count each run of
blanks as one column; ``mesa_column`` turns them into real columns using the source line.
``compile_program`` maps them through the include table of ``facet.gl.glsl_source`` and
raises one ``ShaderError`` reading ``glsl/lib/lighting.glsl:12:6: error: ...`` with two
lines of context.
"""

from __future__ import annotations

import re
from pathlib import Path

import moderngl
import numpy as np

from ..errors import FacetError, ShaderError
from . import bindings
from .glsl_source import ExpandedSource, display_path, expand, glsl_root

_MESA = re.compile(r"^\s*\d+:(\d+)\((\d+)\):\s*(?:preprocessor\s+)?(error|warning)\s*:?\s*(.*)$",
                   re.I)
_NVIDIA = re.compile(r"^\s*\d+\((\d+)\)\s*:\s*(error|warning)\s*\w*\s*:?\s*(.*)$", re.I)
_STAGE_HEADERS = {"vertex_shader": "vertex", "fragment_shader": "fragment",
                  "geometry_shader": "geometry", "compute_shader": "compute"}
# GL type enums of uniforms -> GLSL names (for listings and messages).
GL_TYPES = {0x1406: "float", 0x8B50: "vec2", 0x8B51: "vec3", 0x8B52: "vec4", 0x1404: "int",
            0x8B53: "ivec2", 0x8B54: "ivec3", 0x8B55: "ivec4", 0x8B56: "bool",
            0x8B5A: "mat2", 0x8B5B: "mat3", 0x8B5C: "mat4", 0x8B5E: "sampler2D",
            0x1405: "uint"}
INT_TYPES = {"int", "ivec2", "ivec3", "ivec4", "bool", "uint"}
_UNIFORM_DECL = re.compile(r"\buniform\s+(?:\w+\s+)*?\w+\s+(\w+)")


def parse_log(log: str) -> list[tuple[int, int, str, str]]:
    """(line, column or 0, severity, message) for each diagnostic in a driver log.

    Columns are the driver's own (Mesa's, see ``mesa_column``); NVIDIA gives none: 0.
    """
    found = []
    for raw in log.splitlines():
        if m := _MESA.match(raw):
            found.append((int(m[1]), int(m[2]), m[3].lower(), m[4].strip()))
        elif m := _NVIDIA.match(raw):
            found.append((int(m[1]), 0, m[2].lower(), m[3].strip()))
    return found


def mesa_column(line_text: str, column: int) -> int:
    """The real 1-based column of Mesa's ``column`` in ``line_text`` (Mesa counts a run of
    spaces/tabs as one column)."""
    mesa, i = 1, 0
    while i < len(line_text) and mesa < column:
        if line_text[i] in " \t":
            while i < len(line_text) and line_text[i] in " \t":
                i += 1
        else:
            i += 1
        mesa += 1
    return i + 1


GLSL_SUFFIXES = {".glsl", ".frag", ".vert", ".comp", ".geom", ".fs", ".vs", ".fsh", ".vsh",
                 ".shader", ".inc", ".h"}


def _context_lines(path: str, line: int, column: int, files: list[Path],
                   texts: dict | None = None) -> list[str]:
    """The error line, the two before it, and a caret under the column."""
    source = next((f for f in files if display_path(f) == path), None)
    if source is None:
        return []
    body = (texts or {}).get(source.resolve())  # code given as text (a JSON export's pass)
    if body is None and source.suffix.lower() not in GLSL_SUFFIXES:
        return []  # never quote a file that is not shader source (an include of anything)
    if body is None:
        from ..guard import read_text

        try:  # the file the resolver read (facet's own GLSL is not confined)
            body = read_text(source, "shader file",
                             confine=glsl_root().resolve() not in source.resolve().parents)
        except (FacetError, OSError, RuntimeError, UnicodeDecodeError):
            return []
    text = body.splitlines()
    out = [f"{n:5d} | {text[n - 1]}" for n in range(max(1, line - 2), line + 1)
           if n <= len(text)]
    if column > 0 and out:
        out.append("      | " + " " * (column - 1) + "^")
    return out


def map_log(log: str, sources: dict[str, ExpandedSource], texts=None) -> ShaderError:
    """Build the ``ShaderError`` for a failed compile/link log (sections per stage): errors
    first (the first with its source lines), warnings after them."""
    stage, diagnostics, other = None, [], []
    for raw in log.splitlines():
        key = raw.strip().lower()
        if key in _STAGE_HEADERS:
            stage = _STAGE_HEADERS[key]
            continue
        parsed = parse_log(raw)
        if parsed and stage in sources:
            line, col, severity, message = parsed[0]
            if col and _MESA.match(raw):
                expanded = sources[stage].text.splitlines()
                col = mesa_column(expanded[line - 1], col) if line <= len(expanded) else col
            path, src_line = sources[stage].locate(line)
            diagnostics.append((path, src_line, col, severity, message, stage))
        elif raw.strip().lower().startswith("error") or ": error" in raw.lower():
            other.append(f"{_link_label(sources)}: {raw.strip()}")
    lines = []
    ordered = sorted(diagnostics, key=lambda d: d[3] != "error")  # stable: errors first
    for i, (path, src_line, col, severity, message, stage) in enumerate(ordered):
        lines.append(f"{path}:{src_line}:{col}: {severity}: {message}" if col else
                     f"{path}:{src_line}: {severity}: {message}")
        if i == 0 and severity == "error":
            lines.extend(_context_lines(path, src_line, col, sources[stage].files, texts))
    lines = [*other, *lines] if other and not any(d[3] == "error" for d in diagnostics) \
        else [*lines, *other]
    if not lines:
        lines = [f"{_link_label(sources)}: error: {log.strip()}"]
    return ShaderError("\n".join(lines), [d[:5] for d in diagnostics])


def _link_label(sources: dict[str, ExpandedSource]) -> str:
    names = [src.origin[0][0] for src in sources.values() if src.origin]
    return " + ".join(names) + " (link)"


def compile_program(ctx: moderngl.Context, vertex, fragment, defines=None,
                    search=(), fragment_text: str | None = None,
                    texts: dict | None = None) -> Program:
    """Expand, compile and link a vertex + fragment program; ``ShaderError`` on failure.
    ``fragment_text``: a generated fragment stage named ``fragment``; ``texts``: files given
    as text (see ``expand``)."""
    sources = {"vertex": expand(vertex, defines, search),
               "fragment": expand(fragment, defines, search, text=fragment_text,
                                  texts=texts)}
    try:
        prog = ctx.program(vertex_shader=sources["vertex"].text,
                           fragment_shader=sources["fragment"].text)
    except moderngl.Error as exc:
        resolved = {Path(k).resolve(): v for k, v in (texts or {}).items()}
        raise map_log(str(exc), sources, resolved) from None
    # Every sampler and block to its unit and binding (facet.gl.bindings); facet's own GLSL
    # may declare no sampler the table lacks.
    root = glsl_root().resolve()
    own = fragment_text is None and all(
        f.resolve().is_relative_to(root) for src in sources.values() for f in src.files)
    bindings.bind(prog, own, _link_label(sources))
    return Program(prog, sources)


class Program:
    """A linked program and its expanded sources, with loud uniform writes."""

    def __init__(self, program: moderngl.Program, sources: dict[str, ExpandedSource]):
        self.gl = program
        self.sources = sources
        self.declared = {name for src in sources.values()
                          for name in _UNIFORM_DECL.findall(src.text)}
        self._active = set(program)  # members the linker kept (uniforms, blocks, attributes)

    def set(self, name: str, value, strict: bool = True) -> None:
        """Write uniform ``name``. Declared-but-optimised-away uniforms are skipped; a name the
        shader never declares is an error (a typo must not pass silently) unless ``strict``
        is False (standard inputs a user's shader may not use)."""
        if not strict and name not in self._active:
            return
        if name in self._active:
            member = self.gl[name]
            if isinstance(value, np.ndarray) and value.ndim == 2:
                member.write(mat_bytes(value))
            else:
                member.value = value
        elif name not in self.declared:
            raise ShaderError(f"no uniform named '{name}' in "
                              f"{' + '.join(s.origin[0][0] for s in self.sources.values())}")

    def set_array(self, name: str, values: np.ndarray, strict: bool = True) -> None:
        """Write a float vector array uniform from (N, k) values, zero-padded to its length."""
        if name not in self._active:
            if strict:
                self.set(name, None)  # raises for an undeclared name
            return
        member = self.gl[name]
        width, length = member.dimension, member.array_length
        rows = np.asarray(values, dtype=np.float32).reshape(-1, width)[:length]
        if len(rows) < length:
            rows = np.concatenate([rows, np.zeros((length - len(rows), width), np.float32)])
        member.write(rows.tobytes())

    def uniform_types(self) -> dict[str, tuple[str, int]]:
        """Active uniforms of the linked program: name -> (GLSL type, array length)."""
        found = {}
        for name in self.gl:
            member = self.gl[name]
            if isinstance(member, moderngl.Uniform):
                found[name.split("[")[0]] = (GL_TYPES.get(member.gl_type, hex(member.gl_type)),
                                             member.array_length)
        return found

    @property
    def files(self) -> list[Path]:
        """Every file the program was built from (stages and includes)."""
        return sorted({f for src in self.sources.values() for f in src.files})

    def release(self) -> None:
        self.gl.release()


def mat_bytes(m) -> bytes:
    """A row-major numpy matrix as GLSL's column-major float32 bytes (the one transposition)."""
    return np.ascontiguousarray(np.asarray(m, dtype=np.float32).T).tobytes()
