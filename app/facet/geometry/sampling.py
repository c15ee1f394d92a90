"""Sample patterns over a pixel (notes §2.8-2.10), numpy only, seeded and deterministic.

Each function returns ``n`` offsets, (n, 2) float64 in [-0.5, 0.5)^2 pixel units (x right,
y down, the pixel centre at (0, 0)). They are reused for anti-aliasing, soft shadows, depth
of field and motion blur.

* ``grid``: the centres of a k x k grid of sub-pixels (n must be a square number).
* ``random``: n uniform random points.
* ``poisson``: random points at least ``eps`` apart (dart throwing). For n points in the unit
  square the densest packing (hexagonal) has spacing d_hex = sqrt(2 / (sqrt(3) n)); facet uses
  eps = POISSON_FRACTION x d_hex, a spacing dart throwing reaches quickly while keeping the
  points well spread.
* ``jittered``: one random point in each cell of a k x k grid (n square), or of an r x c grid
  with r * c = n as close to square as possible.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..errors import InputError

PATTERNS = ("grid", "random", "poisson", "jittered")
MAX_SAMPLES = 4096  # larger counts are refused (facet.options.values.parse_aa)
POISSON_FRACTION = 0.7
POISSON_ATTEMPTS = 200  # darts per accepted point before giving up on eps and shrinking it


def _check(n) -> int:
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 1:
        raise InputError(f"sample count must be an integer >= 1, got {n!r}")
    return int(n)


def _factor(n: int) -> tuple[int, int]:
    """rows, cols with rows * cols = n and rows as close to sqrt(n) as possible."""
    rows = int(math.isqrt(n))
    while n % rows:
        rows -= 1
    return rows, n // rows


def grid(n: int) -> np.ndarray:
    n = _check(n)
    k = math.isqrt(n)
    if k * k != n:
        raise InputError(f"a grid pattern needs a square number of samples (4, 9, 16, ...), "
                         f"got {n}")
    c = (np.arange(k) + 0.5) / k - 0.5
    x, y = np.meshgrid(c, c)
    return np.stack([x.ravel(), y.ravel()], axis=1)


def random(n: int, seed: int = 0) -> np.ndarray:
    n = _check(n)
    return np.random.default_rng(seed).random((n, 2)) - 0.5


def poisson_eps(n: int) -> float:
    """The minimum distance the Poisson pattern aims for with n points (module docstring)."""
    return POISSON_FRACTION * math.sqrt(2.0 / (math.sqrt(3.0) * n))


def poisson(n: int, seed: int = 0) -> np.ndarray:
    n = _check(n)
    rng = np.random.default_rng(seed)
    eps = poisson_eps(n)
    points = np.empty((0, 2))
    while len(points) < n:
        for _ in range(POISSON_ATTEMPTS):
            # Darts in batches: vectorised distance tests against the accepted points.
            darts = rng.random((32, 2)) - 0.5
            for d in darts:
                if len(points) == 0 or np.min(np.sum((points - d) ** 2, axis=1)) >= eps * eps:
                    points = np.vstack([points, d])
                    if len(points) == n:
                        return points
        eps *= 0.9  # rare: the square is full at this spacing; relax it a little
    return points


def jittered(n: int, seed: int = 0) -> np.ndarray:
    n = _check(n)
    rows, cols = _factor(n)
    rng = np.random.default_rng(seed)
    i, j = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    x = (j.ravel() + rng.random(n)) / cols - 0.5
    y = (i.ravel() + rng.random(n)) / rows - 0.5
    return np.stack([x, y], axis=1)


@functools.lru_cache(maxsize=64)
def pattern(name: str, n: int, seed: int = 0) -> np.ndarray:
    """The named pattern (``PATTERNS``), computed once per (name, n, seed): read-only."""
    makers = {"grid": lambda: grid(n), "random": lambda: random(n, seed),
              "poisson": lambda: poisson(n, seed), "jittered": lambda: jittered(n, seed)}
    if name not in makers:
        raise InputError(f"unknown sample pattern {name!r}; choose one of "
                         f"{', '.join(PATTERNS)}")
    points = makers[name]()
    points.setflags(write=False)
    return points
