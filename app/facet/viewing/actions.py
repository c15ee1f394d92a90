"""The viewer's actions: what the keys of ``facet.viewing.keys.KEYMAP`` do, plus saving
pictures. A mixin of ``facet.viewing.core.ViewerCore`` (whose fronts own the surface, the
context and the renderer, and give ``grab``, ``draw`` and ``quit``). Keys that change how
the scene is drawn set render options in ``self.keys``, one layer over the scene's and the
command line's (facet.options.render), so screenshots and recorded turntables render with
exactly what the viewer shows."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ..render.capabilities import decided
from .keys import AA_CYCLE, TURNTABLE_FRAMES, help_text
from .playback import FRAME_STEP, SECOND_STEP

BACKGROUNDS = ((1.0, 1.0, 1.0, 1.0), (0.35, 0.37, 0.4, 1.0), (0.0, 0.0, 0.0, 1.0))
BACKGROUND_NAMES = ("the scene's", "white", "grey", "black")  # (None, *BACKGROUNDS)
# What r undoes: every key's change to how the scene is drawn but the engine (a tracer
# chosen with e stays chosen); and the camera (RESET_SAID says so).
RESET_KEYS = ("shading", "wireframe", "background", "shadows", "aa", "lights")
RESET_SAID = ("reset: the camera, shading, wireframe, background, shadows, anti-aliasing "
              "and lights as the view opened (the engine stays)")


def _next(options, current):
    return options[(options.index(current) + 1) % len(options)] if current in options \
        else options[0]


class ViewerActions:
    def save(self, path=None, scale: int = 1) -> Path:
        """Save what the viewer shows as a PNG (``scale`` 2: an offscreen render at twice the
        size), with the camera as JSON beside it; returns the PNG's path (default: a
        time-stamped name in the viewer's screenshots folder)."""
        from ..image.outputs import write_camera_json
        from ..image.writers import save_image

        path = Path(path) if path else self.screenshots / time.strftime(
            f"facet-%Y%m%d-%H%M%S{'-2x' if scale > 1 else ''}.png")
        camera = self.camera()
        w, h = self.surface_size
        if scale == 1:
            if self._dirty:
                self.draw()
            image = self.grab()
        else:
            opts = self.options(size=(w * scale, h * scale), outputs=("color",))
            image = self.renderer.render(self.shown_scene(), camera, opts).color
        # The camera first: once the PNG appears (what a watching script waits for), its
        # JSON is already there.
        write_camera_json(path.with_suffix(".json"), camera.describe(w * scale, h * scale))
        save_image(path, image)
        return path  # (said by the key's action, not by this library call)

    # -- actions (KEYMAP) ----------------------------------------------------------------
    def frame_model(self):
        """(Not ``frame``: a Session's ``frame()`` is its next picture, and the served page's
        and the widget's f key drew a picture instead of framing.)"""
        opts = self.options()
        self.control.bounds = np.asarray(self.scene.at(opts.time, opts.animation).bounds)
        self.control.frame(self.aspect)
        self.say("framed the model")

    def reset(self):
        """The view as it opened (RESET_SAID): the camera (the scene's own, else framed, in
        perspective) and every key's change but the engine's undone."""
        for key in RESET_KEYS:
            self.keys.pop(key, None)
        self.fixed_rig = None
        self._samples = 0
        self._set_scene(self.scene, frame=True)
        self.say(RESET_SAID)

    def toggle_projection(self):
        self.control.toggle_projection()
        self.say(f"projection: {'orthographic' if self.control.orthographic else 'perspective'}")

    def cycle_shading(self):
        from ..options.render import SHADING

        self.keys["shading"] = _next(SHADING, self.options().shading)
        self.say(f"shading: {self.keys['shading']}")

    def toggle_wireframe(self):
        self.keys["wireframe"] = not self.options().wireframe
        self.say(f"wireframe: {'on' if self.keys['wireframe'] else 'off'}")

    def cycle_aa(self):
        """Next anti-aliasing mode: MSAA, none, or progressive supersampling."""
        self.keys["aa"] = _next(AA_CYCLE, str(self.options().aa))
        self._samples = 0
        self.say(f"aa: {self.keys['aa']}")

    def toggle_shadows(self):
        self.keys["shadows"] = not decided(self.options()).shadows
        self.say(f"shadows: {'on' if self.keys['shadows'] else 'off'}")

    def cycle_engine(self):
        from ..options.render import ENGINES

        self.keys["engine"] = _next(ENGINES, self.options().engine)
        self._samples = 0
        self.say(f"engine: {self.keys['engine']}")

    def toggle_headlight(self):
        """Lights follow the camera, or stay in the world: a scene with its own lights
        switches to the default rig following the camera and back; a scene lit by the rig
        freezes it where the camera is now and back."""
        from ..scene.light import camera_rig

        if self.scene.lights:
            following = self.options().lights == "camera"
            self.keys["lights"] = "auto" if following else "camera"
            self.say(f"lights: {'the scene' if following else 'follow the camera'}")
        elif self.fixed_rig is None:
            self.fixed_rig = camera_rig(self.camera().view)
            self.say("lights: fixed in the scene")
        else:
            self.fixed_rig = None
            self.say("lights: follow the camera")

    def cycle_background(self):
        current = self.keys.get("background")
        options = (None, *BACKGROUNDS)
        self.keys["background"] = options[(options.index(current) + 1) % len(options)] \
            if current in options else None
        self.say(f"background: {BACKGROUND_NAMES[options.index(self.keys['background'])]}")

    def screenshot(self):
        self.say(str(self.save()))

    def screenshot_2x(self):
        self.say(str(self.save(scale=2)))

    def record_turntable(self):
        from ..image.sequence import BackgroundWriter, SequenceSink
        from ..render.turntable import turntable

        path = self.screenshots / time.strftime("facet-turntable-%Y%m%d-%H%M%S.gif")
        self.show_status(f"facet - recording {path.name}")
        writer = BackgroundWriter()
        sink = SequenceSink(path, 30.0, writer)
        frames = turntable(self.renderer, self.shown_scene(), TURNTABLE_FRAMES, self.camera(),
                           options=self.options(outputs=("color",)), center=self.control.target)
        try:
            for i, frame in enumerate(frames):
                sink.add(i, frame.color)
            sink.finish()
            writer.close()
        except BaseException:
            sink.abort()
            raise
        self.request_frame()
        self.say(str(path))

    def toggle_playing(self):
        self.say("playing" if self.playback.toggle() else
                 f"paused at {self.playback.time():.3f} s")

    def step_back(self):
        self._step(-FRAME_STEP)

    def step_forward(self):
        self._step(FRAME_STEP)

    def second_back(self):
        self._step(-SECOND_STEP)

    def second_forward(self):
        self._step(SECOND_STEP)

    def _step(self, seconds: float):
        self.say(f"paused at {self.playback.step(seconds):.3f} s")

    def print_help(self):
        self.say(help_text(self.front))

    def use_camera(self, index: int):
        cameras = list(self.scene.cameras.values())
        if index < len(cameras):
            self.set_camera(cameras[index])
