"""The rasterizer: the first engine behind facet.render.renderer (``engine="raster"``):
forward shading, shadow maps, order-independent transparency, planar mirrors, image-based
lighting, back-face culling, the wireframe overlay and users' mesh shaders."""
