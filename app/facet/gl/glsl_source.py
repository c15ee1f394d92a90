"""GLSL source assembly: finding shader files, ``#include`` expansion, and the line table.

Pure Python (no GL), so it is testable anywhere. ``expand(path)`` returns the expanded text and
a table from each expanded line to the (file, line) it came from; ``facet.gl.shaders`` maps
driver error logs through it. Rules:

* ``#version`` only on line 1 of a stage file (.vert/.frag/.comp); defines go right after it.
* ``#include "name"`` looks next to the including file first, then in each search root
  (the bundled ``glsl/`` directory last). Each file is included once per program.
* A cycle is an error showing the chain; a missing file is an error at the including
  file and line.
* Input controls the depth: the expansion is a loop over an explicit stack (no recursion),
  no deeper than the depth budget, and the files together no larger than the shader budget
  (facet.budgets: a compiler fed megabytes of source can crash); every file is read through
  facet.guard (regular files only: an include that is a FIFO or a device is refused).
"""

from __future__ import annotations

import functools
import hashlib
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..budgets import budget
from ..errors import FacetError, ShaderError
from ..paths import data_dir

_INCLUDE = re.compile(r'^\s*#\s*include\s+(?:"([^"]+)"|<([^>]+)>)\s*(?://.*)?$')
_VERSION = re.compile(r"^\s*#\s*version\b")


@functools.cache
def glsl_root() -> Path:
    """The bundled shader directory: ``facet/glsl`` in a wheel, ``<repo>/glsl`` in a checkout."""
    return data_dir("glsl", "lib/lighting.glsl")


def file_digest(path: Path) -> str | None:
    """SHA-1 of a file's content (None if it is missing, not a regular file, or larger than
    the file budget): reloads compare content, not timestamps, so touching a file or saving
    it unchanged reloads nothing. A watched FIFO or device is never opened, nor a file
    outside the confinement folder (facet.guard.confined; facet's own GLSL aside)."""
    from ..guard import read_bytes

    try:
        own = glsl_root().resolve() in Path(path).resolve().parents
        return hashlib.sha1(read_bytes(path, "shader file", confine=not own)).hexdigest()
    except (OSError, RuntimeError, FacetError):
        return None


def display_path(path: Path) -> str:
    """A short name for messages: ``glsl/...`` for bundled shaders, else relative to cwd."""
    path = Path(path).resolve()
    try:
        return "glsl/" + path.relative_to(glsl_root()).as_posix()
    except (ValueError, FacetError):
        pass
    try:
        return path.relative_to(Path.cwd()).as_posix()
    except ValueError:
        return str(path)


@dataclass
class ExpandedSource:
    """Expanded GLSL. ``origin[i]`` is the (display path, 1-based line) of expanded line i+1."""

    text: str
    origin: list[tuple[str, int]]
    files: list[Path] = field(default_factory=list)  # every file read, stage file first

    def locate(self, line: int) -> tuple[str, int]:
        """(file, line) of 1-based expanded ``line``; out-of-range lines clamp to the ends."""
        if not self.origin:
            return ("<empty>", line)
        return self.origin[min(max(line, 1), len(self.origin)) - 1]


def expand(path, defines: dict[str, object] | None = None,
           search: tuple[Path, ...] = (), text: str | None = None,
           texts: dict[Path, str] | None = None) -> ExpandedSource:
    """Read the stage file ``path`` and expand its includes; see the module docstring.

    With ``text`` the stage is generated in memory (e.g. a host around a user's shader);
    ``path`` then only names it and anchors its relative includes. ``texts``: files given
    as text instead of read from disk (resolved paths: a user's file cleaned up, a pass of
    a JSON export). A missing include's error lists the paths it looked for in
    ``missing``, so a reload can watch for the file to appear.
    """
    stage = Path(path)
    if text is None and not stage.exists():
        raise ShaderError(f"{display_path(stage)}: no such shader file")
    return _Expansion(stage, defines or {}, search, text, texts).run()


