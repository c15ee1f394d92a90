"""The served viewer's render thread: it owns the headless session (its GL context is
current in this thread only), applies the page's events in order, draws when something
changed, plays or refines, and hands each picture to the server to broadcast: JPEG while
the view changes, PNG once it has been still for ``LOSSLESS_AFTER`` seconds. Idle, it
waits on its queue (and looks at the open file every ``POLL`` seconds)."""

from __future__ import annotations

import queue
import sys
import threading
import time
import warnings

from ..errors import FacetWarning
from ..guard import carried
from ..viewing.debounce import POLL
from .encode import jpeg, png

LOSSLESS_AFTER = 0.3  # seconds still before the lossless picture is sent
IN_FLIGHT = 2  # pictures sent but not yet shown by a page, before drawing waits


class Worker(threading.Thread):
    """Runs ``make_session()`` in its own thread; ``post(event)`` from any thread;
    ``send(meta, data)`` is called from this thread with each picture."""

    def __init__(self, make_session, send, quality: int):
        super().__init__(name="facet-serve-render", daemon=True)
        self.make_session, self.send, self.quality = make_session, send, quality
        self.events: queue.SimpleQueue = queue.SimpleQueue()
        self.ready = threading.Event()  # the session exists (or failed: self.failure)
        self.failure: BaseException | None = None
        self.index = 0  # pictures sent
        self.shown = 0  # the last picture a page said it showed
        self.pages = 0  # pages connected: none, nothing is drawn
        self.said_quit = False  # the line about q in a page was printed
        self.sent = None  # the last picture sent
        self._carried = carried(self._serve)  # facet.guard: --confine holds here too

    def post(self, event: dict) -> None:
        self.events.put(event)

    def stop(self) -> None:
        self.events.put(None)

    def run(self) -> None:
        self._carried()  # with the confinement of the thread that made this one

    def _serve(self) -> None:
        try:
            session = self.make_session()
        except BaseException as exc:  # reported by the server, in the main thread
            self.failure = exc
            self.ready.set()
            return
        self.ready.set()
        try:
            self._loop(session)
        finally:
            session.close()

    def _loop(self, session) -> None:
        lossless_due = None  # when the last JPEG's lossless picture is due
        while True:
            busy = (self.pages > 0 and session.wants_frame
                    and self.index - self.shown < IN_FLIGHT)
            wait = 0.0 if busy else POLL
            if lossless_due is not None and not busy:
                wait = max(0.0, min(wait, lossless_due - time.monotonic()))
            events = self._take(wait)
            if events is None:
                return
            for event in events:
                self._event(session, event)
            if session.quitting:  # q / Esc in a page: the server stays for the other tabs
                session.quitting = False
                if not self.said_quit:
                    self.said_quit = True
                    print("facet view: q and Esc do not stop a served viewer (other tabs may "
                          "be watching); close the tab, and Ctrl-C here stops the server",
                          file=sys.stderr, flush=True)
            if self.pages == 0 or self.index - self.shown >= IN_FLIGHT:
                lossless_due = None if self.pages == 0 else lossless_due
                continue
            try:
                with warnings.catch_warnings(record=True) as said:
                    warnings.simplefilter("always", FacetWarning)
                    picture = session.frame()
                for w in said:  # (a warning reaches the page, not only this terminal)
                    if issubclass(w.category, FacetWarning):
                        session.say(f"warning: {w.message}")
                    else:
                        warnings.showwarning(w.message, w.category, w.filename, w.lineno)
            except Exception as exc:  # a shader or file that fails: shown, never fatal
                picture = self._failed(session, exc)
            if picture is not None:
                still = not (session.refining or session.animated)
                self._send(session, picture, lossless=False)
                lossless_due = time.monotonic() + LOSSLESS_AFTER if still else None
            elif lossless_due is not None and time.monotonic() >= lossless_due:
                self._send(session, self.sent, lossless=True)  # (what failed showed too)
                lossless_due = None

    def _event(self, session, event: dict) -> None:
        """Apply one page event (checked by the server already; a session's refusal, or
        anything else it raises, is one line and the thread goes on)."""
        kind = event.get("type")
        try:
            if kind == "frame_feedback":
                self.shown = max(self.shown, int(event.get("index", 0)))
            elif kind == "hello":  # a new page: it needs the picture now
                self.pages += 1
                self.shown = self.index  # what went before went to no one waiting
                session.request_frame()
            elif kind == "bye":
                self.pages = max(self.pages - 1, 0)
            else:
                session.handle(event)
        except Exception as exc:
            self._say(f"dropped a {kind} event ({exc})")

    def _failed(self, session, exc: BaseException):
        """A draw that failed: its error in the status line (and one line here), the last
        picture (or a blank one) sent with it, no new attempt until something changes."""
        from ..errors import FacetError

        text = str(exc) if isinstance(exc, FacetError) else \
            f"internal error: {type(exc).__name__}: {exc}"
        session.fail_frame(text)
        self._say(text.splitlines()[0] if text else type(exc).__name__)
        if session.last is not None:
            return session.last
        import numpy as np

        width, height = session.surface_size
        return np.full((height, width, 3), 32, np.uint8)

    def _say(self, line: str) -> None:
        """One line on stderr, not repeated while it stays the same."""
        if line != getattr(self, "_said", None):
            self._said = line
            print(f"facet view: {line}", file=sys.stderr, flush=True)

    def _take(self, wait: float):
        """The events waiting (at least one if any comes within ``wait`` seconds); None
        when asked to stop."""
        out = []
        try:
            out.append(self.events.get(timeout=wait) if wait > 0 else
                       self.events.get_nowait())
            while True:
                out.append(self.events.get_nowait())
        except queue.Empty:
            pass
        return None if None in out else out

    def _send(self, session, picture, lossless: bool) -> None:
        self.sent = picture  # the picture pages show: drawn, or a failed draw's stand-in
        self.index += 1
        camera = session.camera()
        meta = {"type": "frame", "index": self.index, "lossless": lossless,
                "mime": "image/png" if lossless else "image/jpeg",
                "width": int(picture.shape[1]), "height": int(picture.shape[0]),
                "status": session.status(), "state": session.state(),
                "notices": session.take_notices(),
                "camera": camera.describe(
                    int(picture.shape[1]), int(picture.shape[0]))}
        self.send(meta, png(picture) if lossless else jpeg(picture, self.quality))
