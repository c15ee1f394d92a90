"""``facet view``: an interactive glfw window over the same Renderer and shaders as headless.

Mouse: left drag orbits (arcball), right/middle or shift + left drag pans, the wheel zooms
towards the cursor. Keys come from ``KEYMAP`` (``h`` prints it). The window redraws only when
something changed, sleeping in ``glfw.wait_events_timeout`` otherwise, and reloads the open
file when its content changes on disk (keeping the camera). Errors while running go to the
title and stderr; the viewer keeps what it had.

Only this module (and facet.playground) imports glfw.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from .errors import FacetError
from .gl.glsl_source import file_digest
from .viewer_actions import ViewerActions
from .viewer_keys import KEYMAP

WATCH_INTERVAL = 0.25  # seconds between checks of the open file
DEBOUNCE = 0.15  # a change must stay put this long (editors save in two steps)
IDLE_WAIT = 0.5  # longest sleep between events when nothing happens


class NoDisplayError(FacetError):
    """There is no display to open a window on."""


def check_display() -> None:
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise NoDisplayError("no display to open a window on (DISPLAY is not set); "
                             "use 'facet render' for headless images")


def load_source(path) -> object:
    """A Scene from a mesh or scene file."""
    from .scene.mesh import Mesh
    from .scene.scene import Scene
    from .scene.scenefile import load_scene

    path = Path(path)
    if path.suffix.lower() == ".toml":
        return load_scene(path)
    scene = Scene()
    scene.add(Mesh.load(path))
    return scene



class Viewer(ViewerActions):
    """A window showing a scene. ``run()`` blocks until it closes; between runs (or before
    one) a script can ``set_camera``, ``request_frame`` and ``save``."""

    def __init__(self, source, size=(1280, 720), msaa: int = 4, title: str = "facet",
                 shader=None):
        import glfw

        check_display()
        if not glfw.init():
            raise NoDisplayError("cannot open the display "
                                 f"{os.environ.get('DISPLAY', '')!r}; "
                                 "use 'facet render' for headless images")
        self.glfw = glfw
        self.path = None if not isinstance(source, (str, Path)) else Path(source)
        self.user_shader = shader  # --frag: the model's own shader (a UserShader)
        scene = self._load(source) if self.path else source
        glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
        glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
        glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
        glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
        glfw.window_hint(glfw.SCALE_TO_MONITOR, True)
        self.window = glfw.create_window(int(size[0]), int(size[1]), title, None, None)
        if not self.window:
            glfw.terminate()
            raise NoDisplayError("the display gave no OpenGL 3.3 window; "
                                 "use 'facet render' for headless images")
        glfw.make_context_current(self.window)
        glfw.swap_interval(1)
        from .gl.context import create_for_current_window
        from .render.renderer import Renderer

        self.ctx = create_for_current_window()
        fb_w, fb_h = glfw.get_framebuffer_size(self.window)
        self.msaa = min(msaa, self.ctx.max_samples)
        self.aa = f"msaa:{self.msaa}" if self.msaa else "none"
        self._samples = 0  # supersamples accumulated for the current view
        self.renderer = Renderer(fb_w, fb_h, self.msaa, context=self.ctx)
        self.shading, self.wireframe, self.background = "phong", False, None
        self.shadows = False
        self.headlight = not scene.lights
        self.error = ""
        self._set_scene(scene, frame=True)
        self._dirty, self._frames, self._fps, self._fps_time = True, 0, 0.0, time.perf_counter()
        self._start = time.perf_counter()
        self._shader_change = None  # when a user shader's files were first seen changed
        self._drag = None
        self._cursor = self.glfw.get_cursor_pos(self.window)
        self._watch = (self.path, file_digest(self.path) if self.path else None, 0.0, None)
        self._install_callbacks()

    # -- scene and camera ----------------------------------------------------------------
    def _load(self, path):
        scene = load_source(path)
        if self.user_shader is not None:
            for obj in scene.objects:
                obj.material = replace(obj.material, shader=self.user_shader)
        return scene

    def _refine_aa(self) -> str | None:
        """The supersampling a still view converges to: the chosen ssaa mode, or, where the
        scene has depth of field, motion blur, area-light shadows or glossy reflection,
        the accumulation ``render`` would use for them (None: one picture is final)."""
        from .render.antialias import DISTRIBUTED_AA, needs_accumulation

        if self.wireframe:
            return None
        if self.aa.startswith("ssaa"):
            return self.aa
        return DISTRIBUTED_AA if needs_accumulation(self.scene, self.camera(),
                                                    self.shadows) else None

    @property
    def refining(self) -> bool:
        """Progressive supersampling still has samples to add."""
        aa = self._refine_aa()
        return aa is not None and self._samples < int(aa.rsplit(":", 1)[1])

    @property
    def animated(self) -> bool:
        """User shaders may use u_time: keep drawing while they are shown."""
        return any(o.material.shader is not None for o in self.scene.objects)

    def _set_scene(self, scene, frame: bool) -> None:
        from .geometry.orbit import OrbitControl

        self.scene = scene
        self.own_lights = list(scene.lights)
        self.base_background = tuple(scene.background)
        if frame or not hasattr(self, "control"):
            self.control = OrbitControl(scene.bounds, aspect=self.aspect)
            if scene.cameras:
                self.control.set_camera(scene.camera())
        else:
            self.control.bounds = np.asarray(scene.bounds)
        self.triangles = sum(o.mesh.face_count for o in scene.objects)
        self.request_frame()

    @property
    def aspect(self) -> float:
        w, h = self.glfw.get_framebuffer_size(self.window)
        return w / max(h, 1)

    def camera(self):
        """The camera the window shows now."""
        return self.control.camera(self.aspect)

    def set_camera(self, camera) -> None:
        self.control.set_camera(camera)
        self.request_frame()

    def request_frame(self) -> None:
        self._dirty = True

    # -- drawing -------------------------------------------------------------------------
    def _prepare(self, camera):
        from .scene.light import camera_rig

        scene = self.scene
        scene.lights = camera_rig(camera.view) if self.headlight else list(self.own_lights)
        scene.background = np.asarray(self.background or self.base_background)
        return scene

    def draw(self) -> None:
        """Draw one frame into the window and show it."""
        fb = self.glfw.get_framebuffer_size(self.window)
        if fb[0] < 1 or fb[1] < 1:
            return  # minimised
        self.renderer.resize(*fb)
        camera = self.camera()
        elapsed = time.perf_counter() - self._start
        with self.ctx:
            aa = self._refine_aa()
            moving = self._dirty or self.animated
            if aa is not None and (aa == self.aa or not moving):
                # One more sample per frame while nothing changes; a change starts over
                # with one sample (or, for the effects of _refine_aa, one plain picture),
                # so moving stays fast.
                index = 0 if moving else self._samples
                self._samples = self.renderer.present_progressive(
                    self._prepare(camera), camera, self.ctx.screen, aa, index,
                    shading=self.shading, time=elapsed, shadows=self.shadows)
            else:
                self.renderer.present(self._prepare(camera), camera, self.ctx.screen,
                                      shading=self.shading, wireframe=self.wireframe,
                                      time=elapsed, shadows=self.shadows)
                self._samples = 0
            if self.error:  # the picture is stale: say so in the window, not only the title
                from .playground import draw_error_frame

                draw_error_frame(self.ctx.screen, fb)
        self.glfw.swap_buffers(self.window)
        self._dirty = False
        self._frames += 1
        now = time.perf_counter()
        if now - self._fps_time >= 0.5:
            self._fps, self._frames, self._fps_time = self._frames / (now - self._fps_time), \
                0, now
        self._update_title()

    def _update_title(self) -> None:
        name = self.path.name if self.path else "scene"
        title = f"facet - {name} - {self.triangles:,} triangles - {self._fps:.0f} fps"
        self.glfw.set_window_title(self.window, f"{title} - error: {self.error}" if self.error
                                   else title)

    # -- events --------------------------------------------------------------------------
    def _install_callbacks(self) -> None:
        glfw = self.glfw
        glfw.set_char_callback(self.window, self._on_char)
        glfw.set_key_callback(self.window, self._on_key)
        glfw.set_mouse_button_callback(self.window, self._on_button)
        glfw.set_cursor_pos_callback(self.window, self._on_cursor)
        glfw.set_scroll_callback(self.window, self._on_scroll)
        glfw.set_framebuffer_size_callback(self.window, lambda *_: self.request_frame())
        glfw.set_window_refresh_callback(self.window, lambda *_: self.request_frame())
        glfw.set_drop_callback(self.window, self._on_drop)

    def _run_action(self, method: str, *args) -> None:
        try:
            getattr(self, method)(*args)
            self.error = ""
        except FacetError as exc:
            self._report(str(exc))
        self.request_frame()

    def _on_char(self, _window, codepoint: int) -> None:
        char = chr(codepoint)
        if char.isdigit() and char != "0":
            self._run_action("use_camera", int(char) - 1)
        elif char in KEYMAP:
            self._run_action(KEYMAP[char].method)

    def _on_key(self, _window, key, _scancode, action, _mods) -> None:
        if key == self.glfw.KEY_ESCAPE and action == self.glfw.PRESS:
            self.quit()

    def _on_button(self, _window, button, action, mods) -> None:
        glfw = self.glfw
        if action == glfw.PRESS:
            # The position of the last cursor event, not glfw.get_cursor_pos(): queued
            # events are handled after the pointer may have moved on.
            x, y = self._cursor
            pan = button in (glfw.MOUSE_BUTTON_RIGHT, glfw.MOUSE_BUTTON_MIDDLE) or (
                mods & glfw.MOD_SHIFT)
            self._drag = ("pan" if pan else "orbit", (x, y))
        elif action == glfw.RELEASE:
            self._drag = None

    def _on_cursor(self, _window, x: float, y: float) -> None:
        self._cursor = (x, y)
        if self._drag is None:
            return
        kind, (x0, y0) = self._drag
        w, h = self.glfw.get_window_size(self.window)
        if kind == "orbit":
            self.control.orbit((x0, y0), (x, y), w, h)
        else:
            self.control.pan(x - x0, y - y0, w, h)
        self._drag = (kind, (x, y))
        self.request_frame()

    def _on_scroll(self, _window, _dx: float, dy: float) -> None:
        x, y = self._cursor
        w, h = self.glfw.get_window_size(self.window)
        self.control.zoom(dy, x, y, w, h)
        self.request_frame()

    def _on_drop(self, _window, paths) -> None:
        if paths:
            self.open(paths[0])

    def open(self, path) -> None:
        """Show another mesh or scene file (framed anew)."""
        try:
            scene = self._load(path)
        except FacetError as exc:
            self._report(str(exc))
            return
        self.path = Path(path)
        self.headlight = not scene.lights
        self._set_scene(scene, frame=True)
        self._watch = (self.path, file_digest(self.path), 0.0, None)
        self.error = ""

    def _report(self, message: str) -> None:
        self.error = message.splitlines()[0]
        print(f"facet view: error: {message}", file=sys.stderr)
        self._update_title()

    def _check_shaders(self) -> None:
        """Reload user shaders whose files changed and then stayed put (debounced); a failure
        keeps the last good program."""
        user = self.renderer.forward.user
        if not user.changed():
            self._shader_change = None
            return
        now = time.monotonic()
        if self._shader_change is None:
            self._shader_change = now
        if now - self._shader_change < DEBOUNCE:
            return
        self._shader_change = None
        with self.ctx:
            result = user.reload()
        if not result.changed:
            return
        if result.success:
            self.error = ""
            print("shaders reloaded", file=sys.stderr)
        else:
            self._report(result.errors)
        self.request_frame()

    def _check_file(self) -> None:
        """Reload the open file when its content changed and then stayed put (debounced)."""
        path, digest, last_check, pending = self._watch
        now = time.monotonic()
        if now - last_check < WATCH_INTERVAL:
            return
        self._check_shaders()
        if path is None:
            self._watch = (path, digest, now, pending)
            return
        current = file_digest(path)
        if current is None or current == digest:
            self._watch = (path, digest, now, None)
            return
        if pending != current:  # changed: wait until it stops changing
            self._watch = (path, digest, now, current)
            return
        self._watch = (path, current, now, None)
        try:
            scene = self._load(path)
        except FacetError as exc:
            self._report(str(exc))
            return
        self.headlight = self.headlight if not scene.lights else False
        self._set_scene(scene, frame=False)
        self.error = ""
        print(f"reloaded {path}")

    def run(self) -> None:
        """Show the window until it is closed (q, Esc or the window's close button)."""
        glfw = self.glfw
        while not glfw.window_should_close(self.window):
            if self._dirty or self.animated or self.refining:
                self.draw()
            if self.animated or self.refining:
                glfw.poll_events()
            else:
                glfw.wait_events_timeout(DEBOUNCE if self._watch[3] else
                                         min(IDLE_WAIT, WATCH_INTERVAL))
            self._check_file()

    def close(self) -> None:
        if self.window is None:
            return
        self.renderer.close()
        self.ctx.release()
        self.glfw.destroy_window(self.window)
        self.glfw.terminate()
        self.window = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def view(scene, size=(1280, 720), msaa: int = 4, shader=None) -> None:
    """Open a window on ``scene`` (a Scene or a file path) and block until it closes;
    ``shader`` (a UserShader) replaces the file's materials' shaders."""
    with Viewer(scene, size, msaa, shader=shader) as v:
        v.run()
