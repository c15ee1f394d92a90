"""The live shader window's preview size (facet.window.preview): the first frame at a
quarter size, then the size its measured cost allows (no GL: the rule alone)."""

import pytest

from facet.window.preview import FRAME_BUDGET, PreviewSize


def test_the_first_frame_is_a_quarter_of_the_window():
    p = PreviewSize()
    assert p.size((640, 360)) == (160, 90)
    assert p.size((3, 2)) == (1, 1)  # never empty
    assert p.status().startswith("first frame at 1/4 size")


@pytest.mark.parametrize("preview_seconds,divisor", [
    (0.001, 1),  # a full frame of 16 ms: the window's size
    (FRAME_BUDGET / 16 * 4 * 0.99, 2),  # a full frame 4x the budget, less a little
    (FRAME_BUDGET, 4),  # the preview itself meets the budget
    (4.0, 8),  # a minute a full frame: the smallest size
])
def test_an_animation_keeps_the_largest_size_that_meets_the_budget(preview_seconds, divisor):
    p = PreviewSize()
    p.measure(preview_seconds, animated=True)
    assert p.divisor == divisor
    assert p.full_cost == pytest.approx(preview_seconds * 16)
    if divisor > 1:
        assert p.status().startswith(f"drawn at 1/{divisor} size: a full-size frame takes")
    else:
        assert p.status() == ""
    assert not p.measure(0.0, animated=True)  # chosen once: buffers restart on a new size


def test_a_still_picture_refines_to_the_full_size_and_f_asks_for_it():
    p = PreviewSize()
    assert p.measure(3.0, animated=False)  # 48 s at full size: drawn once, all the same
    assert p.divisor == 1 and p.size((640, 360)) == (640, 360)
    q = PreviewSize()
    q.measure(4.0, animated=True)
    assert q.size((640, 360)) == (80, 45)
    assert "about 64.0 s" in q.status() and "f: full size" in q.status()
    q.toggle_full()
    assert q.size((640, 360)) == (640, 360) and q.status() == ""
    q.toggle_full()
    assert q.size((640, 360)) == (80, 45)
