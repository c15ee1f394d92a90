"""``Renderer`` (owns a GL context and everything made in it) and ``Frame`` (its results).

    with Renderer(640, 480, msaa=4) as r:
        frame = r.render(scene, camera)
        frame.color       # (H, W, 4) uint8, row 0 at the top
        frame.depth       # (H, W) float32, linear depth along the camera axis, 0 = no hit
        frame.object_ids  # (H, W) int32, -1 = background

Depth and ids are never blended: they come from a single-sample pass whatever ``msaa`` is.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry.camera import Camera
from ..gl import context as glcontext
from ..gl.resources import ResourceCache
from ..gl.targets import Targets
from ..scene.scene import Scene
from .forward import ForwardPass
from .shading import check_shading

OUTPUTS = ("color", "depth", "ids")


@dataclass
class Frame:
    """One render's results (see the module docstring); outputs not asked for are None."""

    color: np.ndarray | None
    depth: np.ndarray | None
    object_ids: np.ndarray | None
    camera: Camera

    def save(self, path):
        """Write the colour image (PNG; RGBA if the background is transparent)."""
        from ..image.writers import save_image

        if self.color is None:
            raise InputError("this frame has no colour output to save")
        return save_image(path, self.color)


class Renderer:
    """Headless renderer of ``width`` x ``height`` images with optional MSAA (0, 2, 4, 8).

    ``close()`` (or leaving a ``with`` block) releases the context and every GL object.
    """

    def __init__(self, width: int = 800, height: int = 600, msaa: int = 0, *,
                 shading: str = "phong"):
        self.shading = check_shading(shading)
        self.ctx = glcontext.create_headless()
        try:
            self.targets = Targets(self.ctx, width, height, msaa)
        except BaseException:
            self.ctx.release()
            raise
        self.width, self.height, self.msaa = width, height, msaa
        self.cache = ResourceCache(self.ctx)
        self.forward = ForwardPass(self.ctx, self.cache)
        self._closed = False

    @property
    def info(self) -> dict[str, object]:
        return glcontext.describe(self.ctx)

    def render(self, scene: Scene, camera: Camera | None = None, *, shading: str | None = None,
               outputs=OUTPUTS) -> Frame:
        """Render ``scene`` through ``camera`` (default: ``Camera.frame`` of the scene)."""
        if self._closed:
            raise InputError("this Renderer is closed")
        unknown = set(outputs) - set(OUTPUTS)
        if unknown:
            raise InputError(f"unknown outputs {sorted(unknown)}; choose from {OUTPUTS}")
        shading = check_shading(shading or self.shading)
        if camera is None:
            camera = Camera.frame(scene.bounds, aspect=self.width / self.height)
        # Several renderers (contexts) may live in one thread: make ours current.
        with self.ctx:
            return self._render(scene, camera, shading, outputs)

    def _render(self, scene: Scene, camera: Camera, shading: str, outputs) -> Frame:
        w, h, t = self.width, self.height, self.targets
        want_aux = "depth" in outputs or "ids" in outputs
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        bg = tuple(float(c) for c in scene.background)
        if self.msaa:
            if want_aux:  # exact, unblended depth and ids at pixel centres
                t.begin_full(bg)
                self.forward.draw(scene, camera, w, h, "unlit", aux=True)
            t.begin_multisample(bg)
            self.forward.draw(scene, camera, w, h, shading, aux=False)
            t.resolve()
        else:
            t.begin_full(bg) if want_aux else t.begin_color(bg)
            self.forward.draw(scene, camera, w, h, shading, aux=want_aux)
        frame = Frame(t.read_color() if "color" in outputs else None,
                      t.read_depth() if "depth" in outputs else None,
                      t.read_ids() if "ids" in outputs else None, camera)
        self.cache.sweep()
        return frame

    def close(self) -> None:
        """Release every GL object and the context. Safe to call twice."""
        if self._closed:
            return
        self._closed = True
        with self.ctx:
            self.forward.release()
            self.cache.release()
            self.targets.release()
        self.ctx.release()

    def gl_error(self) -> str:
        """The context's pending GL error ('GL_NO_ERROR' when all is well)."""
        with self.ctx:
            return self.ctx.error

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
