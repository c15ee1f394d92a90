"""The Whitted ray tracer, the second engine behind facet.render.renderer
(``engine="trace"``), over the ray scene it shares with the path tracer (facet.render.rays)."""
