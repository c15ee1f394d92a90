"""Drawing into a window: ``Renderer.present`` and ``Renderer.present_progressive``.

The viewer gets the same passes and shaders as headless rendering; only the destination
differs. A window's framebuffer is bottom-up like GL, so these draws are not flipped
(headless targets are, see facet.gl.targets) and nothing is read back.

- ``present``: one picture per call — MSAA if the renderer has it, transparent objects by
  the same weighted blended OIT as ``render``, area lights from their centres, the camera's
  pinhole and the shutter-open pose. It is what a moving camera shows.
- ``present_progressive``: one supersample per call into the accumulator, with the lens,
  shutter-time and area-light points of that sample, so a still camera converges to
  exactly the headless ``render(aa=...)`` picture (depth of field, motion blur, soft
  shadows and glossy reflection included).
"""

from __future__ import annotations

from ..errors import InputError
from .antialias import parse_aa, point_lights_for
from .shading import check_shading
from .transparency import split_transparent

EDGE_COLOR = (0.05, 0.05, 0.05)  # the wireframe overlay's colour (unlit)


class WindowPresenter:
    """The window half of ``facet.render.renderer.Renderer`` (a mixin: it uses the
    renderer's context, targets, passes and shadow maps)."""

    def present(self, scene, camera, framebuffer, *, shading: str | None = None,
                wireframe: bool = False, time: float = 0.0, shadows: bool = False) -> None:
        """Draw ``scene`` into ``framebuffer`` (a window's) with the same passes as
        ``render``; ``wireframe`` overlays the triangle edges."""
        shading = check_shading(shading or self.shading)
        w, h, t, ctx = self.width, self.height, self.targets, self.ctx
        scene = point_lights_for(scene)
        self._shadows = self._draw_shadows(scene) if shadows else None  # own framebuffer
        opaque, transparent = split_transparent(scene)
        ctx.enable_only(ctx.DEPTH_TEST)
        bg = self._background(scene, window=True)
        # The opaque picture goes straight into the window unless it needs resolving (MSAA)
        # or transparent layers composited over it: then into the renderer's targets.
        if self.msaa:
            target = t.begin_multisample(bg)
        elif transparent is not None:
            target = t.begin_color(bg)
        else:
            target = framebuffer
            framebuffer.use()
            framebuffer.clear(*bg, depth=1.0)
        self._colour_draw(opaque, camera, shading, flip_y=False, time=time)
        if transparent is not None:
            zbuffer = t.zbuffer
            if self.msaa:  # layers against the multisampled depth, over the resolved colour
                t.resolve()
                zbuffer, target = t.ms_z, t.color_only
            oit = self._oit().begin(zbuffer)
            self._colour_draw(transparent, camera, shading, flip_y=False, time=time, oit=True)
            self._transparency.end(oit, target)
        if wireframe:
            target.use()
            ctx.depth_func = "<="
            ctx.wireframe = True
            self.forward.draw(_edges(scene), camera, w, h, "unlit", flip_y=False)
            ctx.wireframe = False
            ctx.depth_func = "<"
        if target is not framebuffer:
            ctx.copy_framebuffer(framebuffer, target)
        self.cache.sweep()

    def present_progressive(self, scene, camera, framebuffer, aa: str, index: int, *,
                            shading: str | None = None, time: float = 0.0,
                            shadows: bool = False) -> int:
        """Supersampling in a window, one sample per call: add sample ``index`` of ``aa``'s
        pattern (0 starts over) and show the mean so far. Returns the samples shown; after
        the last one the picture equals the headless ``render(aa=..., shadows=...)``."""
        from .antialias import Accumulator

        mode = parse_aa(aa)
        if mode.kind != "ssaa":
            raise InputError(f"progressive rendering needs ssaa, got {aa!r}")
        shading = check_shading(shading or self.shading)
        if self._accumulator is None:
            self._accumulator = Accumulator(self.ctx, self.width, self.height)
        acc = self._accumulator
        index = min(index, mode.samples - 1)
        if index == 0:
            self._shadows_on, self._pcf = shadows, 1
            self._shadows = self._draw_shadows(point_lights_for(scene)) if shadows else None
            acc.accum.use()
            acc.accum.clear(0.0, 0.0, 0.0, 0.0)
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        # Upright (no flip): the window shows the accumulation as it is.
        bg = self._background(scene, window=True)
        self._draw_sample(scene, camera, shading, mode, index, bg, time, flip_y=False)
        acc.show(framebuffer, index + 1)
        self.cache.sweep()
        return index + 1


def _edges(scene):
    """The same objects with a dark unlit material, for the wireframe overlay (no GL made)."""
    from ..scene.material import Material
    from ..scene.scene import SceneObject

    material = Material(color=EDGE_COLOR)
    edges = scene.view(objects=[SceneObject(o.id, o.mesh, material, o.transform, o.name)
                                for o in scene.objects], lights=[])
    edges.environment = None  # no second sky pass
    return edges
