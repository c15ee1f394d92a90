"""One thread that owns a GL context: every call that may touch the context runs there, one
at a time, whichever thread asks. A context can be current in one thread at a time and a
Renderer's sequence assumes nothing else draws between its steps; a front whose callbacks
come on several threads (ipykernel 7 delivers a notebook widget's messages and timers on
worker threads of its own) hands its work to an ``Owner`` instead of touching the context
itself. (The served viewer's render thread, facet.serve.worker, owns its session the same
way, with a queue of events.)"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

from ..guard import carried


class Owner:
    """A thread of its own for GL work: ``call(fn, *args, **kwargs)`` runs ``fn`` there and
    returns what it returns (raising what it raised); calls from several threads run one
    after another, each whole. A call made from the owner's thread runs at once (no wait on
    itself). ``close()`` ends the thread once the calls already made have run (the context
    is released by then: a later call runs where it is made)."""

    def __init__(self, name: str = "facet-gl"):
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix=name)
        self._ident = self._pool.submit(threading.get_ident).result()
        self._closed = False

    def call(self, fn, *args, **kwargs):
        if self._closed or threading.get_ident() == self._ident:
            return fn(*args, **kwargs)
        # (with the caller's confinement and context variables: facet.guard)
        return self._pool.submit(carried(fn), *args, **kwargs).result()

    def close(self) -> None:
        self._closed = True
        self._pool.shutdown(wait=threading.get_ident() != self._ident)
