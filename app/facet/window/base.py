"""What every facet window shares, and the only place glfw is set up: the display check, an
OpenGL 3.3 core window with its moderngl context, and the red frame around a stale picture."""

from __future__ import annotations

import os

from ..errors import FacetError
from ..viewing.debounce import DEBOUNCE, POLL, Debounce  # noqa: F401 (the windows' import)

ERROR_FRAME = (0.85, 0.1, 0.1, 1.0)  # the red frame drawn around a stale picture
ERROR_BORDER = 8  # pixels


class NoDisplayError(FacetError):
    """There is no display to open a window on."""


def init_glfw(glfw, hint: str = "use 'facet render' for headless images") -> None:
    """glfw.init, or NoDisplayError when there is no display, when the X server DISPLAY
    names does not answer within the wait budget (glfw would wait for ever, deaf to SIGTERM)
    or when glfw cannot open it."""
    display = os.environ.get("DISPLAY")
    if not (display or os.environ.get("WAYLAND_DISPLAY")):
        raise NoDisplayError(f"no display to open a window on (DISPLAY is not set); {hint}")
    from ..budgets import budget
    from .display_probe import answering

    wait = budget("wait_seconds")
    with answering(display or "", wait) as answered:
        if answered is False:
            raise NoDisplayError(f"the X display {display!r} did not answer within {wait} s "
                                 "(a stuck X server, or a forwarded display that is gone; "
                                 f"--budget wait_seconds=N waits longer); {hint}")
        if not glfw.init():  # while the probe is still connected: see display_probe
            raise NoDisplayError(f"cannot open the display {display!r}; {hint}")


class GLWindow:
    """A glfw window with an OpenGL 3.3 core context and a moderngl context over it."""

    def __init__(self, size, title: str, hint: str = "use 'facet render' for headless images"):
        import glfw

        init_glfw(glfw, hint)
        self.glfw = glfw
        glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
        glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
        glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
        glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
        glfw.window_hint(glfw.SCALE_TO_MONITOR, True)
        self.handle = glfw.create_window(int(size[0]), int(size[1]), title, None, None)
        if not self.handle:
            glfw.terminate()
            raise NoDisplayError(f"the display gave no OpenGL 3.3 window; {hint}")
        glfw.make_context_current(self.handle)
        glfw.swap_interval(1)
        from ..gl.context import create_for_current_window

        try:
            self.ctx = create_for_current_window()
        except BaseException:
            glfw.destroy_window(self.handle)
            glfw.terminate()
            raise

    @property
    def framebuffer_size(self) -> tuple[int, int]:
        return tuple(self.glfw.get_framebuffer_size(self.handle))

    @property
    def size(self) -> tuple[int, int]:
        """In screen coordinates (the cursor's), which may differ from the framebuffer's."""
        return tuple(self.glfw.get_window_size(self.handle))

    def set_title(self, title: str) -> None:
        self.glfw.set_window_title(self.handle, title)

    def should_close(self) -> bool:
        return self.glfw.window_should_close(self.handle)

    def quit(self) -> None:
        self.glfw.set_window_should_close(self.handle, True)

    def draw_error_frame(self) -> None:
        """A clearly visible red frame around the last good picture (a file has an error)."""
        screen = self.ctx.screen
        (w, h), b = self.framebuffer_size, ERROR_BORDER
        for rect in ((0, 0, w, b), (0, h - b, w, b), (0, 0, b, h), (w - b, 0, b, h)):
            screen.scissor = rect
            screen.clear(*ERROR_FRAME)
        screen.scissor = None

    def swap(self) -> None:
        self.glfw.swap_buffers(self.handle)

    def close(self) -> None:
        if self.handle is None:
            return
        self.ctx.release()
        self.glfw.destroy_window(self.handle)
        self.glfw.terminate()
        self.handle = None
