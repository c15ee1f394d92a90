"""The path tracer, the third engine behind facet.render.renderer (``engine="path"``): its
engine over the shared ray scene (facet.render.rays), its emitters, area lights and sky."""
