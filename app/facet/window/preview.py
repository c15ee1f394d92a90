"""How much smaller than its window the live shader window draws (facet.window.shader): a
slow shader (a 4-buffer one on llvmpipe can take a minute a frame at full size) shows its
first frame drawn at a quarter of the width and height, so something is on screen in a
sixteenth of the time; that frame's measured cost then decides the size.

A still picture refines to the full size right after its preview. An animation keeps the
largest size whose frames take at most ``FRAME_BUDGET`` (1/15 s), down to an eighth; the
window's title says the size and what a full-size frame would take, and a key asks for
the full size anyway. Moving to another size starts the buffers again (a size is part of
what a feedback buffer holds), so the size is chosen once, not chased every frame.
"""

from __future__ import annotations

FIRST = 4  # the first frame: 1/4 of the window's width and height
DIVISORS = (1, 2, 4, 8)
FRAME_BUDGET = 1.0 / 15.0  # seconds an animated frame may take at the size kept


class PreviewSize:
    """The divisor of the window's size the shader draws at, from one measured frame."""

    def __init__(self):
        self.divisor = FIRST
        self.full_cost: float | None = None  # seconds a full-size frame takes (estimated)
        self.full = False  # asked for the full size whatever it costs
        self.measured = False

    def size(self, window: tuple[int, int]) -> tuple[int, int]:
        """The drawing size for a window of ``window`` pixels (at least 1 x 1)."""
        d = 1 if self.full else self.divisor
        return max(1, window[0] // d), max(1, window[1] // d)

    def measure(self, seconds: float, animated: bool) -> bool:
        """A frame drawn at the current divisor took ``seconds``; the first one decides the
        divisor (the full size for a still picture). Whether the divisor changed."""
        if self.measured or self.full:
            return False
        self.measured = True
        self.full_cost = seconds * self.divisor ** 2  # cost grows with the pixels
        old = self.divisor
        if not animated:
            self.divisor = 1
        else:
            self.divisor = next((d for d in DIVISORS
                                 if self.full_cost / d ** 2 <= FRAME_BUDGET), DIVISORS[-1])
        return self.divisor != old

    def toggle_full(self) -> None:
        """The full size whatever a frame costs, or back to the measured size."""
        self.full = not self.full

    def status(self) -> str:
        """A phrase for the title: empty at the full size."""
        if self.full or self.divisor == 1:
            return ""
        cost = "" if self.full_cost is None else \
            f": a full-size frame takes about {_seconds(self.full_cost)}"
        what = "first frame" if not self.measured else "drawn"
        return f"{what} at 1/{self.divisor} size{cost} (f: full size)"


def _seconds(value: float) -> str:
    return f"{value * 1000:.0f} ms" if value < 1 else f"{value:.1f} s"
