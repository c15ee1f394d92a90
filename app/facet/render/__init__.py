"""Render passes over a scene and a camera. Import ``facet.render.renderer`` for the Renderer
(this package's ``__init__`` stays empty so that ``facet.render.shading`` needs no GL)."""
