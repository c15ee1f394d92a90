"""User shaders for meshes (no GL): the files of a material's own GLSL program and its
uniform values.

A user fragment shader is a complete stage (``#version 330 core`` on line 1) that writes its
colour to output location 0. facet's mesh vertex shader (glsl/mesh/phong.vert, unless
``vertex`` is given) feeds it, in world space:

    in vec3 v_pos_world;  in vec3 v_normal_world;  in vec2 v_uv;  in float v_depth_view;

and facet fills these uniforms when the shader declares them:

    mat4 u_model, u_view, u_projection, u_mvp;  mat3 u_normal_matrix;
    vec3 u_eye_world;  float u_time;  vec2 u_resolution;  vec3 u_color;  int u_object_id;

``#include "lib/lighting.glsl"`` gives the Phong functions; ``#include "lib/lights.glsl"``
the scene's lights (``u_lights[i]``, ``u_light_count``) and ``shade_scene(p, N, V, albedo,
blinn)``, the built-in shading equation with this material's constants.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path


@dataclass(eq=False)
class UserShader:
    """A material's own GLSL: a fragment stage (and optionally a vertex stage) fed by
    facet's vertex shader, with user uniform values (docs: the shader lab).

    Parameters
    ----------
    fragment : str or Path
        The fragment shader file (``#version 330 core``, colour to output 0).
    vertex : str or Path, optional
        A vertex shader file replacing facet's.
    uniforms : dict
        ``{name: value}`` for the shader's own uniforms.
    """

    fragment: Path
    vertex: Path | None = None
    uniforms: dict = field(default_factory=dict)

    def __post_init__(self):
        for attr in ("fragment", "vertex"):
            value = getattr(self, attr)
            if value is None:
                continue
            from ..guard import regular_file

            setattr(self, attr, regular_file(value, "shader file"))
