"""The path tracer as an engine (facet.render.engine): the ray tracer's scene upload, its
hierarchy and its exact channels (facet.render.trace.engine), with colour from
glsl/trace/path.frag: light that bounces between surfaces, by the glTF metallic-roughness
model (lib/pbr.glsl, the rasterizer's), instead of the Whitted tracer's ambient term.

One path per pixel and supersample; a sum of samples like the tracer's (msaa:N or spp=N:
N paths per pixel). The random stream of a path is a hash of its pixel and sample index,
so a picture is the same on every run. Its colour is linear radiance: float colour as it
is, 8-bit colour sRGB-encoded (as the rasterizer's metallic-roughness model writes it), in
either colour mode. ``max_depth`` is the most bounces after the eye
ray; left at facet's default (the Whitted tracer's 5) the path tracer takes
``DEFAULT_BOUNCES``.
"""

from __future__ import annotations

import numpy as np

from ...scene.option_values import DEFAULT_MAX_DEPTH
from ...scene.pbr import PbrMaterial
from ...srgb import srgb_to_linear
from .engine import TraceEngine, feature_lines

DEFAULT_BOUNCES = 8


class PathEngine(TraceEngine):
    """The path tracer of one renderer (module docstring)."""

    name = "path"
    radiance = True
    _sample = 0  # the supersample being drawn (sample_state)

    def sample_state(self, scene, scene_k, state, opts, k: int, plain: bool):
        self._sample = k
        return state

    def draw_sample(self, scene, state, opts, surf, background) -> None:
        bounces = DEFAULT_BOUNCES if opts.max_depth == DEFAULT_MAX_DEPTH else opts.max_depth
        if not state.srgb:  # a display value here; the output is encoded (Engine.radiance)
            background = (*srgb_to_linear(np.asarray(background[:3])), background[3])
        self.draw_colour(scene, state, self._program("path", state, False),
                         u_background=background, u_max_depth=int(bounces),
                         u_sample=self._sample, u_seed=0)

    def unsupported(self, opts, scene) -> list[str]:
        """What the path tracer does not draw as asked (each a warning line)."""
        lines = []
        if opts.wireframe:
            lines.append("the path tracer draws no wireframe overlay")
        if opts.shading not in ("auto", "pbr", "phong"):
            lines.append(f"the path tracer shades by the metallic-roughness model, not "
                         f"shading = {opts.shading}")
        if opts.cull == "on":
            lines.append("the path tracer culls no back faces for cull = on (only "
                         "single-sided glTF materials lose theirs)")
        if not opts.shadows_on:
            lines.append("the path tracer always traces shadows (shadows = off ignored)")
        return lines + feature_lines(scene, _dropped, "the path tracer")


def _dropped(m) -> list[str]:
    """The material features of ``m`` the path tracer does not draw yet."""
    out = []
    if m.shader is not None:
        out.append("users' mesh shaders")
    if not isinstance(m, PbrMaterial):
        if m.reflectivity > 0:
            out.append("Phong reflectivity (mirrors: traced as the metallic-roughness "
                       "mapping of the Phong terms)")
        if m.opacity < 1 or m.ior > 0:
            out.append("Phong opacity and ior (traced opaque)")
        return out
    if m.unlit:
        out.append("KHR_materials_unlit")
    slots = m.slots
    for slot, what in (("metallic_roughness", "metallic-roughness textures"),
                       ("normal", "normal maps"), ("emissive", "emissive textures")):
        if slot in slots:
            out.append(what)
    if any(not np.array_equal(s.transform, np.eye(3)) for s in slots.values()):
        out.append("texture transforms (KHR_texture_transform)")
    if any(s.texcoord != 0 for s in slots.values()):
        out.append("second texture coordinate sets")
    if m.alpha_mode != "OPAQUE":
        out.append(f"alpha {m.alpha_mode} (traced opaque)")
    return out



