"""``facet view``: an interactive window drawing through the same Renderer and pass sequence
as headless rendering (facet.render.renderer: ``present`` is ``render``'s window destination).

Mouse: left drag orbits (arcball), right/middle or shift + left drag pans, the wheel zooms
towards the cursor. Keys come from ``facet.window.keys.KEYMAP`` (``h`` prints it); what they
change is one more layer of render options over the scene file's and the command line's, so
the window shows what ``facet render`` would. The window redraws only when something
changed, sleeping otherwise; with supersampling or a distributed effect (depth of field,
motion blur, area-light shadows, gloss) a still view refines one sample per frame up to the
headless picture. The open file is reloaded when its content changes on disk (keeping the
camera). Errors while running go to the title and stderr; the viewer keeps what it had.
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace
from pathlib import Path

from ..errors import FacetError
from ..gl.glsl_source import file_digest
from ..scene.options import options_for, parse_layer
from ..scene.pbr import as_phong
from .actions import ViewerActions
from .base import DEBOUNCE, POLL, Debounce, GLWindow
from .keys import KEYMAP

IDLE_WAIT = 0.5  # longest sleep between events when nothing happens
FRONT = "view"  # the viewer's defaults (facet.scene.options.FRONT_DEFAULTS)


def explicit_layer(options=None, size=None, msaa=None):
    """The viewer's explicit layer: raw ``options`` (e.g. the command line's), with
    ``size`` and ``msaa`` when given, parsed once."""
    given = {"size": size, "msaa": msaa}
    return parse_layer({**(options or {}), **{k: v for k, v in given.items() if v is not None}})


class Viewer(ViewerActions):
    """A window showing a scene (or a mesh or scene file). ``run()`` blocks until it closes;
    between runs (or before one) a script can ``set_camera``, ``request_frame``, ``save``.
    ``options``: raw render options over the scene's (e.g. the command line's); ``size``
    and ``msaa``, when given, join them. The window opens at the options' size (the
    scene's, else the viewer's default, facet.scene.options.FRONT_DEFAULTS)."""

    def __init__(self, source, size=None, msaa: int | None = None, title: str = "facet",
                 shader=None, options=None, crease: float | None = None,
                 time_end: float | None = None, sizes: dict | None = None):
        self.path = Path(source) if isinstance(source, (str, Path)) else None
        self.crease = crease  # how files without normals are read (facet.scene.loading)
        self.user_shader = shader  # --frag: the model's own shader (a UserShader)
        self.sizes = sizes or {}  # --point-size, --point-radius, --line-width
        self.explicit = explicit_layer(options, size, msaa)
        scene = self._load(self.path) if self.path else source
        self.win = GLWindow(options_for(scene, self.explicit, front=FRONT).size, title)
        self.glfw, self.window, self.ctx = self.win.glfw, self.win.handle, self.win.ctx
        from ..render.renderer import Renderer

        self.renderer = Renderer(context=self.ctx)
        self.keys: dict = {}  # render options the keys changed (facet.window.actions)
        self.fixed_rig = None  # the default lights frozen in the world (key l)
        self.error = ""
        self._samples = 0  # supersamples accumulated for the current view
        self._sample_count = 0  # supersamples the current view refines to (0: none)
        self._set_scene(scene, frame=True)
        self._dirty, self._frames, self._fps, self._fps_time = True, 0, 0.0, time.perf_counter()
        self.time_end = time_end  # --time A:B: loop A..B (else the animations' length)
        self._set_playback()
        self._drag = None
        self._cursor = self.glfw.get_cursor_pos(self.window)
        self._file_digest = file_digest(self.path) if self.path else None
        self._file_watch, self._shader_watch = Debounce(), Debounce()
        self._install_callbacks()

    # -- scene, options and camera ---------------------------------------------------------
    def _load(self, path):
        from ..scene.source import open_scene

        scene = open_scene(path, crease=self.crease)
        if self.sizes:
            from ..scene.points import resize_scene

            resize_scene(scene, self.sizes)
        if self.user_shader is not None:
            for obj in scene.objects:
                obj.material = replace(as_phong(obj.material), shader=self.user_shader)
        return scene

    def options(self, **changes):
        """The render options of the picture now: the scene's < the command line's < the
        keys' < ``changes``, at the window's size and the clock's time."""
        size = self.glfw.get_framebuffer_size(self.window)
        now = {"size": size, "time": self.playback.time()}
        return self.renderer.options(self.scene, options_for(
            self.scene, self.explicit, self.keys, {**now, **changes}, front=FRONT))

    def shown_scene(self):
        """The scene as drawn: with the default lights frozen in place if ``l`` did that."""
        return self.scene if self.fixed_rig is None else self.scene.view(lights=self.fixed_rig)

    @property
    def aa(self) -> str:
        return str(self.options().aa)

    @property
    def refining(self) -> bool:
        """Progressive supersampling still has samples to add."""
        return self._samples < self.renderer.samples(self.shown_scene(), self.camera(),
                                                     self.options())

    @property
    def animated(self) -> bool:
        """The animations play, or a user's shader on the scene reads u_time: keep drawing
        while it is shown (its programs are made at the first draw, which every new scene
        gets)."""
        if not self.playback.playing:
            return False
        return bool(self.scene.animations) or (
            any(o.material.shader is not None for o in self.scene.objects)
            and self.renderer.forward.user.reads_time())

    def _set_playback(self) -> None:
        """The clock of a newly opened scene: from the options' time, looping over --time
        A:B or else the length of the animations that play."""
        from .playback import Playback

        opts = options_for(self.scene, self.explicit, front=FRONT)
        end = self.time_end
        if end is None and self.scene.animated:
            end = max(a.rig.duration(opts.animation if a.rig.has(opts.animation) else None)
                      for a in self.scene.animated)
        self.playback = Playback(opts.time, end if end and end > opts.time else None)

    def _set_scene(self, scene, frame: bool) -> None:
        from ..geometry.orbit import OrbitControl

        self.scene = scene
        opts = options_for(scene, self.explicit, front=FRONT)
        if frame or not hasattr(self, "control"):
            self.control = OrbitControl(scene.at(opts.time, opts.animation).bounds, up=opts.up,
                                        aspect=self.aspect)
            camera = scene.camera(opts.camera)
            if camera is not None:
                self.control.set_camera(camera)
        else:
            import numpy as np

            self.control.bounds = np.asarray(scene.at(opts.time, opts.animation).bounds)
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
    def draw(self) -> None:
        """Draw one frame into the window and show it."""
        fb = self.glfw.get_framebuffer_size(self.window)
        if fb[0] < 1 or fb[1] < 1:
            return  # minimised
        camera, scene = self.camera(), self.shown_scene()
        opts = self.options()
        moving = self._dirty or self.animated
        with self.ctx:
            n = self._sample_count = self.renderer.samples(scene, camera, opts)
            if n and (opts.aa.supersampled or not moving):
                # One more sample per frame while nothing changes; a change starts over
                # with one sample (or, for the distributed effects, one plain picture), so
                # moving stays fast.
                self._samples = self.renderer.present(
                    scene, camera, self.ctx.screen, opts, sample=0 if moving else self._samples)
            else:
                self.renderer.present(scene, camera, self.ctx.screen, opts)
                self._samples = 0
            if self.error:  # the picture is stale: say so in the window, not only the title
                self.win.draw_error_frame()
        self.win.swap()
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
        engine = self.keys.get("engine") or "raster"
        if engine != "raster":
            title += f" - engine {engine}"
        if self.scene.animations:
            title += f" - {self.playback.time():.2f} s" + (
                "" if self.playback.playing else " (paused: p plays)")
        if self._sample_count:  # progressive supersampling: how far it has refined
            title += f" - {self._samples}/{self._sample_count} samples"
        self.win.set_title(f"{title} - error: {self.error}" if self.error else title)

    # -- events --------------------------------------------------------------------------
    def _install_callbacks(self) -> None:
        glfw, w = self.glfw, self.window
        glfw.set_char_callback(w, self._on_char)
        glfw.set_key_callback(w, self._on_key)
        glfw.set_mouse_button_callback(w, self._on_button)
        glfw.set_cursor_pos_callback(w, self._on_cursor)
        glfw.set_scroll_callback(w, self._on_scroll)
        glfw.set_framebuffer_size_callback(w, lambda *_: self.request_frame())
        glfw.set_window_refresh_callback(w, lambda *_: self.request_frame())
        glfw.set_drop_callback(w, self._on_drop)

    def _run_action(self, method: str, *args) -> None:
        try:
            getattr(self, method)(*args)
            self.error = ""
        except FacetError as exc:
            self._report(str(exc))
        self.request_frame()

    def _on_char(self, _window, codepoint: int) -> None:
        char = chr(codepoint)
        if char in "123456789":
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
        w, h = self.win.size
        if kind == "orbit":
            self.control.orbit((x0, y0), (x, y), w, h)
        else:
            self.control.pan(x - x0, y - y0, w, h)
        self._drag = (kind, (x, y))
        self.request_frame()

    def _on_scroll(self, _window, _dx: float, dy: float) -> None:
        x, y = self._cursor
        w, h = self.win.size
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
        self.fixed_rig = None
        self._set_scene(scene, frame=True)
        self._set_playback()
        self._file_digest = file_digest(self.path)
        self.error = ""

    def _report(self, message: str) -> None:
        self.error = message.splitlines()[0]
        print(f"facet view: error: {message}", file=sys.stderr)
        self._update_title()

    def _check_shaders(self) -> None:
        """Reload user shaders whose files changed and then stayed put; a failure keeps the
        last good program."""
        user = self.renderer.forward.user
        if not self._shader_watch.due(user.changed):
            return
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
        """Reload the open file when its content changed and then stayed put."""
        self._check_shaders()
        if self.path is None:
            return

        def changed():
            digest = file_digest(self.path)
            return digest if digest not in (None, self._file_digest) else None

        if not self._file_watch.due(changed):
            return
        self._file_digest = file_digest(self.path)
        try:
            scene = self._load(self.path)
        except FacetError as exc:
            self._report(str(exc))
            return
        self._set_scene(scene, frame=False)
        self.error = ""
        print(f"reloaded {self.path}")

    def run(self) -> None:
        """Show the window until it is closed (q, Esc or the window's close button)."""
        glfw = self.glfw
        while not self.win.should_close():
            if self._dirty or self.animated or self.refining:
                self.draw()
            if self.animated or self.refining:
                glfw.poll_events()
            else:
                glfw.wait_events_timeout(DEBOUNCE if self._file_watch.pending else
                                         min(IDLE_WAIT, POLL))
            self._check_file()

    def close(self) -> None:
        if self.win.handle is None:
            return
        self.renderer.close()
        self.win.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def view(scene, size=None, msaa: int | None = None, shader=None, options=None,
         crease: float | None = None, time_end: float | None = None,
         sizes: dict | None = None) -> None:
    """Open a window on ``scene`` (a Scene or a file path) and block until it closes;
    ``shader`` (a UserShader) replaces the file's materials' shaders; ``options`` are
    render options over the scene's; ``crease`` splits normals of files without them;
    ``time_end``: the animations loop from the options' time to it; ``sizes``: point and
    line sizes over the file's (facet.cli.args.sprite_sizes)."""
    with Viewer(scene, size, msaa, shader=shader, options=options, crease=crease,
                time_end=time_end, sizes=sizes) as v:
        v.run()
