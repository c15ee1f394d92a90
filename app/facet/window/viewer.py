"""``facet view``: an interactive window drawing through the same Renderer and pass sequence
as headless rendering (facet.render.renderer: ``present`` is ``render``'s window destination).

Mouse: left drag orbits (arcball), right/middle or shift + left drag pans, the wheel zooms
towards the cursor. Keys come from ``facet.viewing.keys.KEYMAP`` (``h`` prints it); what they
change is one more layer of render options over the scene file's and the command line's, so
the window shows what ``facet render`` would. The window redraws only when something
changed, sleeping otherwise; with supersampling or a distributed effect (depth of field,
motion blur, area-light shadows, gloss) a still view refines one sample per frame up to the
headless picture. The open file is reloaded when its content changes on disk (keeping the
camera). Errors while running go to the title and stderr; the viewer keeps what it had.
The viewer's state and controls are facet.viewing.core's, shared with the notebook widget
and the served page; this module adds the glfw window and its events.
"""

from __future__ import annotations

import time
from typing import Annotated

import numpy as np

from ..boundary import Count, Crease, FilePath, Number, Size, checked
from ..viewing.core import FRONT, Source, ViewerCore, explicit_layer  # noqa: F401 (FRONT)
from .base import DEBOUNCE, POLL, GLWindow

IDLE_WAIT = 0.5  # longest sleep between events when nothing happens


