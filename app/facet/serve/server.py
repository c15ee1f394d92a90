"""``facet view --serve [HOST:]PORT``: the viewer in a web page, over a WebSocket.

One headless session (facet.viewing.session) renders in a thread of its own
(facet.serve.worker); the page (page.html, viewer.js beside this module) sends pointer,
wheel, key and resize events in jupyter_rfb's vocabulary and shows each picture it gets.
Every open tab sees the one session: the same camera and keys, the picture drawn at the
size of the tab that was resized last. The server binds to 127.0.0.1 unless told otherwise
and asks for a token in the URL (printed at start, with the ``ssh -L`` line that reaches it
from another machine); a request without it gets 403, and so does one whose Host header
names no address of this server (DNS rebinding) or a WebSocket whose Origin is another
site's (cross-site WebSocket hijacking). Messages are checked where they arrive
(facet.viewing.events): a malformed one is dropped with one line and its connection
closed; the render thread outlives anything a page sends. SIGINT / SIGTERM stop it as they
stop any facet command (exit status 130 / 143).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import secrets
import signal
import sys
from pathlib import Path
from urllib.parse import parse_qs, urlsplit

from ..errors import InputError
from ..guard import parse_json
from ..viewing.events import checked
from .encode import QUALITY

HERE = Path(__file__).resolve().parent
STATIC = {"/": ("page.html", "text/html; charset=utf-8"),
          "/viewer.js": ("viewer.js", "text/javascript; charset=utf-8")}
DEFAULT_HOST = "127.0.0.1"
LOCAL = ("127.0.0.1", "localhost", "::1")
LOGGER = "facet.serve.websockets"  # the WebSocket library's records (OneLineLogs)
NEEDS = "facet view --serve needs websockets: pip install 'facet-render[serve]'"


def parse_address(text: str) -> tuple[str, int]:
    """``[HOST:]PORT`` -> (host, port); one clear error otherwise."""
    host, _, port = text.rpartition(":")
    host = host.strip("[]") or DEFAULT_HOST
    if not port.isdigit() or not 0 <= int(port) <= 65535:
        raise InputError(f"--serve: expected [HOST:]PORT with PORT 0-65535 (0: any free "
                         f"port), got {text!r}")
    return host, int(port)


class Server:
    """Serves the page and one session to every tab (see the module docstring)."""

    def __init__(self, make_session, host: str = DEFAULT_HOST, port: int = 0,
                 token: str | None = None, quality: int = QUALITY):
        self.make_session, self.host, self.port = make_session, host, port
        self.token = token or secrets.token_urlsafe(16)
        self.quality = quality
        self.clients: set = set()
        self.loop: asyncio.AbstractEventLoop | None = None
        self.worker = None
        self.last: tuple[str, bytes] | None = None  # the last picture (meta, data)
        self._names: set[str] | None = None  # what Host and Origin may name (_our_names)

    # -- HTTP: the page, its script, and the token check -----------------------------------
    def _names_us(self, netloc: str | None) -> bool:
        """Whether ``netloc`` (a Host header, an Origin's host[:port]) names this server:
        its port and the address it serves or the name the user gave (with the loopback
        names when that is a loopback address; this machine's names and addresses when it
        listens on every interface), as a bare ``host:port``: no user part
        (``evil.example@127.0.0.1``), no other IP address, no domain that resolves here by
        a rebinding."""
        if not netloc or any(c in netloc for c in "@/\\?#%") or \
                any(ord(c) <= 32 or ord(c) >= 127 for c in netloc):
            return False
        try:
            parsed = urlsplit(f"//{netloc}")
            host, port = parsed.hostname, parsed.port
        except ValueError:
            return False
        if not host or port != self.port:
            return False
        return host.lower() in self._our_names()

    def _our_names(self) -> set[str]:
        """The host names and addresses a request may give for this server (above)."""
        if self._names is None:
            import ipaddress
            import socket

            names = {self.host.lower().strip("[]")}
            try:
                address = ipaddress.ip_address(self.host.strip("[]"))
            except ValueError:
                address = None
            if self.host.lower() == "localhost" or (address is not None and
                                                   address.is_loopback):
                names |= set(LOCAL)
            elif address is not None and address.is_unspecified:  # every interface
                names |= set(LOCAL) | {socket.gethostname().lower(),
                                       socket.getfqdn().lower()}
                try:
                    names |= {info[4][0].lower() for info in socket.getaddrinfo(
                        socket.gethostname(), None)}
                except OSError:
                    pass
            self._names = names
        return self._names

    def _process_request(self, connection, request):
        try:
            return self._respond(connection, request)
        except Exception as exc:  # a request line facet cannot follow: 400, one line
            self._say(f"refused a request it cannot read ({type(exc).__name__})")
            return connection.respond(400, "facet: bad request\n")

    def _respond(self, connection, request):
        from websockets.datastructures import Headers
        from websockets.http11 import Response

        if not self._names_us(request.headers.get("Host")):
            return connection.respond(403, "facet: the Host header does not name this "
                                      "server; open the URL 'facet view --serve' printed\n")
        url = urlsplit(request.path)
        token = parse_qs(url.query).get("token", [""])[0]
        if url.path == "/ws":
            origin = request.headers.get("Origin")
            if origin is not None and (urlsplit(origin).scheme not in ("http", "https") or
                                       not self._names_us(urlsplit(origin).netloc)):
                return connection.respond(403, "facet: a page of another site may not "
                                          "connect to this viewer\n")
            if not secrets.compare_digest(token, self.token):
                return connection.respond(403, "facet: wrong or missing token: open the URL "
                                          "'facet view --serve' printed\n")
            return None  # the WebSocket handshake goes on
        if url.path not in STATIC:
            return connection.respond(404, "facet: not found\n")
        if url.path == "/" and not secrets.compare_digest(token, self.token):
            return connection.respond(403, "facet: this viewer needs its token: open the URL "
                                      "'facet view --serve' printed (it ends in ?token=...)\n")
        name, mime = STATIC[url.path]
        body = (HERE / name).read_bytes()
        return Response(200, "OK", Headers({"Content-Type": mime,
                                            "Content-Length": str(len(body)),
                                            "Cache-Control": "no-store"}), body)

    # -- the WebSocket: events in, pictures out --------------------------------------------
    async def _handler(self, websocket) -> None:
        self.clients.add(websocket)
        self.worker.post({"type": "hello"})
        try:
            async for message in websocket:
                try:
                    event = checked(parse_json(message, "a message"))
                except InputError as exc:  # dropped with one line, the connection closed
                    self._say(f"dropped a page's message and closed its connection: {exc}")
                    await websocket.close(1008, "malformed message")
                    break
                self.worker.post(event)
        except Exception:  # a tab that went away mid-message: the others go on
            pass
        finally:
            self.clients.discard(websocket)
            self.worker.post({"type": "bye"})

    @staticmethod
    def _say(line: str) -> None:
        print(f"facet view: {line}", file=sys.stderr, flush=True)

    def _send(self, meta: dict, data: bytes) -> None:
        """From the worker thread: broadcast a picture to every tab."""
        text = json.dumps(meta)
        self.last = (text, data)
        self.loop.call_soon_threadsafe(self._broadcast, text, data)

    def _broadcast(self, text: str, data: bytes) -> None:
        for ws in list(self.clients):
            asyncio.ensure_future(self._send_to(ws, text, data))

    @staticmethod
    async def _send_to(ws, text: str, data: bytes) -> None:
        try:
            await ws.send(text)
            await ws.send(data)
        except Exception:  # closed meanwhile
            pass

    # -- running ---------------------------------------------------------------------------
    def url(self, host: str | None = None) -> str:
        host = host or self.host
        shown = f"[{host}]" if ":" in host else host
        return f"http://{shown}:{self.port}/?token={self.token}"

    async def _main(self, ready) -> int:
        try:
            from websockets.asyncio.server import serve
        except ImportError:
            raise InputError(NEEDS) from None
        from .worker import Worker

        self.loop = asyncio.get_running_loop()
        self.worker = Worker(self.make_session, self._send, self.quality)
        self.worker.start()
        await asyncio.to_thread(self.worker.ready.wait)
        if self.worker.failure is not None:
            raise self.worker.failure
        stop = self.loop.create_future()
        for sig in (signal.SIGINT, signal.SIGTERM):
            self.loop.add_signal_handler(
                sig, lambda s=sig: stop.done() or stop.set_result(s))
        try:
            async with serve(self._handler, self.host, self.port,
                             process_request=self._process_request, max_size=2 ** 16,
                             compression=None,
                             logger=logging.getLogger(LOGGER)) as server:
                self.port = next(iter(server.sockets)).getsockname()[1]
                ready(self)
                return await stop
        except OSError as exc:
            raise InputError(f"--serve: cannot listen on {self.host}:{self.port} "
                             f"({exc.strerror or exc}); pick another port (0: any free one)") \
                from None
        finally:
            self.worker.stop()
            await asyncio.to_thread(self.worker.join, 10)

    def run(self, ready=None) -> None:
        """Serve until SIGINT / SIGTERM; ``ready(server)`` is called once it listens. The
        signal that stopped it is raised again once all is shut down, to the handlers
        that were there before (the command line's: exit status 128 + the signal)."""
        before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
        with library_logs(LOGGER, "asyncio"):
            stopped_by = asyncio.run(self._main(ready or announce))
        for sig, handler in before.items():
            signal.signal(sig, handler)
        signal.raise_signal(stopped_by)


class OneLineLogs(logging.Handler):
    """Library log records (the WebSocket library's, asyncio's) as facet's one-line
    warnings, at most one line of a kind (logger and message) each ``every`` seconds: a
    ping flood or fifty pages gone at once is a line, not hundreds, and never a
    traceback (a record's exception is left out)."""

    def __init__(self, every: float = 60.0):
        super().__init__(logging.WARNING)
        self.every = every
        self._said: dict = {}

    def emit(self, record: logging.LogRecord) -> None:
        import time

        from ..errors import printable

        key, now = (record.name, str(record.msg)), time.monotonic()
        if now - self._said.get(key, -self.every) < self.every:
            return
        self._said[key] = now
        text = record.getMessage().strip().splitlines()
        print(f"facet view: warning: {printable(text[0] if text else record.name)} "
              f"({record.name.split('.')[-1]}; said at most once a minute)",
              file=sys.stderr, flush=True)


@contextlib.contextmanager
def library_logs(*names: str):
    """Within this block, the loggers ``names`` go through ``OneLineLogs`` only."""
    handler = OneLineLogs()
    saved = []
    for name in names:
        logger = logging.getLogger(name)
        saved.append((logger, logger.handlers[:], logger.propagate, logger.level))
        logger.handlers, logger.propagate = [handler], False
        logger.setLevel(logging.WARNING)
    try:
        yield
    finally:
        for logger, handlers, propagate, level in saved:
            logger.handlers, logger.propagate = handlers, propagate
            logger.setLevel(level)


def announce(server: Server) -> None:
    """Say where the page is, and how to reach it from another machine."""
    print(f"facet view: open {server.url()}", flush=True)
    if server.host in LOCAL:
        print(f"  from another machine: ssh -L {server.port}:127.0.0.1:{server.port} "
              f"USER@THIS-HOST, then open the URL above there", flush=True)
    else:
        print(f"facet view: warning: listening on {server.host}, beyond this machine: anyone "
              "with the URL (its token) can see and drive the view", file=sys.stderr,
              flush=True)
    print("  Ctrl-C stops it", flush=True)


def serve(source, address: str, **session_args) -> None:
    """Serve the viewer of ``source`` at ``address`` ([HOST:]PORT) until interrupted;
    ``session_args`` go to facet.viewing.session.Session."""
    host, port = parse_address(address)
    try:
        import websockets  # noqa: F401
    except ImportError:
        raise InputError(NEEDS) from None
    from ..viewing.session import Session

    Server(lambda: Session(source, **session_args), host, port).run()
