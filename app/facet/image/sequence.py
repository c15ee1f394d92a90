"""Writing frame sequences (GIF, MP4, numbered PNGs) on a background thread.

The render loop hands each finished frame to a ``BackgroundWriter`` and goes on rendering
while a worker thread encodes and writes (Pillow, ffmpeg and zlib release the GIL). The
queue is bounded, so a slow disk slows the loop down instead of filling memory. The first
error in the worker is raised again by ``close()``.

Sequence targets (``open_sequence``):
* ``spin.gif``: looping GIF through imageio/Pillow;
* ``spin.mp4``: H.264 through imageio-ffmpeg (its bundled ffmpeg binary);
* a pattern such as ``frames/{:04d}.png``: one PNG per frame.
GIF and MP4 are written to a temporary name and renamed when complete.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import queue
import re
import string
import threading
import time
from pathlib import Path

import numpy as np

from ..errors import InputError
from .writers import (
    FLOAT_FORMATS,
    IMAGE_FORMATS,
    save_float_color,
    save_image,
    temp_beside,
)

QUEUE_FRAMES = 8
PARENT_POLL = 0.25  # seconds between a writer process's checks that its parent lives
VIDEO_FORMATS = (".gif", ".mp4")


class BackgroundWriter:
    """Runs submitted callables in order on one worker thread."""

    def __init__(self, max_pending: int = QUEUE_FRAMES):
        self._queue: queue.Queue = queue.Queue(max_pending)
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name="facet-writer", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while True:
            job = self._queue.get()
            if job is None:
                return
            if self._error is None:
                try:
                    job[0](*job[1])
                except BaseException as exc:  # handed to the caller by close()
                    self._error = exc

    def submit(self, fn, *args) -> None:
        if self._error is not None:
            self.close()
        self._queue.put((fn, args))

    def close(self) -> None:
        """Wait for every job; raise the first error one of them hit."""
        if self._thread.is_alive():
            self._queue.put(None)
            self._thread.join()
        if self._error is not None:
            error, self._error = self._error, None
            raise error


class ProcessWriter:
    """Runs submitted picklable functions in a separate process (spawned, so the GL context
    and threads of this one are not copied). Used for per-frame dataset files: rendering
    holds the GIL while the driver works, so encoding in a thread of the same process would
    mostly wait for it. Results come back in submission order through ``results``; at most
    ``max_pending`` jobs are in flight, so a slow disk slows rendering instead of memory.

    The process is shared by every writer of this process and kept between sequences
    (``writer_process``): starting one costs about a third of a CPU-second (Python, numpy,
    Pillow), which a second turntable need not pay again, and ``prestart_writer`` lets a
    command start it while it is still loading the scene."""

    def __init__(self, max_pending: int = 2 * QUEUE_FRAMES, warm_up: str = "facet.image.outputs"):
        self._pool = writer_process(warm_up)
        self._pending: list = []
        self._max = max_pending
        self.results: list = []

    def submit(self, fn, *args) -> None:
        self._pending.append(self._pool.submit(fn, *args))
        while len(self._pending) > self._max:
            self.results.append(self._pending.pop(0).result())

    def close(self) -> None:
        """Wait for every job; raise the first error one of them hit (the jobs after it are
        cancelled where they have not started)."""
        try:
            while self._pending:
                self.results.append(self._pending.pop(0).result())
        finally:
            self.abort()

    def abort(self) -> None:
        """Cancel the jobs not started (a run stopped by Ctrl-C or an error); the one being
        written finishes, so no file is left half-written under its final name."""
        for future in self._pending:
            future.cancel()
        for future in self._pending:
            if not future.cancelled():
                with contextlib.suppress(BaseException):
                    future.result()
        self._pending.clear()


_WRITER: dict = {}  # "pool": the shared writer process (a ProcessPoolExecutor of one)
_WRITER_LOCK = threading.Lock()


def writer_process(warm_up: str = "facet.image.outputs"):
    """The shared writer process, started (and ``warm_up`` imported there) on first use or
    again after it broke; shut down when this process exits."""
    import atexit
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    with _WRITER_LOCK:
        pool = _WRITER.get("pool")
        if pool is None or getattr(pool, "_broken", False):
            pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"),
                                       initializer=_worker_start)
            pool.submit(_preload, warm_up)  # imports now, while this process goes on
            if "pool" not in _WRITER:
                atexit.register(_stop_writer)
            _WRITER["pool"] = pool
        return pool


def prestart_writer() -> None:
    """Start the writer process now (its start-up then overlaps loading a scene)."""
    writer_process()


def _stop_writer() -> None:
    pool = _WRITER.pop("pool", None)
    if pool is not None:
        pool.shutdown(wait=True, cancel_futures=True)


def _worker_start() -> None:
    """The writer process's set-up: it yields the CPU to rendering (on a machine whose cores
    a CPU rasteriser keeps busy, files are written in the gaps instead of slowing frames),
    leaves Ctrl-C to its parent (which shuts it down: no second traceback), and exits when
    its parent is gone, however the parent died (SIGKILL included), so no orphan keeps the
    caller's pipes open."""
    try:
        os.nice(10)
    except (AttributeError, OSError):  # not on every platform; a nicety, not a need
        pass
    watch_parent()