class Viewer(ViewerCore):
    """A window showing a scene, drawn as ``facet render`` draws it.

    ``run()`` blocks until it closes; between runs (or before one) a script can
    ``set_camera``, ``request_frame``, ``save``. The keys and the mouse are the viewer's
    (``h`` prints them); ``close()`` (or ``with``) releases the window and its GL.

    Parameters
    ----------
    source : Scene or str or Path
        A scene, or a mesh or scene file (reloaded when it changes on disk).
    size : (int, int), optional
        The window's size (default: the options', the scene's, else 1280x720).
    msaa : int, optional
        Multisample anti-aliasing samples.
    title : str
        The window's title (until the first frame shows the status).
    shader : UserShader, optional
        Replaces the file's materials' shaders.
    options : mapping, optional
        Raw render options over the scene's (e.g. the command line's).
    crease : float, optional
        Where a file has no normals, split them at edges sharper than this (degrees).
    time_end : float, optional
        The animations loop from the options' time to this (default: their length).
    sizes : dict, optional
        Point and line sizes over the file's (``point_size``, ``point_radius``,
        ``line_width``).
    screenshots : str or Path, optional
        The folder the ``s``, ``S`` and ``t`` keys write into (default: the working
        directory).

    Raises
    ------
    facet.window.base.NoDisplayError
        When there is no display to open a window on.
    """

    def __init__(self, source, size=None, msaa: int | None = None, title: str = "facet",
                 shader=None, options=None, crease: float | None = None,
                 time_end: float | None = None, sizes: dict | None = None, screenshots=None):
        super().__init__(source, size, msaa, shader=shader, options=options, crease=crease,
                         time_end=time_end, sizes=sizes, screenshots=screenshots)
        self.win = GLWindow(self.initial_size, title)
        self.glfw, self.window, self.ctx = self.win.glfw, self.win.handle, self.win.ctx
        from ..render.renderer import Renderer

        self.start(Renderer(context=self.ctx))
        self._frames, self._fps, self._fps_time = 0, 0.0, time.perf_counter()
        self._cursor = self.glfw.get_cursor_pos(self.window)
        self._install_callbacks()

    # -- what ViewerCore asks of a front ---------------------------------------------------
    @property
    def surface_size(self) -> tuple[int, int]:
        return tuple(self.glfw.get_framebuffer_size(self.window))

    @property
    def pointer_size(self) -> tuple[float, float]:
        return self.win.size

    def show_status(self, text: str) -> None:
        """Show a one-line status in the title.

        Parameters
        ----------
        text : str
            The line.
        """
        self.win.set_title(text)

    def grab(self) -> np.ndarray:
        """The window's current picture.

        Returns
        -------
        (H, W, 3) uint8 ndarray
            Row 0 at the top.
        """
        w, h = self.surface_size
        with self.renderer.current():
            data = self.ctx.screen.read(viewport=(0, 0, w, h), components=3)
        return np.frombuffer(data, np.uint8).reshape(h, w, 3)[::-1].copy()

    def quit(self) -> None:
        """Close the window at the next turn of ``run``'s loop."""
        self.win.quit()

    # -- drawing -------------------------------------------------------------------------
    def draw(self) -> None:
        """Draw one frame into the window and show it."""
        fb = self.surface_size
        if fb[0] < 1 or fb[1] < 1:
            return  # minimised
        with self.renderer.current():
            self.draw_into(self.ctx.screen)
            if self.error:  # the picture is stale: say so in the window, not only the title
                self.win.draw_error_frame()
        self.win.swap()
        self._frames += 1
        now = time.perf_counter()
        if now - self._fps_time >= 0.5:
            self._fps, self._frames, self._fps_time = self._frames / (now - self._fps_time), \
                0, now
        self.show_status(self.status(self._fps))

    # -- events --------------------------------------------------------------------------
    def _install_callbacks(self) -> None:
        glfw, w = self.glfw, self.window
        glfw.set_char_callback(w, lambda _w, codepoint: self.char(chr(codepoint)))
        glfw.set_key_callback(w, self._on_key)
        glfw.set_mouse_button_callback(w, self._on_button)
        glfw.set_cursor_pos_callback(w, lambda _w, x, y: self.move(x, y))
        glfw.set_scroll_callback(w, lambda _w, _dx, dy: self.scroll(dy))
        glfw.set_framebuffer_size_callback(w, lambda *_: self.request_frame())
        glfw.set_window_refresh_callback(w, lambda *_: self.request_frame())
        glfw.set_drop_callback(w, self._on_drop)

    def _on_key(self, _window, key, _scancode, action, _mods) -> None:
        if key == self.glfw.KEY_ESCAPE and action == self.glfw.PRESS:
            self.quit()

    def _on_button(self, _window, button, action, mods) -> None:
        glfw = self.glfw
        if action == glfw.PRESS:
            # The position of the last cursor event, not glfw.get_cursor_pos(): queued
            # events are handled after the pointer may have moved on.
            pan = button in (glfw.MOUSE_BUTTON_RIGHT, glfw.MOUSE_BUTTON_MIDDLE) or bool(
                mods & glfw.MOD_SHIFT)
            self.press(*self._cursor, pan)
        elif action == glfw.RELEASE:
            self.release()

    def _on_drop(self, _window, paths) -> None:
        if paths:
            self.open(paths[0])

    def run(self) -> None:
        """Show the window until it is closed (q, Esc or the window's close button)."""
        glfw = self.glfw
        while not self.win.should_close():
            if self.wants_frame:
                self.draw()
            if self.animated or self.refining:
                glfw.poll_events()
            else:
                glfw.wait_events_timeout(DEBOUNCE if self._file_watch.pending else
                                         min(IDLE_WAIT, POLL))
            with self.renderer.current():  # (a reloaded shader is compiled in it)
                self.check_files()

    def close(self) -> None:
        if self.win.handle is None:
            return
        self.renderer.close()
        self.win.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


@checked
def view(scene: Source, size: Size | None = None,
         msaa: Annotated[int | None, Count(0, 64)] = None, shader=None, options=None,
         crease: Crease = None, time_end: Annotated[float | None, Number()] = None,
         sizes: dict | None = None, screenshots: FilePath | None = None) -> None:
    """Open a window on a scene and block until it closes (``facet view``).

    Parameters
    ----------
    scene : Scene or str or Path
        A scene, or a mesh or scene file.
    size : (int, int), optional
        The window's size.
    msaa : int, optional
        Multisample anti-aliasing samples.
    shader : UserShader, optional
        Replaces the file's materials' shaders.
    options : mapping, optional
        Raw render options over the scene's (e.g. the command line's).
    crease : float, optional
        Where a file has no normals, split them at edges sharper than this (degrees).
    time_end : float, optional
        The animations loop from the options' time to this (default: their length).
    sizes : dict, optional
        Point and line sizes over the file's (``point_size``, ``point_radius``,
        ``line_width``).
    screenshots : str or Path, optional
        The folder the ``s``, ``S`` and ``t`` keys write into (default: the working
        directory).
    """
    with Viewer(scene, size, msaa, shader=shader, options=options, crease=crease,
                time_end=time_end, sizes=sizes, screenshots=screenshots) as v:
        v.run()
