"""Debouncing of file changes: editors save in two steps, and a reload between them would see
half a file (no GL, no glfw: every viewer front watches files through it)."""

from __future__ import annotations

import time

DEBOUNCE = 0.15  # a change must stay put this long before it is loaded
POLL = 0.1  # seconds between checks of watched files


class Debounce:
    """Says when a change has stayed put for ``delay`` seconds, checking at most every
    ``interval`` (editors save in two steps: a reload between them would see half a file)."""

    def __init__(self, delay: float = DEBOUNCE, interval: float = POLL):
        self.delay, self.interval = delay, interval
        self._since: float | None = None
        self._token = None
        self._checked = 0.0

    @property
    def pending(self) -> bool:
        return self._since is not None

    def due(self, changed) -> bool:
        """Whether to load now. ``changed()`` returns something false when the watched
        content is as loaded, else a token of the new content (a digest; True will do):
        a different token starts the wait again."""
        now = time.monotonic()
        if now - self._checked < self.interval:
            return False
        self._checked = now
        token = changed()
        if not token:
            self._since = self._token = None
            return False
        if self._since is None or token != self._token:
            self._since, self._token = now, token
        if now - self._since < self.delay:
            return False
        self._since = self._token = None
        return True
