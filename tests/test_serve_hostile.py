"""``facet view --serve`` against hostile pages and inputs: --confine holds (a model, a scene
naming a file outside, a symbolic link leading out, a served file replaced by one and
reloaded); Host and Origin are checked against the address it serves; malformed messages
are dropped with one line and never stop the render thread; a shader that fails shows its
error in the page's status line; an unreadable request line and a ping flood leave no
traceback; SIGTERM exits 143. Servers bind 127.0.0.1 and are stopped by the tests."""

from __future__ import annotations

import asyncio
import json
import os
import shutil
import socket
import subprocess
import urllib.request

import pytest

from test_serve import FACET, MODEL, Served, _status, watch

pytest.importorskip("websockets", reason="the serve extra (websockets) is not installed")


async def _picture(url, *, origin=None, first=(), timeout=60):
    """Connect, send ``first`` and a resize, and return the first picture's meta."""
    from websockets.asyncio.client import connect

    headers = {"Origin": origin} if origin else None
    async with connect(url, additional_headers=headers, origin=None) as ws:
        for message in first:
            await ws.send(message)
        await ws.send(json.dumps({"type": "resize", "width": 32, "height": 24}))
        while True:
            meta = json.loads(await asyncio.wait_for(ws.recv(), timeout))
            await asyncio.wait_for(ws.recv(), timeout)
            await ws.send(json.dumps({"type": "frame_feedback", "index": meta["index"]}))
            return meta


def _facet_lines_only(err: str) -> None:
    assert "Traceback" not in err and "Exception in thread" not in err, err
    assert all(line.startswith(("facet", "  ")) for line in err.splitlines() if line), err


def test_confine_holds_for_every_file_the_served_viewer_reads(tmp_path):
    inside = tmp_path / "in"
    inside.mkdir()
    hidden = tmp_path / "hidden.obj"
    shutil.copy(MODEL, hidden)
    (inside / "link.obj").symlink_to(hidden)
    (inside / "scene.toml").write_text(f'[[objects]]\nmesh = "{hidden}"\n')
    for model in (hidden, inside / "link.obj", inside / "scene.toml"):
        done = subprocess.run([*FACET, "view", str(model), "--serve", "127.0.0.1:0",
                               "--confine", str(inside)], capture_output=True, text=True,
                              timeout=60)
        assert done.returncode == 2, done.stderr
        assert "outside the confinement folder" in done.stderr
        assert len(done.stderr.strip().splitlines()) == 1, done.stderr


def test_a_served_file_replaced_by_a_link_leading_out_is_not_reloaded(tmp_path):
    import trimesh

    inside = tmp_path / "in"
    inside.mkdir()
    served = inside / "model.ply"
    trimesh.creation.box().export(served)
    trimesh.creation.icosphere(subdivisions=3).export(tmp_path / "hidden.ply")

    replaced = []

    async def react(meta, pixels, ws):
        if meta["state"]["error"] or meta["state"]["triangles"] == 1280:
            return meta["status"]
        if meta["lossless"] and not replaced:
            served.unlink()
            served.symlink_to(tmp_path / "hidden.ply")
            replaced.append(True)
            await ws.send(json.dumps({"type": "key_down", "key": "o"}))
        return None

    with Served("--confine", str(inside), model=str(served)) as s:
        status = asyncio.run(watch(s.ws, (32, 24), react))
    assert "outside the confinement folder" in status and "12 triangles" in status, status


def test_host_and_origin_are_checked_against_the_served_address(tmp_path):
    with Served() as s:
        port = s.url.split(":")[2].split("/")[0]
        good = urllib.request.Request(s.url, headers={"Host": f"localhost:{port}"})
        assert _status(good) == 200
        for host in (f"rebound.example.com:{port}", "127.0.0.1:1", "", "[::1",
                     f"evil.example@127.0.0.1:{port}", f"203.0.113.7:{port}",
                     f"127.0.0.1:{port}/x", f"127.0.0.1:{port}?x"):
            assert _status(urllib.request.Request(
                s.url, headers={"Host": host})) == 403, host
        meta = asyncio.run(_picture(s.ws, origin=f"http://127.0.0.1:{port}"))
        assert meta["type"] == "frame"
        for origin in ("https://evil.example.com", f"http://evil.example.com:{port}",
                       "null", f"http://203.0.113.7:{port}", f"http://10.0.0.1:{port}",
                       f"http://evil.example@127.0.0.1:{port}"):
            with pytest.raises(Exception, match="403"):
                asyncio.run(_picture(s.ws, origin=origin))
        s.stop()
        _facet_lines_only(s.proc.stderr.read())


BAD = [json.dumps(e) for e in (
    {"type": "pointer_move", "x": "a", "y": 0}, {"type": "pointer_down", "x": [1], "y": 0},
    {"type": "pointer_down", "x": None, "y": 0}, {"type": "wheel", "dy": 1e308},
    {"type": "resize", "width": "wide", "height": 10}, {"type": "pointer_down",
                                                        "modifiers": 3},
    {"type": "frame_feedback", "index": "x"}, {"type": "frame_feedback", "index": 1e300},
    {"type": "key_down", "key": None}, [1, 2], None, "text", {"type": 7})] + [
    '{"type": "pointer_move", "x": NaN, "y": 0}', '{"type": "wheel", "dy": Infinity}',
    "not json", "[" * 5000]