def watch_parent() -> None:
    """In a worker process: ignore Ctrl-C (the parent handles it and shuts workers down:
    no second traceback) and exit as soon as the parent is gone, however it died (SIGKILL
    included), so no orphan keeps the caller's pipes open."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    parent = os.getppid()

    def watch() -> None:
        while True:
            if os.getppid() != parent:  # re-parented: the parent is dead
                os._exit(1)
            time.sleep(PARENT_POLL)

    threading.Thread(target=watch, name="facet-parent-watch", daemon=True).start()


def _preload(module: str) -> None:
    """Import ``module`` in the writer process (its start-up then overlaps rendering)."""
    importlib.import_module(module)


def check_sequence_path(path) -> str:
    """'gif', 'mp4' or 'pattern' for a sequence target; InputError for anything else."""
    text = str(path)
    if Path(text).suffix.lower() in VIDEO_FORMATS:
        return Path(text).suffix.lower()[1:]
    if "{" in text:
        hint = f"{text}: a frame pattern takes one number, like frames/{{:04d}}.png"
        try:
            fields = [f for f in string.Formatter().parse(text) if f[1] is not None]
        except ValueError:
            raise InputError(hint) from None
        # One plain field ({} or {0}) with a short numeric format: nothing else is read
        # from the frame number (no attributes, items or huge widths).
        if len(fields) != 1 or fields[0][1] not in ("", "0") or fields[0][3] or \
                not re.fullmatch(r"0?\d{0,2}d?", fields[0][2] or ""):
            raise InputError(hint + " (at most two digits of width, e.g. {:06d})")
        names = {text.format(0), text.format(1)}
        if len(names) != 2 or Path(text.format(0)).suffix.lower() not in IMAGE_FORMATS:
            raise InputError(f"{text}: a frame pattern must number image files "
                             f"({', '.join(IMAGE_FORMATS)}), like frames/{{:04d}}.png")
        return "pattern"
    raise InputError(f"{text}: a sequence is written as .gif, .mp4 or a numbered image "
                     "pattern like frames/{:04d}.png (or .jpg, .webp, .tif, .exr, .hdr)")


class SequenceSink:
    """Receives frames (uint8 (H, W, 3|4)) in order and writes them on the writer thread."""

    def __init__(self, path, fps: float, writer: BackgroundWriter,
                 quality: int | None = None):
        self.path, self.kind, self.writer = str(path), check_sequence_path(path), writer
        self.fps, self.quality = fps, quality
        self._video = None
        self._tmp: str | None = None
        self.written: list[Path] = []

    def add(self, index: int, rgba: np.ndarray) -> None:
        self.writer.submit(self._write, index, rgba)

    def _write(self, index: int, rgba: np.ndarray) -> None:
        if self.kind == "pattern":  # (float frames for float formats: facet.image.writers)
            name = self.path.format(index)
            self.written.append(save_float_color(name, rgba) if Path(name).suffix.lower()
                                in FLOAT_FORMATS else save_image(name, rgba, self.quality))
            return
        if self._video is None:
            import imageio.v2 as iio

            target = Path(self.path)
            target.parent.mkdir(parents=True, exist_ok=True)
            self._tmp = temp_beside(target, target.suffix)
            if self.kind == "gif":
                self._video = iio.get_writer(self._tmp, format="GIF", mode="I", loop=0,
                                             duration=1000.0 / self.fps)
            else:
                self._video = iio.get_writer(self._tmp, format="FFMPEG", fps=self.fps,
                                             codec="libx264", quality=8, macro_block_size=2)
        self._video.append_data(np.ascontiguousarray(rgba[..., :3]))

    def finish(self) -> list[Path]:
        """Queue the final step (closing the video and renaming it into place)."""
        self.writer.submit(self._finish)
        return [Path(self.path)] if self.kind != "pattern" else self.written

    def _finish(self) -> None:
        if self._video is not None:
            self._video.close()
            os.chmod(self._tmp, 0o644)
            os.replace(self._tmp, self.path)
            self._video = None

    def abort(self) -> None:
        """Drop a half-written video (called when rendering fails)."""
        if self._video is not None:
            with contextlib.suppress(Exception):
                self._video.close()
        if self._tmp:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self._tmp)


def cameras_path(path) -> Path:
    """Where a sequence's cameras go: ``spin.json`` beside ``spin.gif``; for a pattern
    ``frames/{:04d}.png`` the name without its number fields plus ``cameras.json``
    (``frames/cameras.json``; ``out/f_{:03d}.png`` -> ``out/f_cameras.json``)."""
    import re

    p = Path(str(path))
    if check_sequence_path(path) != "pattern":
        return p.with_suffix(".json")
    stem = re.sub(r"\{[^}]*\}", "", p.stem)
    return p.parent / f"{stem}cameras.json"
