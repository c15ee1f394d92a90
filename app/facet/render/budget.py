"""When a sum of supersamples stops (facet.render.sequence's accumulation): after its
paths per pixel, at a time limit, when the caller asks (a progress callback that returns
False: the command line's SIGINT / SIGTERM), or pixel by pixel when its noise is low
enough (adaptive sampling, as Cycles' noise threshold).

Adaptive sampling estimates each pixel's error from its own samples: they come in rounds
of ROUND, and the spread of a pixel's round means (batch means) gives the standard error
of its mean. A pixel stops when that error, over its mean luminance (or over DARK for a
pixel darker than that), is below the threshold, once it has MIN_ADAPTIVE paths and its
eight neighbours have stopped too (a lone pixel whose first rounds all missed a small
light would otherwise stop black). Stopped pixels are skipped by the path tracer's shader
(a mask texture; their sample is 0) and each pixel's sum is divided by its own count.

The caller syncs with the GPU after each sample (or each strip of one: a sample that takes
long is drawn in strips), so a stop is heard within a strip's time, not at the end of
the whole sum.
"""

from __future__ import annotations

import math
import time

import numpy as np

ROUND = 4  # samples between two looks at the noise
MIN_ADAPTIVE = 16  # paths every pixel gets before it may stop
DARK = 0.01  # linear luminance under which the error is taken as absolute
STRIP_SECONDS = 0.4  # a sample that takes longer is drawn in strips of about this
LUMINANCE = np.array([0.2126, 0.7152, 0.0722], np.float32)


class SampleBudget:
    """The stopping rule of one sum (module docstring).

    Parameters
    ----------
    ctx : moderngl.Context
    size : (int, int)
        (width, height).
    noise : float or None
        The relative error at which a pixel stops; None: no adaptive sampling.
    time_limit : float or None
        Seconds the sum may take; None: none.
    progress : callable or None
        ``progress(done, total, seconds) -> bool``, called after each sample and each
        strip of one; False stops (a sample stopped halfway is dropped).
    masked : bool
        Stopped pixels are skipped (the mask texture); False: every pixel goes on being
        drawn and the noise only says when the whole picture is done (a still view,
        whose sum is shown as it grows: facet.render.sequence).
    """

    def __init__(self, ctx, size, noise=None, time_limit=None, progress=None,
                 masked: bool = True):
        self.ctx, self.size = ctx, size
        self.noise, self.progress = noise, progress
        self.start = time.monotonic()
        self.deadline = None if time_limit is None else self.start + time_limit
        self.synced = noise is not None or time_limit is not None or progress is not None
        self.done = 0  # samples added
        self.stopped = False  # by the caller (progress returned False)
        self.sample_seconds = 0.0
        w, h = size
        self._count = np.zeros((h, w), np.float32) if noise is not None else None
        self._stats = None  # (rounds, sum of round means, sum of their squares)
        self._last = None  # the sum at the last look
        self.mask = None  # the active pixels' texture (R8: 255 active), adaptive only
        self.masked = masked

    @property
    def adaptive(self) -> bool:
        return self.noise is not None

    def strips(self) -> int:
        """How many strips the next sample is drawn in (1 unless one takes long)."""
        if not self.synced or self.sample_seconds <= STRIP_SECONDS:
            return 1
        return min(self.size[1], math.ceil(self.sample_seconds / STRIP_SECONDS))

    def go_on(self, total: int = 0) -> bool:
        """Whether another strip or sample may start (the caller has synced)."""
        if not self.stopped and self.progress is not None and total and \
                self.progress(self.done, total, time.monotonic() - self.start) is False:
            self.stopped = True
        if self.stopped:
            return False
        if self.deadline is not None and self.done > 0 and \
                time.monotonic() + self.sample_seconds > self.deadline:
            return False
        return True

    def added(self, total: int, seconds: float, accum_tex, n: int = 1) -> bool:
        """``n`` samples were added (taking ``seconds``; more than one only where nothing
        watches sample by sample: a mosaic, facet.render.sequence); False: stop here."""
        self.done += n
        self.sample_seconds = seconds / n
        if self.adaptive:
            self._count += self._active_now
            if self.done % ROUND == 0 and not self._look(accum_tex):
                return False
        if self.progress is not None and \
                self.progress(self.done, total, time.monotonic() - self.start) is False:
            self.stopped = True
            return False
        return self.go_on()

    # -- adaptive sampling -----------------------------------------------------------------
    def begin(self) -> None:
        """Before the first sample: every pixel active."""
        if self.adaptive:
            w, h = self.size
            self._active_now = np.ones((h, w), np.float32)
            if not self.masked:
                return
            self.mask = self.ctx.texture((w, h), 1, np.full((h, w), 255, np.uint8).tobytes())
            self.mask.filter = (self.ctx.NEAREST, self.ctx.NEAREST)

    def _look(self, accum_tex) -> bool:
        """Round statistics from the sum, and the mask of pixels that go on; False when
        none does."""
        w, h = self.size
        total = np.frombuffer(accum_tex.read(), np.float32).reshape(h, w, 4)[..., :3]
        luma = total @ LUMINANCE
        last = self._last if self._last is not None else np.zeros_like(luma)
        self._last = luma
        live = self._active_now > 0
        mean = (luma - last) / ROUND  # this round's mean, where the pixel was active
        if self._stats is None:
            self._stats = [np.zeros_like(luma) for _ in range(3)]
        n, s, s2 = self._stats
        n += live
        s += np.where(live, mean, 0.0)
        s2 += np.where(live, mean * mean, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            avg = s / np.maximum(n, 1)
            var = np.maximum(s2 - n * avg * avg, 0.0) / np.maximum(n - 1, 1)
            error = np.sqrt(var / np.maximum(n, 1)) / np.maximum(avg, DARK)
        go_on = (error >= self.noise) | (self._count < MIN_ADAPTIVE)
        go_on = _dilated(go_on) & live  # a stopped pixel never restarts
        self._active_now = go_on.astype(np.float32)
        if self.mask is None:  # (unmasked: every pixel is drawn on)
            return bool(go_on.any())
        # (the sum is read back as it lies, row 0 first: the mask lies the same way)
        self.mask.write(np.where(go_on, 255, 0).astype(np.uint8).tobytes())
        return bool(go_on.any())

    def counts(self) -> np.ndarray:
        """(H, W) float32 paths per pixel, rows as the sum lies (offscreen: row 0 at the
        top)."""
        w, h = self.size
        if self._count is not None:
            return self._count.copy()
        return np.full((h, w), float(self.done), np.float32)

    def even_out(self, accum_tex) -> None:
        """Each pixel's sum scaled to ``done`` samples' worth (adaptive pixels have fewer),
        so dividing by ``done`` gives every pixel its own mean."""
        if not self.adaptive or self.done == 0:
            return
        w, h = self.size
        total = np.frombuffer(accum_tex.read(), np.float32).reshape(h, w, 4).copy()
        total *= (self.done / np.maximum(self._count, 1))[..., None]
        accum_tex.write(total.tobytes())

    def release(self) -> None:
        if self.mask is not None:
            self.mask.release()
            self.mask = None


def _dilated(mask: np.ndarray) -> np.ndarray:
    """``mask`` or any of its eight neighbours."""
    out = mask.copy()
    out[1:] |= mask[:-1]
    out[:-1] |= mask[1:]
    rows = out.copy()
    out[:, 1:] |= rows[:, :-1]
    out[:, :-1] |= rows[:, 1:]
    return out
