"""The command line's watch over one picture's sum of samples (``facet render``): a progress
line on stderr once it has run DELAY seconds (samples done, seconds so far, about how many
are left), on a terminal and without --quiet; and SIGINT / SIGTERM, which stop the sum
after the strip being drawn (facet.render.budget syncs with the GPU after each). With
--keep-partial the picture reached so far is written, then the run ends as a stopped one
(exit status 128 + the signal); without it the signal ends the run at once and nothing is
written.
"""

from __future__ import annotations

import signal
import sys
import time

DELAY = 2.0  # seconds before the line shows
REFRESH = 0.25  # seconds between two updates of it


class SampleProgress:
    """A ``Renderer.progress`` callback and the signal handlers of one render (module
    docstring); a context manager (the handlers are put back on exit)."""

    def __init__(self, quiet: bool, keep_partial: bool, time_limit: float | None = None):
        self.show = not quiet and sys.stderr.isatty()
        self.keep_partial = keep_partial
        self.time_limit = time_limit
        self.stopped_by = None  # the signal that stopped the sum
        self.done = self.total = 0
        self._shown_at = 0.0
        self._line = False
        self._before = {}

    def __call__(self, done: int, total: int, seconds: float) -> bool:
        self.done, self.total = done, total
        if self.show and seconds >= DELAY and time.monotonic() - self._shown_at >= REFRESH:
            self._shown_at = time.monotonic()
            left = seconds / max(done, 1) * (total - done)
            if self.time_limit is not None:
                left = min(left, max(self.time_limit - seconds, 0.0))
            sys.stderr.write(f"\r\x1b[Kfacet: {done}/{total} samples, {seconds:.1f} s, "
                             f"about {left:.0f} s left")
            sys.stderr.flush()
            self._line = True
        return self.stopped_by is None

    def _stop(self, signum, _frame) -> None:
        from . import _STOPPED_BY

        _STOPPED_BY[0] = signum
        if self.keep_partial and self.stopped_by is None:
            self.stopped_by = signum  # the sum stops after this strip; the picture is kept
            return
        raise KeyboardInterrupt

    def __enter__(self) -> SampleProgress:
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                self._before[sig] = signal.signal(sig, self._stop)
            except ValueError:  # not the main thread: signals stay as they are
                break
        return self

    def __exit__(self, *exc) -> None:
        for sig, handler in self._before.items():
            signal.signal(sig, handler)
        if self._line:
            sys.stderr.write("\r\x1b[K")
            sys.stderr.flush()

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
