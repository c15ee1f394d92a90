"""Shader experimentation: users' own GLSL on meshes (``mesh_shaders``) and full-screen
Shadertoy-style programs (``shadertoy``), both hot reloaded through ``programs`` and with
their uniforms checked by ``uniforms``."""
