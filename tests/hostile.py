"""Running facet on hostile input, for the reliability tests: a `facet` command in a child
process under a memory limit and a timeout, so a blow-up fails the test, not the machine;
and what a handled refusal looks like (exit 2, one line, no traceback, no signal)."""

from __future__ import annotations

import os
import re
import resource
import socket
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MEMORY = 3 << 30  # address space of the child: facet's budgets keep far below it


def _limit():  # in the child, before exec
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def facet(*args, cwd=None, timeout: float = 60, env=None, stdin=None):
    """(exit status, stderr) of `python -m facet ARGS` (a signal: a negative status)."""
    full = {**os.environ, "PYTHONPATH": str(ROOT / "app"), **(env or {})}
    run = subprocess.run([sys.executable, "-m", "facet", *map(str, args)], cwd=cwd,
                         env=full, capture_output=True, text=True, timeout=timeout,
                         preexec_fn=_limit, stdin=stdin if stdin is not None else
                         subprocess.DEVNULL)
    return run.returncode, run.stderr


def refused(result, *fragments) -> str:
    """Assert ``result`` is a refusal: exit 2, one line of stderr starting with facet's
    error prefix (``facet: error:``, or ``facet COMMAND: error:`` for a usage error;
    warnings before it allowed), no traceback; returns the line."""
    code, err = result
    lines = [line for line in err.strip().splitlines() if not line.startswith(
        "facet: warning:")]
    assert code == 2, (code, err[-2000:])
    assert "Traceback" not in err, err[-2000:]
    assert len(lines) == 1 and re.match(r"facet( [a-z]+)?: error: ", lines[0]), err[-2000:]
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    return lines[0]


def png_header(width: int, height: int) -> bytes:
    """A PNG that claims width x height pixels (RGB) and holds almost nothing: what a
    reader that trusts the header would allocate for."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(
            ">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"")) + \
        chunk(b"IEND", b"")


def x_socket(first: int):
    """(display name, listening socket, path) for a stand-in X server on a unix socket in
    /tmp/.X11-unix, at the first free display number from ``first`` (tests running side by
    side each get their own)."""
    folder = Path("/tmp/.X11-unix")
    folder.mkdir(exist_ok=True)
    for number in range(first, first + 100):
        path = folder / f"X{number}"
        server = socket.socket(socket.AF_UNIX)
        try:
            server.bind(str(path))
        except OSError:  # taken
            server.close()
            continue
        server.listen(8)
        return f":{number}", server, path
    raise AssertionError(f"no free X display number from {first}")
