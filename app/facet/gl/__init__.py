"""The only package that imports moderngl: contexts, shader programs, GPU resources, targets.

Submodules are imported explicitly (``facet.gl.context`` ...) so that importing
``facet.gl.glsl_source`` alone stays free of GL.
"""
