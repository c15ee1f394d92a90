"""Shader experimentation: full-screen Shadertoy and glslViewer programs (``shadertoy``,
its passes, channels and projects), hot reloaded (facet.gl.reload) with their uniforms
checked (facet.gl.uniforms). Users' shaders on meshes are drawn by the rasterizer
(facet.render.raster.user_shaders); the lab is a front: render never imports it."""
