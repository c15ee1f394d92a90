"""The viewer as a notebook widget: jupyter_rfb's remote frame buffer (the one pygfx uses)
over a headless ``facet.viewing.session.Session`` rendering in the kernel.

The browser sends pointer, wheel, key and resize events; the session applies them with the
window's controls and keys (drag orbits, right / shift drag pans, the wheel zooms, ``e``
engine, ``m`` shading, ``s`` screenshot, ... ``h`` lists them) and draws the next picture.
jupyter_rfb sends it as JPEG while the view changes and as a lossless PNG once it has been
still for a moment; a still view refines (supersampling, the tracers) frame by frame as in
the window, and an idle widget draws nothing. The status line (the file, the engine, how far
a still view has refined, an error) is the widget's title bar. The open file is looked at every
``WATCH_EVERY`` seconds on the kernel's event loop and reloaded when it changed, as the
window reloads it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..gl.owner import Owner
from ..viewing.session import Session

QUALITY = 80  # JPEG quality while the view moves (lossless once it is still)
WATCH_EVERY = 0.25  # seconds between looks at the open file (and users' shaders)
SIZE = (640, 480)  # CSS pixels, when neither the call nor the scene gives a size
NEEDS = "the notebook widget needs jupyter_rfb: pip install 'facet-render[notebook]'"


def _base():
    try:
        from jupyter_rfb import RemoteFrameBuffer
    except ImportError:
        raise InputError(NEEDS) from None
    return RemoteFrameBuffer


def widget_class():
    """The widget class (made on first use: jupyter_rfb is an optional dependency)."""
    global Widget
    if Widget is None:
        Widget = type("Widget", (_WidgetMixin, _base()), {"__doc__": _WidgetMixin.__doc__,
                                                          "__module__": __name__})
    return Widget


Widget = None  # the class, once widget_class() made it


class _WidgetMixin:
    """An interactive view of ``source`` (a Scene, or a mesh or scene file) in a notebook.

    Parameters
    ----------
    source : Scene or str or Path
        What to show.
    size : (int, int), optional
        The widget's size in CSS pixels (default: the scene file's, else 640x480).
    quality : int
        JPEG quality (1-100) while the view moves; 100 sends PNG always.
    screenshots : str or Path, optional
        The folder the ``s``, ``S`` and ``t`` keys write into (default: the kernel's working
        directory).
    **options
        Render options over the scene's (``engine="path"``, ``shading="pbr"``, ...).
    """

    if TYPE_CHECKING:  # jupyter_rfb's RemoteFrameBuffer gives these
        def request_draw(self) -> None: ...
        def print(self, *args, **kwargs) -> None: ...  # into the widget's output area
        def _rfb_send_frame(self, array, is_lossless_redraw: bool = False) -> None: ...
        def close(self) -> None: ...
        quality: int
        title: str
        has_titlebar: bool
        _frame_feedback: dict
        _rfb_frame_index: int
        _rfb_last_confirmed_index: int
        css_width: str
        css_height: str

    def __init__(self, source, size=None, quality: int = QUALITY, screenshots=None,
                 **options):
        # The session's GL work runs in a thread of its own, one call at a time (ipykernel 7
        # delivers a widget's messages and timers on several threads: two frames drawn at
        # once on one context corrupted the sum of a refining view).
        gl = Owner("facet-widget")
        try:
            session = gl.call(Session, source, size=size, options=options,
                              screenshots=screenshots)
        except BaseException:
            gl.close()
            raise
        if size is None and session.scene.options.get("size") is None:
            gl.call(session.resize, *SIZE)
        super().__init__()
        self._gl = gl
        self.session = session
        w, h = session.surface_size
        self.css_width, self.css_height = f"{w}px", f"{h}px"
        self.quality = int(quality)
        # The status line (file, engine, refinement, an error) in the widget's title bar, as
        # the served page shows it under its picture.
        self.has_titlebar = True
        self.title = session.status()
        self._watching = self._schedule_watch()

    # -- jupyter_rfb's two methods ---------------------------------------------------------
    def handle_event(self, event: dict) -> None:
        """One browser event: applied to the session; a picture is asked for when it
        changed the view."""
        from ..viewing.events import checked

        try:  # input from a browser: checked as the served page's events are
            event = checked(event)
        except InputError as exc:
            import warnings

            from ..errors import FacetWarning

            warnings.warn(FacetWarning(f"dropped an event ({exc})"), stacklevel=2)
            return
        kind = event.get("event_type") or event.get("type")
        if kind == "close":
            self._gl.call(self.session.close)
            self._gl.close()
            return
        last, wants_frame, quitting = self._gl.call(self._apply, event)
        if kind == "resize":  # (also a view shown again, which has no picture yet)
            # A reloaded page never confirms the pictures sent to the page it replaced, and
            # jupyter_rfb sends nothing while max_buffered_frames are unconfirmed: forget them
            # (else the new view stays blank for good; confirmed in jupyter_rfb's statistics
            # too: they were never seen).
            import time

            sent, now = self._rfb_frame_index, time.time()
            self._rfb_last_confirmed_index = max(self._rfb_last_confirmed_index, sent)
            self._frame_feedback = {"index": sent, "timestamp": now, "localtime": now}
            if last is not None and not wants_frame:
                # A view of the same size shown again: the picture as it is, lossless at
                # once (the views that have it see no change; nothing is redrawn).
                self._rfb_send_frame(last, True)
        if quitting:
            self.close()
        elif wants_frame:
            self.request_draw()

    def _apply(self, event: dict):
        """(In the GL thread) the event applied: (the last picture, whether a new one is
        wanted, whether q was pressed)."""
        session = self.session
        session.handle(event)
        return session.last, session.wants_frame, session.quitting

    def get_frame(self) -> np.ndarray | None:
        """The next picture, (H, W, 3) uint8, or None when nothing changed; asks for
        another while the view refines or plays."""
        if self.session.closed:
            return None
        picture, status, notices, again = self._gl.call(self._next_frame)
        if status is not None and status != self.title:
            self.title = status
        for text in notices:  # a key's result, the key map: into the widget's output area,
            self.print(text)  # under it in its cell (print() from a comm's callback is lost)
        if again:
            self.request_draw()
        return picture

    def _next_frame(self):
        """(In the GL thread) the next picture, the status line, the notices said and
        whether to ask for another picture."""
        session = self.session
        if session.closed:
            return None, None, [], False
        picture = session.frame()
        return (picture, session.status(), session.take_notices(),
                session.animated or session.refining)

    # -- the open file ---------------------------------------------------------------------
    def _schedule_watch(self) -> bool:
        """Look at the open file again in WATCH_EVERY seconds, on the kernel's event loop
        (none outside a running loop: a script calls ``watch()`` itself)."""
        import asyncio

        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            return False
        loop.call_later(WATCH_EVERY, self._watch_and_again)
        return True

    def _watch_and_again(self) -> None:
        if self.watch():
            self._schedule_watch()

    def watch(self) -> bool:
        """Reload the open file (and users' shaders) when they changed, as the window does,
        and ask for a picture when there is one to draw; returns False once the widget is
        closed (the loop stops looking)."""
        session = self.session
        if session.closed:
            return False
        if self._gl.call(session.poll):
            self.request_draw()
        return True

    # -- for scripts -------------------------------------------------------------------
    def camera(self):
        """The camera shown now (facet.Camera)."""
        return self._gl.call(self.session.camera)

    def set_camera(self, camera) -> None:
        self._gl.call(self.session.set_camera, camera)
        self.request_draw()

    def press(self, key: str) -> None:
        """Press a viewer key (``"e"``: next engine, ...), as a user would."""
        self.handle_event({"type": "key_down", "key": key, "modifiers": []})

    @property
    def picture(self) -> np.ndarray | None:
        """The last picture drawn, (H, W, 3) uint8 (None before the first)."""
        return self.session.last


def in_jupyter() -> bool:
    """Whether this runs in a Jupyter kernel (where widgets display)."""
    import sys

    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None
    return shell is not None and hasattr(shell, "kernel")
