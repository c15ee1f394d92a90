"""Child processes for tests that stop them from outside: each in a session of its own (a
signal to its group reaches it and its children only), with SIGINT at its default. A shell
that starts a command in the background (``make test &``, ``nohup``) hands it SIGINT
ignored, and children inherit that: a stopped-with-Ctrl-C test would then see its render
run to the end."""

from __future__ import annotations

import os
import signal


def own_session() -> None:
    """``preexec_fn`` of subprocess.Popen: a new session, SIGINT as a terminal gives it."""
    os.setsid()
    signal.signal(signal.SIGINT, signal.SIG_DFL)
