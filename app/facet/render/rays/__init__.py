"""The ray scene that the Whitted tracer (facet.render.trace) and the path tracer
(facet.render.path) share: ``pack`` lays meshes, instances and materials out as texels (no
GL), ``sprites`` turns points and lines into spheres and capsules, ``layers`` the materials'
images into one texture array, and ``scene`` uploads it all and runs glsl/trace/'s passes."""
