"""The live shader window (``facet shader FILE`` without -o): Shadertoy-style, hot reloaded.

Every file of the program (includes and the common file too) is watched by content hash;
a change is reloaded once it has stayed put (facet.window.base.Debounce). A shader that
fails to compile does not stop anything: the last good program keeps drawing inside a red
frame, the error goes to the window title and to stderr as ``path:line:col: error:
message``; fixing the file brings the picture back. Uniforms and textures survive a reload
and iTime keeps running. Mouse: Shadertoy's iMouse (xy while a button is held, origin
bottom-left; z/w the click, negative once released). Keys: q / Esc quit, space pauses,
r restarts time and buffers, f draws at the window's full size whatever a frame costs;
when a pass reads the keyboard channel every key but Esc goes to the shader (Shadertoy's
keyboard texture, JavaScript key codes). iDate is the wall clock unless --date fixes it.

The first frame is drawn at a quarter of the window's width and height and its cost
decides the size after it (facet.window.preview): a still picture refines to the full
size; an animation keeps the largest size that draws at 15 frames a second or more, and
the title says so (``drawn at 1/4 size: a full-size frame takes about 3.2 s``).

It draws only when the picture can change: every frame while the program reads a time or
frame input or a buffer feeds back on itself (ShaderToy.animated); otherwise once, and
again when a file is reloaded, the window is resized or exposed, the mouse moves or clicks
(if the program reads it) or a key reaches the keyboard channel. Idle, it sleeps.
"""

from __future__ import annotations

import sys
import time

from .base import POLL, Debounce, GLWindow
from .preview import PreviewSize

HEADLESS_HINT = "render frames with -o, e.g. -o frame.png or --time 0:4 -o clip.mp4"
# GLFW key -> the JavaScript key code Shadertoy's keyboard texture is indexed by (letters,
# digits and space are the same numbers in both).
JS_KEYS = {262: 39, 263: 37, 264: 40, 265: 38, 257: 13, 256: 27, 258: 9, 259: 8, 261: 46,
           260: 45, 268: 36, 269: 35, 266: 33, 267: 34, 340: 16, 344: 16, 341: 17, 345: 17,
           342: 18, 346: 18, 59: 186, 61: 187, 44: 188, 45: 189, 46: 190, 47: 191, 96: 192,
           91: 219, 92: 220, 93: 221, 39: 222,
           **{290 + i: 112 + i for i in range(12)}, **{320 + i: 96 + i for i in range(10)}}


def js_key(key: int) -> int | None:
    if 65 <= key <= 90 or 48 <= key <= 57 or key == 32:
        return key
    return JS_KEYS.get(key)


