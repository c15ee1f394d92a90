"""Validation helpers for scene files: each check raises ``SceneError`` naming the file,
the key path and what was expected (``scene.toml: objects[2].radius: expected a number > 0,
got 0``); unknown keys get a did-you-mean."""

from __future__ import annotations

import difflib
from pathlib import Path

import numpy as np

from ..errors import SceneError
from ..options.values import number_problem


def show(value) -> str:
    return f'"{value}"' if isinstance(value, str) else repr(value)


class Reader:
    """Validation helpers that raise ``SceneError`` with file and key path."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, where: str, message: str):
        raise SceneError(f"{self.path.name}: {where}: {message}" if where else
                         f"{self.path.name}: {message}")

    def table(self, value, where: str, allowed) -> dict:
        if not isinstance(value, dict):
            self.fail(where, f"expected a table, got {show(value)}")
        for key in value:
            if key not in allowed:
                close = difflib.get_close_matches(key, list(allowed), n=1)
                hint = f"; did you mean '{close[0]}'?" if close else \
                    f"; expected one of {', '.join(allowed)}"
                self.fail(f"{where}.{key}" if where else key, f"unknown key{hint}")
        return value

    def number(self, value, where: str, minimum=None, above=None) -> float:
        problem = number_problem(value, minimum, above)
        if problem:
            self.fail(where, f"{problem}, got {show(value)}")
        return float(value)

    def vector(self, value, where: str, n: int = 3) -> np.ndarray:
        if not (isinstance(value, list) and len(value) == n):
            self.fail(where, f"expected {n} numbers, got {show(value)}")
        return np.array([self.number(v, f"{where}[{i}]") for i, v in enumerate(value)])

    def matrix(self, value, where: str) -> np.ndarray:
        if not (isinstance(value, list) and len(value) == 4):
            self.fail(where, f"expected a 4x4 matrix (4 rows of 4 numbers), got {show(value)}")
        return np.array([self.vector(row, f"{where}[{i}]", 4) for i, row in enumerate(value)])

    def color(self, value, where: str, channels=(3,)) -> np.ndarray:
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            value = [value] * 3
        n = len(value) if isinstance(value, list) and len(value) in channels else channels[0]
        c = self.vector(value, where, n)
        if c.min() < 0 or c.max() > 1:
            self.fail(where, f"expected colour values in [0, 1], got {show(value)}")
        return c

    def string(self, value, where: str) -> str:
        if not isinstance(value, str) or not value:
            self.fail(where, f"expected a non-empty string, got {show(value)}")
        return value

    def choice(self, value, where: str, options) -> str:
        self.string(value, where)
        if value not in options:
            close = difflib.get_close_matches(value, list(options), n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            self.fail(where, f"expected one of {', '.join(options)}, got {show(value)}{hint}")
        return value

    def integer(self, value, where: str, minimum: int = 1) -> int:
        if not isinstance(value, int) or isinstance(value, bool) or value < minimum:
            self.fail(where, f"expected an integer >= {minimum}, got {show(value)}")
        return value


class AnyKey(tuple):
    """Allows any key (named tables such as [materials.NAME])."""

    def __contains__(self, key) -> bool:
        return True
