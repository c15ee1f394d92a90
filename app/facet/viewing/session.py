"""The viewer without a window: events in, pictures out. The notebook widget
(facet.notebook) and the served page (facet.serve) drive one ``Session`` each; it renders
headless through its own Renderer into a canvas (facet.gl.targets.Canvas) with the
window's pass sequence (quick pictures while the view moves, supersamples added while it
is still) and hands the picture back as an (H, W, 3) uint8 array.

Events use the vocabulary of jupyter_rfb (the remote frame buffer pygfx uses), which the
served page speaks too: dicts with ``type`` (or ``event_type``) ``pointer_down`` /
``pointer_move`` / ``pointer_up`` (``x``, ``y`` in CSS pixels, ``button`` 1 left, 2 right,
3 middle, ``modifiers`` such as ``"Shift"``), ``wheel`` (``dy`` in pixels, positive away
from the user), ``key_down`` (``key``: one character, or a name such as ``"Escape"``) and
``resize`` (``width``, ``height`` in CSS pixels, ``pixel_ratio``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from .core import ViewerCore

if TYPE_CHECKING:
    from ..gl.targets import Canvas

WHEEL_NOTCH = 100.0  # wheel pixels a browser reports for one notch (zoom step)
LEFT, RIGHT, MIDDLE = 1, 2, 3  # jupyter_rfb's button numbers
MAX_SIDE = 4096  # the largest canvas side a page may ask for (pixels)


class Session(ViewerCore):
    """A headless viewer of ``source`` (a Scene, or a mesh or scene file).

    The arguments are the window's (facet.window.viewer.Viewer); ``renderer``: draw through
    this one (not closed here) instead of a new headless Renderer. ``frame()`` returns the
    next picture when something changed, plays or refines, else None: an idle viewer
    costs nothing. ``handle(event)`` applies one event; ``close()`` releases the GL.
    """

    status_name = "facet"

    def __init__(self, source, size=None, msaa: int | None = None, shader=None, options=None,
                 crease: float | None = None, time_end: float | None = None,
                 sizes: dict | None = None, renderer=None, screenshots=None):
        super().__init__(source, size, msaa, shader=shader, options=options, crease=crease,
                         time_end=time_end, sizes=sizes, screenshots=screenshots)
        from ..render.renderer import Renderer

        w, h = self.initial_size
        self._size: tuple[int, int] = (int(w), int(h))  # pixels drawn
        self._pointer: tuple[float, float] = (float(w), float(h))  # the events' CSS pixels
        self._own_renderer = renderer is None
        self.canvas: Canvas | None = None
        self.quitting = False  # q was pressed: the front closes the view
        self.closed = False
        self.last: np.ndarray | None = None  # the last picture drawn
        self.frames = 0  # pictures drawn
        self.start(Renderer() if renderer is None else renderer)

    # -- what ViewerCore asks of a front ---------------------------------------------------
    @property
    def surface_size(self) -> tuple[int, int]:
        return self._size

    @property
    def pointer_size(self) -> tuple[float, float]:
        return self._pointer

    def grab(self) -> np.ndarray:
        return self.draw() if self.last is None or self._dirty else self.last

    def quit(self) -> None:
        self.quitting = True

    # -- size, events and pictures ---------------------------------------------------------
    def resize(self, width: float, height: float, pixel_ratio: float = 1.0) -> None:
        """The view is ``width`` x ``height`` CSS pixels at ``pixel_ratio`` pixels each."""
        if not (width >= 1 and height >= 1 and 0 < pixel_ratio <= 8):
            return  # a hidden or collapsed view: keep the last size
        pw, ph = (min(max(int(round(v * pixel_ratio)), 1), MAX_SIDE) for v in (width, height))
        pixels = (pw, ph)
        self._pointer = (float(width), float(height))
        if pixels != self._size:
            self._size = pixels
            self.request_frame()

    def show_status(self, text: str) -> None:
        """The status line travels with each picture (a page's, a widget's): a new one
        (a reload that failed, say) is drawn with the next picture, so one is asked for."""
        self.request_frame()

    front = "page"

    def say(self, text: str) -> None:
        """A notice travels with the next picture (facet.serve.worker: the page shows it
        over the picture), not to the server's terminal, where no one looks."""
        self.notices = [*getattr(self, "notices", []), text][-8:]
        self.request_frame()

    def take_notices(self) -> list[str]:
        """The notices said since the last picture (and forgets them)."""
        out, self.notices = list(getattr(self, "notices", [])), []
        return out

    def handle(self, event: dict) -> None:
        """Apply one event (the module docstring's vocabulary); unknown kinds are ignored
        (a page may send more than the viewer uses). InputError naming the field when the
        event is malformed (facet.viewing.events), or when it would leave the camera
        somewhere not finite (the view is kept as it was)."""
        from .events import checked

        event = checked(event)
        before = {k: v.copy() if isinstance(v, np.ndarray) else v
                  for k, v in vars(self.control).items()}
        try:
            with np.errstate(all="ignore"):  # a result out of range is caught just below
                self._apply(event)
            finite = _finite_camera(self.camera())
        except (InputError, ArithmeticError, ValueError):  # a camera out of range
            finite = False
        if not finite:
            vars(self.control).update(before)
            kind = event.get("type") or event.get("event_type")
            raise InputError(f"{kind}: would move the camera somewhere not finite; ignored")

    def _apply(self, event: dict) -> None:
        kind = event.get("type") or event.get("event_type")
        x, y = float(event.get("x", 0.0)), float(event.get("y", 0.0))
        if kind == "pointer_down":
            button = event.get("button", LEFT)
            self.press(x, y, button in (RIGHT, MIDDLE) or "Shift" in event.get("modifiers", ()))
        elif kind == "pointer_move":
            self.move(x, y)
        elif kind == "pointer_up":
            self.release()
        elif kind == "wheel":
            self.scroll(-float(event.get("dy", 0.0)) / WHEEL_NOTCH, x, y)
        elif kind == "key_down":
            key = str(event.get("key", ""))
            if key == "Escape":
                self.quit()
            elif len(key) == 1:
                self.char(key)
        elif kind == "resize":
            self.resize(float(event.get("width", 0)), float(event.get("height", 0)),
                        float(event.get("pixel_ratio", event.get("ratio", 1.0)) or 1.0))

    def draw(self) -> np.ndarray:
        """Draw the next frame now and return it, (H, W, 3) uint8, row 0 at the top."""
        with self.renderer.current():
            return self._draw()

    def _draw(self) -> np.ndarray:
        canvas = self.canvas
        if canvas is None or canvas.size != self._size:
            from ..gl.targets import Canvas

            if canvas is not None:
                canvas.release()
                self.canvas = None
            canvas = self.canvas = Canvas(self.renderer.ctx, *self._size)
        self.draw_into(canvas.framebuffer)
        self.last = canvas.read()
        self.frames += 1
        return self.last

    def frame(self) -> np.ndarray | None:
        """The next picture when something changed, plays or refines (None: nothing to
        draw); reloads the open file and user shaders first when they changed."""
        with self.renderer.current():  # engines are made, and shaders reloaded, in it
            self.check_files()
            return self._draw() if self.wants_frame else None

    def poll(self) -> bool:
        """Reload the open file and user shaders when they changed (and then stayed put);
        returns whether there is a picture to draw. What a front without its own frame
        loop calls every so often (the notebook widget)."""
        if self.closed:
            return False
        with self.renderer.current():
            self.check_files()
            return self.wants_frame

    def close(self) -> None:
        """Release the canvas (and the renderer when the session made it). Safe to call
        twice."""
        if self.closed:
            return
        self.closed = True
        if self.canvas is not None:
            with self.renderer.current():
                self.canvas.release()
            self.canvas = None
        if self._own_renderer:
            self.renderer.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _finite_camera(camera) -> bool:
    """Whether a camera's view and projection hold finite numbers only."""
    return bool(np.isfinite(camera.view).all() and
                np.isfinite(camera.projection(16, 16)).all())