class ShaderWindow:
    """``make_toy(size, context)`` makes the ShaderToy (facet.lab.shadertoy) it shows."""

    def __init__(self, make_toy, name: str, size, fps: float = 60.0):
        self.win = GLWindow(size, f"facet shader - {name}", HEADLESS_HINT)
        glfw = self.glfw = self.win.glfw
        try:
            self.toy = make_toy(self.win.framebuffer_size, self.win.ctx)
        except BaseException:
            self.win.close()
            raise
        self.name = str(name)
        self.keyboard = self.toy.reads_keys
        self.error, self.paused, self.fps = "", False, fps
        self.dirty = True  # draw once, then when something changes (module docstring)
        self.start = self.last = time.perf_counter()
        self.mouse = [0.0, 0.0, 0.0, 0.0]
        self.debounce = Debounce()
        self.preview = PreviewSize()
        self._upscale = None  # the full-screen pass that stretches a smaller picture
        glfw.set_key_callback(self.win.handle, self._on_key)
        glfw.set_mouse_button_callback(self.win.handle, self._on_button)
        glfw.set_cursor_pos_callback(self.win.handle, self._on_cursor)
        glfw.set_framebuffer_size_callback(self.win.handle, lambda *_: self._redraw())
        glfw.set_window_refresh_callback(self.win.handle, lambda *_: self._redraw())

    def _redraw(self) -> None:
        self.dirty = True
    def _on_key(self, _w, key, _s, action, _m):
        glfw = self.glfw
        code = js_key(key)
        if code is not None and action in (glfw.PRESS, glfw.RELEASE):
            keys = self.toy.resources.keys  # rows: down, pressed this frame, toggled
            keys[0, code] = 255 if action == glfw.PRESS else 0
            if action == glfw.PRESS:
                keys[1, code] = 255
                keys[2, code] = 255 - keys[2, code]
        if action != glfw.PRESS:
            return
        if self.keyboard and key != glfw.KEY_ESCAPE:
            self.dirty = True
            return  # the shader reads the keyboard: keys are its own
        if key in (glfw.KEY_ESCAPE, glfw.KEY_Q):
            self.win.quit()
        elif key == glfw.KEY_SPACE:
            self.paused = not self.paused
        elif key == glfw.KEY_R:
            self.toy.restart()
            self.start = time.perf_counter()
            self.dirty = True
        elif key == glfw.KEY_F:
            self.preview.toggle_full()
            self._set_title()
            self.dirty = True

    def _pixel(self, x, y):
        """Window cursor -> framebuffer pixels, origin bottom-left (Shadertoy's iMouse)."""
        (w, h), (fw, fh) = self.win.size, self.win.framebuffer_size
        return x * fw / max(w, 1), (h - y) * fh / max(h, 1)

    def _on_button(self, _w, button, action, _m):
        x, y = self._pixel(*self.glfw.get_cursor_pos(self.win.handle))
        if action == self.glfw.PRESS:
            self.mouse = [x, y, x, y]  # z, w > 0: pressed, and w > 0 this frame: clicked
        elif action == self.glfw.RELEASE:
            self.mouse[2] = -abs(self.mouse[2])
        self.dirty = self.dirty or self.toy.reads_mouse

    def _on_cursor(self, _w, x, y):
        if self.mouse[2] > 0:  # iMouse (and u_mouse) follow a held button
            self.mouse[0], self.mouse[1] = self._pixel(x, y)
            self.dirty = self.dirty or self.toy.reads_mouse

    def _check_reload(self):
        if not self.debounce.due(self.toy.changed):
            return
        result = self.toy.reload()
        if result.success:
            if self.error:
                print(f"{self.name}: compiled again", file=sys.stderr)
            self.error = ""
        else:
            self.error = result.errors.splitlines()[0]
            print(result.errors, file=sys.stderr)
        self._set_title()
        self.dirty = True

    def _set_title(self, doing: str = "") -> None:
        """The name, then what is being drawn, the preview's size, or the error."""
        parts = [f"facet shader - {self.name}"]
        if self.error:
            parts.append(f"error: {self.error}")
        elif doing or self.preview.status():
            parts.append(doing or self.preview.status())
        self.win.set_title(" - ".join(parts))

    def frame(self):
        fb = self.win.framebuffer_size
        if min(fb) < 1:
            return
        size = self.preview.size(fb)
        self.toy.resize(*size)
        cost = self.preview.full_cost
        if size == tuple(fb) and cost is not None and cost > 1.0 and not self.toy.animated:
            self._set_title(f"refining to full size, about {cost:.1f} s")  # (it blocks)
            self.glfw.poll_events()
        now = time.perf_counter()
        if not self.paused:
            self.toy.step(now - self.start, now - self.last, tuple(self.mouse), fps=self.fps)
            self.mouse[3] = -abs(self.mouse[3])  # the click shows for one frame only
            self.toy.resources.keys[1] = 0  # "pressed" lasts one frame
            if not self.preview.measured:
                self.win.ctx.finish()  # (GL runs behind: wait for the frame to time it)
                if self.preview.measure(time.perf_counter() - now, self.toy.animated):
                    self.dirty = True  # drawn again at the size chosen
                self._set_title()
        self.last = now
        self._show(size, fb)
        if size == tuple(fb) and cost is not None and cost > 1.0 and not self.toy.animated:
            self._set_title()
        self.win.swap()

    def _show(self, size, fb) -> None:
        """The toy's picture on the window: copied, or stretched when drawn smaller."""
        ctx = self.win.ctx
        with ctx:
            ctx.screen.use()
            ctx.screen.viewport = (0, 0, *fb)
            if size == tuple(fb):
                ctx.copy_framebuffer(ctx.screen, self.toy.image_framebuffer)
            else:
                if self._upscale is None:
                    from ..gl.fullscreen import FullScreenPass

                    self._upscale = FullScreenPass(ctx, "post/upscale.frag")
                self._upscale.draw({"u_source": self.toy.image_texture},
                                   u_size=tuple(float(v) for v in fb))
            if self.error:
                self.win.draw_error_frame()

    def run(self):
        while not self.win.should_close():
            moving = self.toy.animated and not self.paused
            if moving or self.dirty:
                self.dirty = False
                self.frame()
            if moving:
                self.glfw.poll_events()
            else:  # asleep until an event, or the next look at the files
                self.glfw.wait_events_timeout(POLL)
            self._check_reload()

    def close(self):
        if self._upscale is not None:
            with self.win.ctx:
                self._upscale.release()
        self.toy.close()
        self.win.close()


def run_window(make_toy, name: str, size, fps: float = 60.0) -> None:
    """Show the toy ``make_toy(size, context)`` makes until the window is closed."""
    window = ShaderWindow(make_toy, name, size, fps)
    try:
        window.run()
    finally:
        window.close()
