"""The viewer's actions: what the keys of ``facet.viewer_keys.KEYMAP`` do, plus grabbing
and saving pictures. A mixin of ``facet.viewer.Viewer`` (which owns the window, ``self.glfw``,
the context and the renderer)."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from .viewer_keys import TURNTABLE_FRAMES, help_text

BACKGROUNDS = ((1.0, 1.0, 1.0, 1.0), (0.35, 0.37, 0.4, 1.0), (0.0, 0.0, 0.0, 1.0))
SHADING_CYCLE = ("phong", "blinn", "gouraud", "flat", "unlit", "normals")
AA_CYCLE = ("msaa:4", "none", "ssaa:jittered:16", "ssaa:jittered:64")


class ViewerActions:
    def grab(self) -> np.ndarray:
        """The window's current picture, (H, W, 3) uint8, row 0 at the top."""
        w, h = self.glfw.get_framebuffer_size(self.window)
        with self.ctx:
            data = self.ctx.screen.read(viewport=(0, 0, w, h), components=3)
        return np.frombuffer(data, np.uint8).reshape(h, w, 3)[::-1].copy()

    def save(self, path=None, scale: int = 1) -> Path:
        """Save what the window shows as a PNG (``scale`` 2: an offscreen render at twice the
        size), with the camera as JSON beside it; returns the PNG's path."""
        from .image.outputs import write_camera_json
        from .image.writers import save_image

        path = Path(path or time.strftime(f"facet-%Y%m%d-%H%M%S{'-2x' if scale > 1 else ''}"
                                          ".png"))
        camera = self.camera()
        w, h = self.glfw.get_framebuffer_size(self.window)
        if scale == 1:
            if self._dirty:
                self.draw()
            image = self.grab()
        else:
            from .render.renderer import Renderer

            with Renderer(w * scale, h * scale, self.msaa, context=self.ctx) as big:
                image = big.render(self._prepare(camera), camera, shading=self.shading,
                                   outputs=("color",), aa=self.aa,
                                   shadows=self.shadows).color
        save_image(path, image)
        write_camera_json(path.with_suffix(".json"), camera.describe(w * scale, h * scale))
        print(path)
        return path

    # -- actions (KEYMAP) ----------------------------------------------------------------
    def frame(self):
        self.control.bounds = np.asarray(self.scene.bounds)
        self.control.frame(self.aspect)

    def reset(self):
        self.frame()
        self.shading, self.wireframe, self.background = "phong", False, None

    def toggle_projection(self):
        self.control.toggle_projection()

    def cycle_shading(self):
        self.shading = SHADING_CYCLE[(SHADING_CYCLE.index(self.shading) + 1) % 6]
        print(f"shading: {self.shading}")

    def toggle_wireframe(self):
        self.wireframe = not self.wireframe

    def cycle_aa(self):
        """Next anti-aliasing mode: MSAA in the renderer, or progressive supersampling."""
        self.aa = AA_CYCLE[(AA_CYCLE.index(self.aa) + 1) % len(AA_CYCLE)] \
            if self.aa in AA_CYCLE else AA_CYCLE[0]
        msaa = int(self.aa.split(":")[1]) if self.aa.startswith("msaa") else 0
        self.msaa = min(msaa, self.ctx.max_samples)
        self.renderer.set_msaa(self.msaa)
        self._samples = 0
        print(f"aa: {self.aa}")

    def toggle_shadows(self):
        self.shadows = not self.shadows

    def toggle_headlight(self):
        self.headlight = not self.headlight

    def cycle_background(self):
        options = (None, *BACKGROUNDS)
        self.background = options[(options.index(self.background) + 1) % len(options)]

    def screenshot(self):
        self.save()

    def screenshot_2x(self):
        self.save(scale=2)

    def record_turntable(self):
        from .image.sequence import BackgroundWriter, SequenceSink
        from .render.turntable import orbit_cameras

        path = Path(time.strftime("facet-turntable-%Y%m%d-%H%M%S.gif"))
        self.glfw.set_window_title(self.window, f"facet - recording {path.name}")
        writer = BackgroundWriter()
        sink = SequenceSink(path, 30.0, writer)
        camera = self.camera()
        for i, cam in enumerate(orbit_cameras(camera, self.control.target, TURNTABLE_FRAMES)):
            frame = self.renderer.render(self._prepare(cam), cam, shading=self.shading,
                                         outputs=("color",), aa=self.aa, shadows=self.shadows)
            sink.add(i, frame.color)
        sink.finish()
        self.request_frame()  # the supersampling targets were used by the recording
        writer.close()
        print(path)

    def print_help(self):
        print(help_text())

    def quit(self):
        self.glfw.set_window_should_close(self.window, True)

    def use_camera(self, index: int):
        cameras = list(self.scene.cameras.values())
        if index < len(cameras):
            self.set_camera(cameras[index])

