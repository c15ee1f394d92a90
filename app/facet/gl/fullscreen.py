"""Full-screen passes: one triangle over the viewport (glsl/post/fullscreen.vert, no vertex
buffers) running a fragment stage, for post-processing and Shadertoy-style programs."""

from __future__ import annotations

from pathlib import Path

import moderngl

from . import bindings
from .glsl_source import glsl_root
from .shaders import Program, compile_program


def fullscreen_vertex() -> Path:
    return glsl_root() / "post" / "fullscreen.vert"


class FullScreenPass:
    """A fragment program over the whole viewport. ``textures`` maps sampler uniforms to
    textures (each bound at its unit, facet.gl.bindings); other keyword values are
    uniforms."""

    def __init__(self, ctx: moderngl.Context, fragment, *, program: Program | None = None):
        self.ctx = ctx
        self.program = program or compile_program(ctx, fullscreen_vertex(),
                                                  glsl_root() / fragment)
        # Attribute-less: the vertex shader makes the triangle from gl_VertexID.
        self.vao = ctx.vertex_array(self.program.gl, [])

    def draw(self, textures: dict | None = None, **uniforms) -> None:
        for name, texture in (textures or {}).items():
            texture.use(location=bindings.unit(name))
        for name, value in uniforms.items():
            self.program.set(name, value)
        self.vao.render(vertices=3)

    def release(self) -> None:
        self.vao.release()
        self.program.release()
