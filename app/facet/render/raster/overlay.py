"""The wireframe overlay: every triangle's edges over the picture, in a dark unlit colour,
drawn after the opaque objects with the depth test at "<=" so visible edges win."""

from __future__ import annotations

from dataclasses import replace

from ...gl.targets import writing
from ...scene.material import Material

EDGE_COLOR = (0.05, 0.05, 0.05)


def wireframe_overlay(forward, scene, state) -> None:
    """Draw ``scene``'s edges into the bound target with ``forward`` (a ForwardPass)."""
    material = Material(color=EDGE_COLOR)
    edges = scene.view(objects=[replace(o, material=material) for o in scene.objects
                                if o.mesh.kind == "mesh"], lights=[])  # (not points, lines)
    ctx = forward.ctx
    ctx.depth_func = "<="
    ctx.wireframe = True
    # Lines pulled a depth step towards the camera: a line's depth and its own triangle's
    # fill differ by rounding, which decided edge by edge whether "<=" let it through (so a
    # window's picture, drawn unflipped, showed other edges than the offscreen render).
    ctx.polygon_offset = (-1.0, -1.0)
    try:
        with writing(ctx.fbo, exact=False):  # the lines leave the exact channels as they are
            forward.draw(edges, state.with_(shading="unlit", lights=(), shadows=None,
                                            environment=None), colour_pass=False)
    finally:
        ctx.polygon_offset = (0.0, 0.0)
        ctx.wireframe = False
        ctx.depth_func = "<"
