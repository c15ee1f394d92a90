"""The live shader window (``facet shader FILE`` without -o): Shadertoy-style, hot reloaded.

Every file of the program (includes and the common file too) is watched by content hash;
a change is reloaded once it has stayed put for ``DEBOUNCE`` seconds (editors save in two
steps). A shader that fails to compile does not stop anything: the last good program keeps
drawing inside a red frame, the error goes to the window title and to stderr as
``path:line:col: error: message``; fixing the file brings the picture back. Uniforms and
textures survive a reload and iTime keeps running. Mouse: Shadertoy's iMouse (xy while a
button is held, origin bottom-left; z/w the click, negative once released). Keys: q / Esc
quit, space pauses, r restarts time and buffers.
"""

from __future__ import annotations

import sys
import time

from .errors import FacetError
from .viewer import NoDisplayError, check_display

DEBOUNCE = 0.15
POLL = 0.1  # seconds between checks of the watched files
ERROR_FRAME = (0.85, 0.1, 0.1, 1.0)  # the red frame drawn around a stale picture
ERROR_BORDER = 8  # pixels


def draw_error_frame(screen, size) -> None:
    """A clearly visible red frame around the last good picture (the file has an error)."""
    w, h, b = size[0], size[1], ERROR_BORDER
    for rect in ((0, 0, w, b), (0, h - b, w, b), (0, 0, b, h), (w - b, 0, b, h)):
        screen.scissor = rect
        screen.clear(*ERROR_FRAME)
    screen.scissor = None


class Playground:
    def __init__(self, args, size=(800, 450)):
        import glfw

        from .gl.context import create_for_current_window
        from .shader_command import build

        check_display()
        if not glfw.init():
            raise NoDisplayError("cannot open the display; render frames with -o instead")
        self.glfw = glfw
        glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
        glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
        glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
        glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
        self.window = glfw.create_window(*size, f"facet shader - {args.shader}", None, None)
        if not self.window:
            glfw.terminate()
            raise NoDisplayError("the display gave no OpenGL 3.3 window")
        glfw.make_context_current(self.window)
        glfw.swap_interval(1)
        self.ctx = create_for_current_window()
        self.name = str(args.shader)
        self.toy = build(args, glfw.get_framebuffer_size(self.window), context=self.ctx)
        self.error, self.paused, self.fps = "", False, args.fps
        self.start, self.last = time.perf_counter(), time.perf_counter()
        self.mouse = [0.0, 0.0, 0.0, 0.0]
        self._pending, self._pending_since, self._last_poll = False, 0.0, 0.0
        glfw.set_key_callback(self.window, self._on_key)
        glfw.set_mouse_button_callback(self.window, self._on_button)
        glfw.set_cursor_pos_callback(self.window, self._on_cursor)

    def _on_key(self, _w, key, _s, action, _m):
        glfw = self.glfw
        if action != glfw.PRESS:
            return
        if key in (glfw.KEY_ESCAPE, glfw.KEY_Q):
            glfw.set_window_should_close(self.window, True)
        elif key == glfw.KEY_SPACE:
            self.paused = not self.paused
        elif key == glfw.KEY_R:
            self.toy.restart()
            self.start = time.perf_counter()

    def _pixel(self, x, y):
        """Window cursor -> framebuffer pixels, origin bottom-left (Shadertoy's iMouse)."""
        w, h = self.glfw.get_window_size(self.window)
        fw, fh = self.glfw.get_framebuffer_size(self.window)
        return x * fw / max(w, 1), (h - y) * fh / max(h, 1)

    def _on_button(self, _w, button, action, _m):
        x, y = self._pixel(*self.glfw.get_cursor_pos(self.window))
        if action == self.glfw.PRESS:
            self.mouse = [x, y, x, y]  # z, w > 0: pressed, and w > 0 this frame: clicked
        elif action == self.glfw.RELEASE:
            self.mouse[2] = -abs(self.mouse[2])

    def _on_cursor(self, _w, x, y):
        if self.mouse[2] > 0:
            self.mouse[0], self.mouse[1] = self._pixel(x, y)

    def _check_reload(self):
        now = time.monotonic()
        if now - self._last_poll < POLL:
            return
        self._last_poll = now
        if not self._pending:
            if self.toy.changed():
                self._pending, self._pending_since = True, now
            return
        if now - self._pending_since < DEBOUNCE:
            return
        self._pending = False
        result = self.toy.reload()
        if result.success:
            if self.error:
                print(f"{self.name}: compiled again", file=sys.stderr)
            self.error = ""
        else:
            self.error = result.errors.splitlines()[0]
            print(result.errors, file=sys.stderr)
        self._title()

    def _title(self):
        title = f"facet shader - {self.name}"
        self.glfw.set_window_title(self.window, f"{title} - error: {self.error}" if self.error
                                   else title)

    def frame(self):
        fb = self.glfw.get_framebuffer_size(self.window)
        if min(fb) < 1:
            return
        self.toy.resize(*fb)
        now = time.perf_counter()
        if not self.paused:
            self.toy.step(now - self.start, now - self.last, tuple(self.mouse), fps=self.fps)
            self.mouse[3] = -abs(self.mouse[3])  # the click shows for one frame only
        self.last = now
        with self.ctx:
            screen = self.ctx.screen
            self.ctx.copy_framebuffer(screen, self.toy.image_framebuffer)
            if self.error:
                draw_error_frame(screen, fb)
        self.glfw.swap_buffers(self.window)

    def run(self):
        glfw = self.glfw
        while not glfw.window_should_close(self.window):
            self.frame()
            glfw.poll_events()
            self._check_reload()
            if self.paused:
                glfw.wait_events_timeout(POLL)

    def close(self):
        self.toy.close()
        self.ctx.release()
        self.glfw.destroy_window(self.window)
        self.glfw.terminate()


def run_window(args) -> None:
    try:
        check_display()
    except NoDisplayError:
        raise NoDisplayError("no display to open a window on (DISPLAY is not set); render "
                             "frames with -o, e.g. -o frame.png or --time 0:4 -o clip.mp4"
                             ) from None
    pg = Playground(args, size=args.size or (800, 450))
    try:
        pg.run()
    except FacetError:
        raise
    finally:
        pg.close()