class _Expansion:
    """One expansion (``expand``): the files in include order, the lines out and where
    each came from."""

    def __init__(self, stage: Path, defines: dict, search, text, texts):
        self.stage, self.defines, self.stage_text = stage, defines, text
        self.texts = {Path(k).resolve(): v for k, v in (texts or {}).items()}
        self.roots = tuple(Path(p) for p in search) + (glsl_root(),)
        self.own = glsl_root().resolve()  # facet's library: always readable, never confined
        self.out_lines: list[str] = []
        self.origin: list[tuple[str, int]] = []
        self.files: list[Path] = []
        self.done: set[Path] = set()
        self.size_limit, self.depth_limit = budget("shader_bytes"), budget("depth")
        self.total = 0

    def emit(self, text: str, where: tuple[str, int]) -> None:
        self.out_lines.append(text)
        self.origin.append(where)

    def read(self, file: Path, is_stage: bool) -> list[str]:
        """The lines of ``file`` (given text first), read through facet.guard."""
        name = display_path(file)
        if is_stage and self.stage_text is not None:
            body = self.stage_text
        elif file in self.texts:
            body = self.texts[file]
        else:
            try:
                body = self._read(file, name)
            except UnicodeDecodeError:
                raise ShaderError(f"{name}: error: not a text file (GLSL must be UTF-8)") \
                    from None
        self.total += len(body)
        if self.total > self.size_limit:
            raise ShaderError(f"{name}: error: the shader and its includes pass "
                              f"{self.size_limit:,} bytes, facet's budget (a GL compiler fed "
                              "that much can crash; raise it with --budget shader_bytes=N)")
        return body.splitlines()

    def _read(self, file: Path, name: str) -> str:
        """``file``'s text through facet.guard, its size checked against what is left of
        the shader budget before a byte is read (a sparse 3 GiB include is refused, not
        read)."""
        from ..guard import opened

        with opened(file, "shader file", ShaderError,
                    confine=self.own not in file.parents) as (f, size):
            if self.total + size > self.size_limit:
                raise ShaderError(f"{name}: error: the shader and its includes pass "
                                  f"{self.size_limit:,} bytes, facet's budget (a GL compiler "
                                  "fed that much can crash; raise it with --budget "
                                  "shader_bytes=N)")
            text = f.read(size).decode("utf-8")
        return text.replace("\r\n", "\n").replace("\r", "\n")

    def enter(self, file: Path, chain: list[Path], is_stage: bool):
        """A frame for ``file`` (None when it was included already)."""
        file = file.resolve()
        if file in chain:
            names = " -> ".join(display_path(p) for p in [*chain, file])
            raise ShaderError(f"{display_path(chain[-1])}: error: #include cycle: {names}")
        if file in self.done:
            return None
        if len(chain) >= self.depth_limit:
            raise ShaderError(f"{display_path(chain[-1])}: error: #include nested more than "
                              f"{self.depth_limit:,} deep, facet's budget (--budget depth=N)")
        self.done.add(file)
        self.files.append(file)
        return [file, self.read(file, is_stage), 0, chain, is_stage, display_path(file)]

    def include(self, target: str, file: Path, chain: list, is_stage: bool, where) -> list:
        """The frame of ``#include target`` in ``file`` (empty: included already); the
        error names the paths searched."""
        for base in (file.parent, *self.roots):
            candidate = base / target
            if self.own not in (base.resolve(), *base.resolve().parents):  # outside facet's
                from ..guard import check_confined  # library, what is outside is refused

                check_confined(candidate, "include file", ShaderError)
            if candidate.exists() or candidate.resolve() in self.texts:
                inner = self.enter(candidate, [*chain, file], is_stage=False)
                return [] if inner is None else [inner]
        name, number, col = where
        searched = ", ".join(display_path(b) for b in (file.parent, *self.roots))
        error = ShaderError(f'{name}:{number}:{col}: error: cannot find include '
                            f'"{target}" (searched {searched})')
        error.missing = [file.parent / target]  # where a new file would be found
        raise error

    def run(self) -> ExpandedSource:
        stack = [self.enter(self.stage, [], True)]
        while stack:
            frame = stack[-1]
            file, lines, index, chain, is_stage, name = frame
            if index >= len(lines):
                stack.pop()
                continue
            line, number = lines[index], index + 1
            frame[2] += 1
            if _VERSION.match(line):
                if not (is_stage and number == 1):
                    raise ShaderError(f"{name}:{number}:1: error: #version belongs on line 1 "
                                      "of a stage file only (.vert/.frag/.comp)")
                self.emit(line, (name, number))
                for key, value in self.defines.items():
                    self.emit(f"#define {key} {'' if value is None else value}".rstrip(),
                              ("<defines>", len(self.origin)))
                continue
            m = _INCLUDE.match(line)
            if not m:
                self.emit(line, (name, number))
                continue
            target = m.group(1) or m.group(2)
            col = line.index(target) + 1 if target in line else 1
            stack += self.include(target, file, chain, is_stage, (name, number, col))
        if self.stage_text is not None:
            self.files.remove(self.stage.resolve())  # nothing on disk to watch or quote
        if not self.out_lines or not _VERSION.match(self.out_lines[0]):
            raise ShaderError(f"{display_path(self.stage)}:1:1: error: a stage file must "
                              "start with #version (for example '#version 330 core')")
        return ExpandedSource("\n".join(self.out_lines) + "\n", self.origin, self.files)
