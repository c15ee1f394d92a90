"""Users' mesh shaders on the GPU: one program per (shader, variant of the frame), with the
user's uniforms checked and written, hot reloaded through facet.gl.reload (a save
that fails to compile keeps the last good program drawing)."""

from __future__ import annotations

from ...gl.glsl_source import glsl_root
from ...gl.reload import ReloadResult, WatchedPrograms
from ...gl.shaders import Program, compile_program
from ...gl.uniforms import check_uniform, write_uniform
from ...scene.shader import UserShader

DEFAULT_VERTEX = "mesh/phong.vert"
# Uniforms facet fills for user mesh shaders (facet.scene.shader lists them; u_material is
# the material record lib/lights.glsl's shade_scene reads).
STANDARD = {"u_model", "u_view", "u_projection", "u_mvp", "u_normal_matrix", "u_eye_world",
            "u_time", "u_resolution", "u_color", "u_object_id", "u_material"}


def compile_mesh_shader(ctx, shader: UserShader, defines: dict) -> Program:
    """A user's fragment (and vertex) stage linked with facet's mesh vertex shader, its
    uniforms written; ShaderError / InputError when either fails."""
    vertex = shader.vertex or glsl_root() / DEFAULT_VERTEX
    prog = compile_program(ctx, vertex, shader.fragment, defines)
    try:
        for name, value in shader.uniforms.items():
            values = check_uniform(name, value, [prog], STANDARD, str(shader.fragment))
            if values is not None:
                write_uniform(prog, name, values)
    except BaseException:
        prog.release()
        raise
    return prog


class UserPrograms:
    """Cache: (UserShader, defines) -> Program, reloaded when any of their files changes."""

    def __init__(self, ctx, forget_vao):
        self.ctx = ctx
        # forget_vao drops the vertex arrays made for a program that is replaced.
        self.watched = WatchedPrograms(on_release=lambda prog: forget_vao(prog.gl))

    def program(self, shader: UserShader, defines: dict) -> Program:
        key = (id(shader), tuple(sorted(defines.items())))
        return self.watched.get(key, lambda: compile_mesh_shader(self.ctx, shader, defines),
                                files=(shader.fragment, shader.vertex))

    def changed(self) -> bool:
        return self.watched.changed()

    def reads_time(self) -> bool:
        """Whether a program made so far reads ``u_time`` (its picture changes by itself)."""
        return any("u_time" in prog.gl for prog in self.watched.programs.values())

    def reload(self) -> ReloadResult:
        """Recompile when a file changed; keep the old programs if a new one fails."""
        return self.watched.reload()

    def release(self) -> None:
        self.watched.release()
