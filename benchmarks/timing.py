"""The benchmarks' one timer: the median wall time of a call over some runs."""

from __future__ import annotations

import statistics
import time


def median_time(fn, runs: int = 3) -> float:
    """Median seconds of ``fn()`` over ``runs`` calls."""
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)
