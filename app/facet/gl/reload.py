"""Hot reload, written once for mesh shaders and Shadertoy passes: programs built from files,
recompiled when a file's content changes, and swapped in only when every one of them
compiles, so the last good programs keep drawing while a file is broken.

Files are compared by content (SHA-1), not timestamps: touching a file or saving it
unchanged reloads nothing. ``reload`` returns a ``ReloadResult`` whose ``errors`` read like a
compiler (``path:line:col: error: ...``, mapped through includes to the user's files).
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import FacetError, ShaderError
from .glsl_source import file_digest
from .shaders import Program


@dataclass
class ReloadResult:
    """What ``reload()`` did: ``success`` (all programs compiled and are in use), ``changed``
    (some file's content differed), ``errors`` (compiler-style text) and ``diagnostics``."""

    success: bool
    changed: bool = True
    errors: str = ""
    diagnostics: list = field(default_factory=list)


class WatchedPrograms:
    """Programs by key, each made by its ``build()`` (which compiles and writes the user's
    uniforms); ``on_release(program)`` runs before a replaced program is released (to drop
    vertex arrays made for it)."""

    def __init__(self, on_release: Callable[[Program], None] | None = None):
        self.programs: dict[Hashable, Program] = {}
        self._builders: dict[Hashable, Callable[[], Program]] = {}
        self._digests: dict[Path, str | None] = {}
        self._extra: tuple[Path, ...] = ()
        self._failed: set[Path] = set()  # stages of first builds that failed (``get``)
        self._on_release = on_release
        self.labels: dict[Hashable, str] = {}  # key -> the name errors give it (passes)

    def get(self, key: Hashable, build: Callable[[], Program], files=()) -> Program:
        """The program for ``key``, built on first use (errors raise). When that first
        build fails, ``files`` (its stages) are watched all the same: fixing them reloads
        it (a viewer started on a broken shader draws once it is fixed)."""
        if key not in self.programs:
            self._builders[key] = build
            try:
                self.programs[key] = build()
            except FacetError:
                self._failed |= {Path(f).resolve() for f in files if f is not None}
                self._remember()
                raise
            self._remember()
        return self.programs[key]

    def add(self, key: Hashable, build: Callable[[], Program]) -> None:
        """Register ``key``'s builder; the next ``reload(force=True)`` builds it."""
        self._builders[key] = build

    def watch(self, *paths) -> None:
        """Also watch ``paths`` (files that decide what is built, e.g. a pass's source)."""
        self._extra = tuple(Path(p).resolve() for p in paths)
        self._remember()

    def files(self) -> list[Path]:
        """Every file the programs were built from (stages and includes), and the watched."""
        found = {f.resolve() for prog in self.programs.values() for f in prog.files}
        return sorted(found | set(self._extra) | self._failed)

    def _remember(self, extra=()) -> None:
        self._digests = {f: file_digest(f) for f in {*self.files(), *extra}}

    def changed(self) -> bool:
        """Whether a watched file's content differs from the last (re)load."""
        return any(file_digest(f) != d for f, d in self._digests.items())

    def reload(self, force: bool = False) -> ReloadResult:
        """Rebuild every program when a file changed (or ``force``); keep the old ones if
        any fails."""
        if not force and not self.changed():
            return ReloadResult(True, changed=False)
        new, errors, diagnostics, missing = {}, [], [], []
        for key, build in self._builders.items():
            try:
                new[key] = build()
            except ShaderError as exc:
                errors.append(self.label(key, str(exc)))
                diagnostics += exc.diagnostics
                missing += exc.missing
            except FacetError as exc:
                errors.append(self.label(key, str(exc)))
        # Remember what was read now, the failed attempt's files included (and includes
        # that do not exist yet: creating one is a change), so that only a new change
        # triggers the next reload.
        self._remember(extra=[*(f for p in new.values() for f in p.files),
                              *(Path(m).resolve() for m in missing)])
        if errors:
            for prog in new.values():
                prog.release()
            return ReloadResult(False, errors="\n".join(errors), diagnostics=diagnostics)
        for prog in self.programs.values():
            self._release(prog)
        self.programs, self._failed = new, set()
        self._remember()
        return ReloadResult(True)

    def label(self, key: Hashable, text: str) -> str:
        """``text`` with each line naming the program it is about (``labels[key]``), when
        there is more than one program to tell apart."""
        name = self.labels.get(key)
        if name is None:
            return text
        return "\n".join(f"[{name}] {line}" if line and not line.startswith(" ") else line
                         for line in text.splitlines())

    def _release(self, prog: Program) -> None:
        if self._on_release is not None:
            self._on_release(prog)
        prog.release()

    def release(self) -> None:
        for prog in self.programs.values():
            self._release(prog)
        self.programs.clear()
        self._builders.clear()