def test_malformed_messages_are_dropped_and_the_render_thread_lives_on():
    with Served() as s:
        for message in BAD:
            try:
                asyncio.run(_picture(s.ws, first=[message], timeout=20))
            except Exception:
                pass  # the server may close a connection that sent garbage
            meta = asyncio.run(_picture(s.ws))  # a new page still gets pictures
            assert meta["type"] == "frame", message
        # A camera dragged and zoomed to the extremes stays finite and drawn.
        extremes = [json.dumps(e) for e in (
            {"type": "pointer_down", "x": 0, "y": 0, "button": 1},
            {"type": "pointer_move", "x": 1e6, "y": -1e6}, {"type": "pointer_up"},
            *[{"type": "wheel", "dy": 1e6, "x": 1e6, "y": 1e6}] * 40)]
        meta = asyncio.run(_picture(s.ws, first=extremes))
        assert meta["type"] == "frame"
        s.stop()
        err = s.proc.stderr.read()
    _facet_lines_only(err)
    assert err.count("dropped") >= len(BAD) - 1, err


def test_a_shader_that_fails_shows_its_error_in_the_page(tmp_path):
    bad = tmp_path / "bad.frag"
    bad.write_text("#version 330\nout vec4 frag;\nvoid main() { frag = vec4(nothing); }\n")
    with Served("--frag", str(bad)) as s:
        meta = asyncio.run(_picture(s.ws))
        assert "error:" in meta["status"] and "nothing" in meta["status"], meta["status"]
        s.stop()
        _facet_lines_only(s.proc.stderr.read())


def test_a_viewer_started_on_a_broken_shader_draws_once_it_is_fixed(tmp_path):
    """Started with a shader that does not compile: the error shows, the render thread
    lives on past the lossless picture (it once died sending a picture that was never
    drawn), and the fixed file is drawn."""
    shader = tmp_path / "s.frag"
    shader.write_text("#version 330\nout vec4 frag;\nvoid main() { frag = vec4(nothing); }\n")

    async def until_drawn(url):
        from websockets.asyncio.client import connect

        async with connect(url) as ws:
            await ws.send(json.dumps({"type": "resize", "width": 32, "height": 24}))
            fixed = False
            while True:
                meta = json.loads(await asyncio.wait_for(ws.recv(), 60))
                await asyncio.wait_for(ws.recv(), 60)
                await ws.send(json.dumps({"type": "frame_feedback", "index": meta["index"]}))
                if "error:" in meta["status"]:
                    if meta["lossless"] and not fixed:  # past the lossless picture
                        shader.write_text("#version 330\nout vec4 frag;\n"
                                          "void main() { frag = vec4(1.0, 0.0, 0.0, 1.0); }\n")
                        fixed = True
                elif fixed:
                    return meta

    with Served("--frag", str(shader)) as s:
        meta = asyncio.run(asyncio.wait_for(until_drawn(s.ws), 120))
        assert meta["type"] == "frame" and "error" not in meta["status"], meta
        s.stop()
        _facet_lines_only(s.proc.stderr.read().replace("shaders reloaded\n", ""))


def test_a_fifo_named_as_a_model_is_refused_by_the_served_viewer(tmp_path):
    fifo = tmp_path / "cloud.ply"
    os.mkfifo(fifo)
    run = subprocess.run([*FACET, "view", str(fifo), "--serve", "127.0.0.1:0"],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "FIFO" in run.stderr, run.stderr
    _facet_lines_only(run.stderr)


def test_library_logs_are_one_line_a_kind_a_minute(capsys):
    """asyncio's and the WebSocket library's records (a ping flood's "socket.send() raised
    exception.", hundreds of times) are one facet line per kind per minute."""
    import logging

    from facet.serve.server import LOGGER, library_logs

    with library_logs(LOGGER, "asyncio"):
        for _ in range(300):
            logging.getLogger("asyncio").warning("socket.send() raised exception.")
            try:
                raise ConnectionResetError("gone")
            except ConnectionResetError:
                logging.getLogger(LOGGER).error("connection handler failed", exc_info=True)
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 2, err
    assert all(line.startswith("facet view: warning: ") for line in lines), err
    assert "socket.send() raised exception." in lines[0] and "Traceback" not in err


def test_an_unreadable_request_and_a_ping_flood_leave_no_traceback():
    with Served() as s:
        port = int(s.url.split(":")[2].split("/")[0])
        for line in (b"GET http://[ HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n",
                     b"GET /?token=%zz%00 HTTP/1.1\r\n\r\n", b"\x16\x03\x01garbage\r\n\r\n"):
            with socket.create_connection(("127.0.0.1", port), timeout=10) as c:
                c.sendall(line)
                try:
                    c.recv(1024)
                except OSError:
                    pass

        async def flood():
            from websockets.asyncio.client import connect

            async with connect(s.ws) as ws:
                for _ in range(2000):
                    await ws.ping()  # not waiting for the pongs
                await ws.send(json.dumps({"type": "resize", "width": 16, "height": 16}))

        asyncio.run(flood())
        assert asyncio.run(_picture(s.ws))["type"] == "frame"
        s.stop()
        _facet_lines_only(s.proc.stderr.read())


def test_sigterm_stops_the_server_with_exit_status_143():
    with Served() as s:
        assert s.stop() == 143
