"""The command line's progress line for one picture (``facet render``), on stderr, on a
terminal and without --quiet, once a stage has run DELAY seconds: the stages without steps
to count (loading the model, preparing the scene for an engine: its hierarchy, its upload,
its shaders) with their seconds so far, then the sum of samples (samples done, seconds so
far, about how many are left). And SIGINT / SIGTERM, which stop the sum after the strip
being drawn (facet.render.budget syncs with the GPU after each). With --keep-partial the
picture reached so far is written, then the run ends as a stopped one (exit status 128 +
the signal); without it the signal ends the run at once and nothing is written.
FACET_PROGRESS_DELAY sets DELAY (the tests show the line at once).
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
import warnings

DELAY = float(os.environ.get("FACET_PROGRESS_DELAY", "2.0"))  # seconds before a line shows
REFRESH = 0.25  # seconds between two updates of it
STABLE = 0.25  # two measured rates this close (relative) make the time left worth saying


class Ticker:
    """The one progress line: a thread rewrites it every REFRESH seconds while a stage runs
    (after DELAY), the sum of samples sets its text; cleared when the stage ends, and
    before a warning is printed (the warning keeps a line of its own)."""

    def __init__(self, show: bool):
        self.show = show
        self._lock = threading.Lock()
        self._text = None  # a callable giving the line's text, or None: no line
        self._since = 0.0
        self._line = False
        self._thread: threading.Thread | None = None
        self._done = threading.Event()

    @contextlib.contextmanager
    def stage(self, label: str):
        """While in it: "facet: <label>, <seconds> s" once it has run DELAY seconds."""
        if not self.show:
            yield
            return
        start = time.monotonic()
        with self._lock:
            self._text, self._since = (lambda: f"{label}, {time.monotonic() - start:.1f} s"), \
                start
        self._run()
        shown = warnings.showwarning

        def warn(*args, **kwargs):  # (the line first cleared: the warning has its own)
            with self._lock:
                self._clear()
            shown(*args, **kwargs)
        warnings.showwarning = warn
        try:
            yield
        finally:
            warnings.showwarning = shown
            with self._lock:
                self._text = None
                self._clear()

    def set(self, text: str) -> None:
        """The line says ``text`` now (until the stage ends or the next call)."""
        with self._lock:
            self._text, self._since = (lambda: text), 0.0
            self._write()

    def _run(self) -> None:
        if self._thread is None:
            self._thread = threading.Thread(target=self._tick, name="facet-progress",
                                            daemon=True)
            self._thread.start()

    def _tick(self) -> None:
        while not self._done.wait(REFRESH):
            with self._lock:
                if self._text is not None and time.monotonic() - self._since >= DELAY:
                    self._write()

    def _write(self) -> None:
        if self._text is not None:
            sys.stderr.write(f"\r\x1b[Kfacet: {self._text()}")
            sys.stderr.flush()
            self._line = True

    def _clear(self) -> None:
        if self._line:
            sys.stderr.write("\r\x1b[K")
            sys.stderr.flush()
            self._line = False

    def close(self) -> None:
        self._done.set()
        with self._lock:
            self._text = None
            self._clear()


def ticker(quiet: bool) -> Ticker:
    """The progress line of a command: shown on a terminal, without --quiet."""
    return Ticker(not quiet and sys.stderr.isatty())


class TimeLeft:
    """The seconds left of a sum of samples, from the rate measured since the first sample
    (which carries compiling shaders and uploading the scene, and would inflate every
    estimate), said only once two rates in a row agree within STABLE (then from there on):
    None until then."""

    def __init__(self):
        self._first: tuple[float, int] | None = None  # (time, samples) at the first sample
        self._rate: float | None = None  # seconds a sample, at the last update
        self.stable = False

    def update(self, done: int, total: int, now: float) -> float | None:
        if self._first is None:
            if done >= 1:
                self._first = (now, done)
            return None
        t0, d0 = self._first
        if done - d0 < 1 or now <= t0:
            return None
        rate = (now - t0) / (done - d0)
        if not self.stable and self._rate is not None and done - d0 >= 2:
            self.stable = abs(rate - self._rate) <= STABLE * self._rate
        self._rate = rate
        return rate * max(total - done, 0) if self.stable else None


class SampleProgress:
    """A ``Renderer.progress`` callback and the signal handlers of one render (module
    docstring); a context manager (the handlers are put back on exit)."""

    def __init__(self, quiet: bool, keep_partial: bool, time_limit: float | None = None,
                 line: Ticker | None = None):
        self.line = line or ticker(quiet)
        self.show = self.line.show
        self.keep_partial = keep_partial
        self.time_limit = time_limit
        self.stopped_by = None  # the signal that stopped the sum
        self.done = self.total = 0
        self._shown_at = 0.0
        self._before = {}
        self._start = time.monotonic()  # the stage's start: its seconds never go back
        self._left = TimeLeft()

    def __call__(self, done: int, total: int, seconds: float) -> bool:
        self.done, self.total = done, total
        now = time.monotonic()
        left = self._left.update(done, total, now)
        elapsed = now - self._start  # (the renderer's seconds start after its preparation)
        if self.show and elapsed >= DELAY and now - self._shown_at >= REFRESH:
            self._shown_at = now
            if left is not None and self.time_limit is not None:
                left = min(left, max(self.time_limit - seconds, 0.0))
            said = "estimating the time left" if left is None else f"about {left:.0f} s left"
            self.line.set(f"{done}/{total} samples, {elapsed:.1f} s, {said}")
        return self.stopped_by is None

    def _stop(self, signum, _frame) -> None:
        from . import _STOPPED_BY

        _STOPPED_BY[0] = signum
        if self.keep_partial and self.stopped_by is None:
            self.stopped_by = signum  # the sum stops after this strip; the picture is kept
            return
        raise KeyboardInterrupt

    def __enter__(self) -> SampleProgress:
        self._start = time.monotonic()
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                self._before[sig] = signal.signal(sig, self._stop)
            except ValueError:  # not the main thread: signals stay as they are
                break
        return self

    def __exit__(self, kind, *exc) -> None:
        for sig, handler in self._before.items():
            signal.signal(sig, handler)
        self.line.close()
        if kind is KeyboardInterrupt and not self.keep_partial and self.total > 1:
            from . import _STOPPED_BY

            name = signal.Signals(_STOPPED_BY[0]).name
            print(f"facet: stopped by {name} after {self.done} of {self.total} samples; "
                  "nothing was written (--keep-partial writes the picture so far)",
                  file=sys.stderr)

    def after_writing(self, written) -> None:
        """Once the picture is written: a stopped sum ends the run as stopped (a line says
        how far it got)."""
        if self.stopped_by is not None:
            name = signal.Signals(self.stopped_by).name
            print(f"facet: stopped by {name} after {self.done} of {self.total} samples; "
                  f"the picture so far is in {', '.join(str(p) for p in written)}",
                  file=sys.stderr)
            raise KeyboardInterrupt

    def nothing_to_keep(self) -> bool:
        """Stopped before a single sample was in: there is no picture to write."""
        return self.stopped_by is not None and self.done == 0
