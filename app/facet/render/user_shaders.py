"""User mesh shaders on the GPU: compiled per (shader, light set), reloaded when any of
their files changes, never swapped in unless they compile (the last good program keeps
drawing), and their user uniforms checked against what the linked program declares."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import FacetError, InputError, ShaderError
from ..gl.glsl_source import file_digest, glsl_root
from ..gl.shaders import GL_TYPES, INT_TYPES, Program, compile_program
from ..scene.shader import UserShader
from .shadertoy import ReloadResult

DEFAULT_VERTEX = "mesh/phong.vert"
# Uniforms facet fills for user mesh shaders (facet.scene.shader lists them).
STANDARD = {"u_model", "u_view", "u_projection", "u_mvp", "u_normal_matrix", "u_eye_world",
            "u_time", "u_resolution", "u_color", "u_object_id", "u_ambient_term",
            "u_light_diffuse", "u_light_specular", "u_shininess"}



class UserPrograms:
    """Cache: (UserShader, defines) -> Program, with file digests for reloading."""

    def __init__(self, ctx, forget_vao):
        self.ctx = ctx
        self._forget_vao = forget_vao  # drops the vertex arrays made for a released program
        self.programs: dict[tuple, Program] = {}
        self.digests: dict[tuple, dict[Path, str | None]] = {}

    def program(self, shader: UserShader, defines: dict) -> Program:
        key = (id(shader), tuple(sorted(defines.items())))
        if key not in self.programs:
            prog = self._compile(shader, defines)
            try:
                self._write_uniforms(prog, shader)
            except BaseException:
                prog.release()
                raise
            prog.shader, prog.defines = shader, defines
            self.programs[key] = prog
            self.digests[key] = {f: file_digest(f) for f in prog.files}
        return self.programs[key]

    def _compile(self, shader: UserShader, defines: dict) -> Program:
        vertex = shader.vertex or glsl_root() / DEFAULT_VERTEX
        return compile_program(self.ctx, vertex, shader.fragment, defines)

    def _write_uniforms(self, prog: Program, shader: UserShader) -> None:
        for name, value in shader.uniforms.items():
            write_user_uniform(prog, name, value, shader.fragment)

    def changed(self) -> bool:
        """Whether a file of any program differs from when it was (re)compiled."""
        return any(file_digest(f) != d for digests in self.digests.values()
                   for f, d in digests.items())

    def reload(self) -> ReloadResult:
        """Recompile the programs whose files changed; keep the old one where the new fails."""
        changed, errors, diagnostics = False, [], []
        for key, prog in list(self.programs.items()):
            if all(file_digest(f) == d for f, d in self.digests[key].items()):
                continue
            changed = True
            self.digests[key] = {f: file_digest(f) for f in self.digests[key]}
            new = None
            try:
                new = self._compile(prog.shader, prog.defines)
                self._write_uniforms(new, prog.shader)
            except ShaderError as exc:
                errors.append(str(exc))
                diagnostics += exc.diagnostics
                continue
            except FacetError as exc:
                errors.append(str(exc))
                if new is not None:
                    new.release()
                continue
            new.shader, new.defines = prog.shader, prog.defines
            self.digests[key] = {f: file_digest(f) for f in new.files}
            self._forget_vao(prog.gl)
            prog.release()
            self.programs[key] = new
        return ReloadResult(not errors, changed, "\n".join(errors), diagnostics)

    def release(self) -> None:
        for prog in self.programs.values():
            self._forget_vao(prog.gl)
            prog.release()
        self.programs.clear()


def write_user_uniform(prog: Program, name: str, value, where) -> None:
    """Set a user uniform, checking its name, size and number type against the program."""
    members = {n.split("[")[0]: prog.gl[n] for n in prog.gl
               if type(prog.gl[n]).__name__ == "Uniform"}
    if name not in members or name in STANDARD:
        user = [n for n in members if n not in STANDARD]
        raise InputError(f"{where}: no uniform named {name!r}; the program's uniforms are: "
                         f"{', '.join(sorted(user)) or 'none'}")
    member = members[name]
    gl_type = GL_TYPES.get(member.gl_type, "?")
    values = np.atleast_1d(np.asarray(value, dtype=np.float64)).ravel()
    size = member.dimension * member.array_length
    if values.size != size or not np.all(np.isfinite(values)):
        raise InputError(f"{where}: uniform {name} is {gl_type}: expected {size} finite "
                         f"number(s), got {values.size}")
    integer = gl_type in INT_TYPES
    if integer and not np.all(values == np.round(values)):
        raise InputError(f"{where}: uniform {name} is {gl_type}: expected integers")
    member.write(values.astype("i4" if integer else "f4").tobytes())
