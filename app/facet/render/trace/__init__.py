"""The ray tracer: the second engine behind facet.render.renderer (``engine="trace"``).
``pack`` lays the scene out in arrays (no GL), ``engine`` uploads them and runs
glsl/trace/ over the pixels."""
