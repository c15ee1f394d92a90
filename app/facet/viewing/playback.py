"""The viewer's clock (no glfw): where the scene's animations (and users' shaders' u_time)
stand, playing from a start time, looping over a span, paused and stepped by keys."""

from __future__ import annotations

import time

FRAME_STEP = 1.0 / 30.0  # the , and . keys: one frame at 30 fps
SECOND_STEP = 1.0  # the [ and ] keys


class Playback:
    """Seconds of scene time: ``start`` at creation, advancing with ``clock`` while
    playing, wrapped into [start, end) when ``end`` (> start) is given."""

    def __init__(self, start: float = 0.0, end: float | None = None, clock=time.perf_counter):
        self.start, self.end, self.clock = float(start), end, clock
        self.playing = True
        self._offset, self._origin = self.start, clock()

    def time(self) -> float:
        t = self._offset + (self.clock() - self._origin if self.playing else 0.0)
        if self.end is not None and self.end > self.start:
            t = self.start + (t - self.start) % (self.end - self.start)
        return max(t, 0.0)

    def toggle(self) -> bool:
        """Pause or play on from where it stands; returns whether it plays now."""
        self._offset, self._origin = self.time(), self.clock()
        self.playing = not self.playing
        return self.playing

    def step(self, seconds: float) -> float:
        """Pause, ``seconds`` later (or earlier); returns the time shown now."""
        self._offset, self._origin = max(self.time() + seconds, 0.0), self.clock()
        self.playing = False
        return self.time()
