"""Where a render goes and what it needs of the image size.

``Destination``: offscreen (drawn upside down so readback lands row 0 on top, facet.gl.
targets; every channel read back) or a window's framebuffer (bottom-up like GL, colour only,
supersamples added one per frame while the view is still). ``Surfaces``: the targets and
supersampling buffers of one image size, and any engine's own buffers of that size (the
rasterizer's OIT sums), made on first use and replaced together when the size changes.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..gl.targets import Targets
from ..options.render import RenderOptions
from .antialias import Accumulator


class Surfaces:
    """What depends on the image size: the targets, the supersampling buffers and an
    engine's own (``part``), each made on first use."""

    def __init__(self, ctx, size: tuple[int, int]):
        self.ctx, self.size = ctx, size
        self.targets = Targets(ctx, *size)
        self._accumulator = None
        self._parts: dict[str, object] = {}

    @property
    def accumulator(self) -> Accumulator:
        if self._accumulator is None:
            self._accumulator = Accumulator(self.ctx, *self.size)
        return self._accumulator

    def part(self, name: str, make):
        """An engine's buffers of this size called ``name``: ``make(ctx, width, height)``
        the first time (an object with ``release()``), released with the rest."""
        if name not in self._parts:
            self._parts[name] = make(self.ctx, *self.size)
        return self._parts[name]

    def release(self) -> None:
        for part in (self._accumulator, *self._parts.values(), self.targets):
            if part is not None:
                part.release()


@dataclass(frozen=True)
class Destination:
    """Where a sequence ends: offscreen (``window`` None: drawn flipped, read back) or a
    window's framebuffer, adding progressive supersample ``sample`` (None: one picture)."""

    window: object = None
    sample: int | None = None

    @property
    def flip_y(self) -> bool:
        return self.window is None

    @property
    def preview(self) -> bool:
        """One plain picture in a window (what a moving camera shows)."""
        return self.window is not None and self.sample is None

    def channels(self, opts: RenderOptions) -> tuple[str, ...]:
        """The exact channels to read back (a window shows colour only; the paths per
        pixel are counted, not drawn)."""
        return () if self.window is not None else \
            tuple(o for o in opts.outputs if o not in ("color", "spp"))

    def wants_colour(self, opts: RenderOptions) -> bool:
        return self.window is not None or "color" in opts.outputs

    def samples(self, n: int) -> range:
        """Which of ``n`` supersamples to draw now: all offscreen, one more in a window
        (none once all n are in: the sum is shown as it is; adding the last one again
        would weigh it twice)."""
        if self.window is None:
            return range(n)
        if self.sample is not None and self.sample >= n:
            return range(n, n)
        k = 0 if self.sample is None else self.sample  # a preview: one
        return range(k, k + 1)
