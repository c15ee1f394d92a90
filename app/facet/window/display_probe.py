"""Whether the X server that DISPLAY names answers, within a bounded wait, before glfw
opens it: Xlib's XOpenDisplay (inside glfw.init) waits for ever on a server that accepts
the connection and never replies, in C, where not even SIGTERM stops it. The probe sends
the X11 connection-setup request and waits (in Python, so signals still work) for the
first byte of any reply: success, failure or "authenticate" all show a live server.

The probe's connection stays open until glfw has made its own: an X server resets when its
last client leaves, and a reset drops connections still in their setup, so a probe that
left just as glfw connected made glfw fail ("Failed to open display") at random.
"""

from __future__ import annotations

import re
import socket
import struct
from contextlib import contextmanager

# The 12-byte connection setup request: little-endian, protocol 11.0, no authorisation.
SETUP_REQUEST = b"l\0" + struct.pack("<HHHH", 11, 0, 0, 0) + b"\0\0"


def address(display: str):
    """(socket family, address candidates) for an X11 DISPLAY string, or None when it is a
    form this probe does not know (launchd sockets, ...): those are not probed."""
    m = re.fullmatch(r"(?:(unix|[A-Za-z0-9_.\-]+|\[[0-9A-Fa-f:.]+\]))?:(\d+)(?:\.\d+)?",
                     display.strip())
    if m is None:
        return None
    host, number = m.group(1), int(m.group(2))
    if host in (None, "", "unix"):
        path = f"/tmp/.X11-unix/X{number}"
        return socket.AF_UNIX, [path, "\0" + path]  # the file, then the abstract name
    host = host.strip("[]")
    return socket.AF_INET6 if ":" in host else socket.AF_INET, [(host, 6000 + number)]


@contextmanager
def answering(display: str, timeout: float):
    """Yields True when the server answers the setup request within ``timeout`` seconds,
    False when it accepts and stays silent, None when no connection could be made (glfw then
    says so itself) or the DISPLAY form is not probed; a connection that was answered stays
    open until the ``with`` block ends."""
    where = address(display)
    if where is None:
        yield None
        return
    family, candidates = where
    for target in candidates:
        s = socket.socket(family, socket.SOCK_STREAM)
        try:
            s.settimeout(timeout)
            s.connect(target)
            s.sendall(SETUP_REQUEST)
            answered = s.recv(1)
        except TimeoutError:
            s.close()
            yield False
            return
        except OSError:  # refused, no such socket, unreachable: try the next candidate
            s.close()
            continue
        with s:
            yield True if answered else None  # closed at once: glfw says why
        return
    yield None
