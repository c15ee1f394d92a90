"""The public API's one boundary check (no GL; numpy only when an array is checked).

A public function, method or class says what it takes in its signature, and ``@checked``
holds every call to it: each argument given (a default is not checked again) must be of
its annotated type, checked by beartype (``beartype.door.is_bearable``; numbers by the
PEP 484 tower: an ``int`` or a numpy scalar is a fine ``Real``), and must pass the value
checks declared beside the type with ``typing.Annotated``::

    @checked
    def sky(size: Annotated[int, Count(1, per_pixels=6)] = 128): ...

    Vec3 = Annotated[object, Array("3")]          # three finite numbers

The checks are facet's (``Array``: real numbers, finite, of a shape, within the element
budget, looked at before anything is allocated for them; ``Number``; ``Count``; ``PathArg``).
A refusal is one ``ArgumentError`` (an ``InputError`` and a ``TypeError``: code that
catches either keeps working) for a wrong type, or an ``InputError`` (a ``ValueError``)
for a wrong value, and names the callable, the argument, what was expected and what was
given: ``Splats: means: expected (N, 3) finite real numbers, got shape (4,)``.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers
import os
import re
import typing
from collections.abc import Sequence
from typing import Annotated

from .errors import InputError

SMALL = 1 << 16  # numbers below every budget: no budget is looked up for fewer


class ArgumentError(InputError, TypeError):
    """An argument of the wrong type given to facet's API (a ``TypeError`` as well as an
    ``InputError``)."""


class Check:
    """A value check declared in ``Annotated`` metadata: ``check(value, where)`` raises
    InputError naming ``where`` (the callable and the argument) when ``value`` is wrong."""

    expected = "a valid value"

    def __call__(self, value, where: str) -> None:  # pragma: no cover - subclasses
        raise NotImplementedError

    def fail(self, where: str, given: str, error=InputError):
        raise error(f"{where}: expected {self.expected}, got {given}")


def given(value) -> str:
    """A short description of ``value`` for an error message."""
    if value is None:
        return "None"
    shape = getattr(value, "shape", None)
    if shape is not None and hasattr(value, "dtype"):
        return f"an array of shape {tuple(shape)} and dtype {value.dtype}"
    if isinstance(value, (bool, numbers.Number)):
        return repr(value)
    if isinstance(value, (str, bytes)):
        text = repr(value)
        return text if len(text) <= 60 else text[:57] + "..."
    if isinstance(value, (list, tuple)):
        return f"a {type(value).__name__} of {len(value)} items"
    return f"a {type(value).__name__}"


class Array(Check):
    """Real numbers (not complex, not objects or text) of one of ``shapes`` (strings such
    as ``"N,3"``: a letter is any length, the same letter the same length; a digit that
    length), finite unless ``finite=False``, with at most the element budget of numbers
    (``budget``: its name in facet.budgets) and at least ``rows`` rows."""

    def __init__(self, *shapes: str, finite: bool = True, budget: str = "elements",
                 unit: int = 1, rows: int = 0, what: str = "real numbers"):
        self.shapes = [tuple(s.replace(" ", "").split(",")) if s else () for s in shapes]
        self.finite, self.budget, self.unit, self.rows = finite, budget, unit, rows
        shown = " or ".join(f"({s[0]},)" if len(s) == 1 else f"({', '.join(s)})" if s else
                            "a scalar" for s in self.shapes)
        self.expected = f"{shown} {'finite ' if finite else ''}{what}".strip()

    def _fits(self, shape: tuple) -> bool:
        if not self.shapes:
            return True
        for pattern in self.shapes:
            if len(pattern) != len(shape):
                continue
            bound: dict = {}
            if all(int(p) == n if p.isdigit() else bound.setdefault(p, n) == n
                   for p, n in zip(pattern, shape, strict=True)):
                return True
        return False

    def _within(self, size: int, where: str) -> None:
        if size <= SMALL:  # below every budget: no lookup
            return
        from .budgets import budget

        limit, count = budget(self.budget), size // self.unit
        if count > limit:
            noun = "pixels" if self.budget == "pixels" else "numbers"
            raise InputError(f"{where}: expected at most {limit:,} {noun} (facet's budget; "
                             f"--budget {self.budget}=N), got {count:,}")

    def __call__(self, value, where: str) -> None:
        import numpy as np

        if isinstance(value, np.ndarray):  # the common case, without a copy
            self._within(value.size, where)  # size first: a broadcast view
            array = value
        else:
            if value is None or isinstance(value, (str, bytes, dict, set)):
                self.fail(where, given(value), ArgumentError)
            shape = getattr(value, "shape", None)
            if shape is not None and hasattr(value, "dtype"):
                self._within(math.prod(int(n) for n in shape), where)
            try:
                array = np.asarray(value)
            except (ValueError, TypeError):
                self.fail(where, f"a ragged or mixed {type(value).__name__}", ArgumentError)
            self._within(array.size, where)
        kind = array.dtype.kind
        if kind not in "biuf":
            self.fail(where, given(array), ArgumentError)
        if not self._fits(array.shape):
            self.fail(where, f"shape {array.shape}")
        if self.rows and array.ndim and array.shape[0] < self.rows:
            self.fail(where, f"{array.shape[0]} rows (at least {self.rows} needed)")
        if self.finite and kind == "f" and not np.isfinite(array).all():
            bad = ~np.isfinite(array.reshape(len(array), -1) if array.ndim else array)
            rows = bad.any(axis=1) if bad.ndim == 2 else bad
            place = "row" if array.ndim > 1 else "index"
            first = f" (the first at {place} {int(np.argmax(rows))})" if array.ndim else ""
            self.fail(where, f"{int(np.count_nonzero(bad))} values that are NaN or "
                      f"infinite, not finite{first}")


class Number(Check):
    """A finite real number within [lo, hi] (either bound open when ``open_lo`` /
    ``open_hi``; None: unbounded)."""

    def __init__(self, lo=None, hi=None, *, open_lo: bool = False, open_hi: bool = False,
                 finite: bool = True):
        self.lo, self.hi, self.open_lo, self.open_hi = lo, hi, open_lo, open_hi
        self.finite = finite
        left = "" if lo is None else f"{'>' if open_lo else '>='} {lo:g}"
        right = "" if hi is None else f"{'<' if open_hi else '<='} {hi:g}"
        self.expected = "a finite number" + (f" {left}" if left else "") + \
            (f" and {right}" if left and right else f" {right}" if right else "")

    def __call__(self, value, where: str) -> None:
        import math

        if not isinstance(value, numbers.Real):
            self.fail(where, given(value), ArgumentError)
        v = float(value)
        if (self.finite and not math.isfinite(v)) or math.isnan(v) or \
                (self.lo is not None and (v <= self.lo if self.open_lo else v < self.lo)) or \
                (self.hi is not None and (v >= self.hi if self.open_hi else v > self.hi)):
            self.fail(where, repr(value))


class Count(Check):
    """A whole number in [lo, hi]; with ``per_pixels``, ``n * n * per_pixels`` within the
    pixel budget (a cube map's face size: six faces of n x n)."""

    def __init__(self, lo: int = 0, hi: int | None = None, *, per_pixels: int = 0):
        self.lo, self.hi, self.per_pixels = lo, hi, per_pixels
        self.expected = f"a whole number >= {lo}" + ("" if hi is None else f" and <= {hi}")

    def __call__(self, value, where: str) -> None:
        from .budgets import budget

        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            self.fail(where, given(value), ArgumentError)
        n = int(value)
        if n < self.lo or (self.hi is not None and n > self.hi):
            self.fail(where, repr(value))
        if self.per_pixels and n * n * self.per_pixels > budget("pixels"):
            raise InputError(f"{where}: expected at most {budget('pixels'):,} pixels "
                             f"(facet's budget; --budget pixels=N), got {n}, which makes "
                             f"{n * n * self.per_pixels:,}")


class PathArg(Check):
    """A file's path: a ``str`` or ``os.PathLike``, not empty, without a NUL byte."""

    expected = "a path (str or pathlib.Path)"

    def __call__(self, value, where: str) -> None:
        if not isinstance(value, (str, os.PathLike)):
            self.fail(where, given(value), ArgumentError)
        text = os.fspath(value)
        if not isinstance(text, str) or not text or "\0" in text:
            self.fail(where, given(value))


class Items(Check):
    """A sequence (not text) of exactly ``count`` items, each passing ``each`` (if given)."""

    def __init__(self, count: int, each: Check | None = None, noun: str = "items"):
        self.count, self.each = count, each  # count -1: any number of them
        self.expected = f"a sequence of {count if count >= 0 else 'any number of'} {noun}"

    def __call__(self, value, where: str) -> None:
        if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
            self.fail(where, given(value), ArgumentError)
        if self.count >= 0 and len(value) != self.count:
            self.fail(where, f"{len(value)} items")
        if self.each is not None:
            for i, item in enumerate(value):
                self.each(item, f"{where}[{i}]")


def reals(value, where: str, most: int | None = None):
    """``value`` as a float64 array; ArgumentError naming ``where`` when numpy cannot make
    real numbers of it (text, objects, a ragged list, complex numbers, ints too large for
    a float), InputError when it holds more than ``most`` numbers (looked at before it is
    converted: a broadcast view of trillions is not copied). For value checks of their own
    (a dataclass's ``__post_init__``)."""
    import numpy as np

    size = getattr(value, "size", None) if hasattr(value, "dtype") else \
        len(value) if isinstance(value, (list, tuple)) else None
    if most is not None and size is not None and size > most:
        raise InputError(f"{where}: expected at most {most} numbers, got {given(value)}")
    try:
        if np.iscomplexobj(value):
            raise TypeError("complex")
        return np.asarray(value, dtype=np.float64)
    except (ValueError, TypeError, OverflowError):
        raise ArgumentError(f"{where}: expected real numbers, got {given(value)}") from None


def finite(value) -> bool:
    """Whether ``value`` is one finite real number (an int too large for a float is not)."""
    import math

    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


# The shapes of what the API takes, declared once.
ArrayLike = typing.Any  # a numpy array or anything numpy makes one of (lists, tuples)
Vec3 = Annotated[ArrayLike, Array("3")]
Real = Annotated[float, Number()]  # any finite number (checked as numbers.Real: _runtime)
Positive = Annotated[float, Number(0, open_lo=True)]  # a finite number > 0
Color = Annotated[ArrayLike, Array("3", "4")]
FilePath = Annotated[str | os.PathLike, PathArg()]
Crease = Annotated[float | None, Number(0, 180)]  # degrees: sharper is an edge
Size = Annotated[Sequence,  # (width, height) in pixels
                 Items(2, Count(1, 1 << 16), "whole numbers >= 1")]


def _describe(hint) -> str:
    """``hint`` in words, for a type refusal."""
    origin = typing.get_origin(hint)
    if origin is typing.Union or type(hint).__name__ == "UnionType":
        return " or ".join(_describe(h) for h in typing.get_args(hint))
    if hint is type(None):
        return "None"
    if hint is numbers.Real or hint is float:
        return "a number"
    if hint is numbers.Integral or hint is int:
        return "a whole number"
    if hint is bool:
        return "True or False"
    if hint is str:
        return "a string"
    if hint is os.PathLike:
        return "a path"
    name = getattr(hint, "__name__", None) or re.sub(r"^typing\.", "", str(hint))
    return f"a {name}"


def _specs(func, signature: inspect.Signature) -> dict:
    """parameter -> (type hint, [checks]) of ``func``'s annotated parameters."""
    try:
        hints = typing.get_type_hints(func, include_extras=True)
    except Exception:  # a name only imported for type checkers: resolve one by one
        hints = {}
        module = inspect.getmodule(func)
        for name, p in signature.parameters.items():
            if isinstance(p.annotation, str):
                try:
                    hints[name] = eval(p.annotation, vars(module))  # noqa: S307 - our code
                except Exception:
                    continue
    out = {}
    for name, p in signature.parameters.items():
        if name not in hints or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        hint, checks = _split(hints[name])
        out[name] = (None if hint in (object, typing.Any) else _runtime(hint), checks)
    return out


def _runtime(hint):
    """``hint`` as checked at run time: ``float`` as ``numbers.Real`` and ``int`` as
    ``numbers.Integral`` (a numpy scalar is a fine number; annotations keep the builtins
    for type checkers), in unions too."""
    if hint is float:
        return numbers.Real
    if hint is int:
        return numbers.Integral
    args = typing.get_args(hint)
    if args and (typing.get_origin(hint) is typing.Union or
                 type(hint).__name__ == "UnionType"):
        return functools.reduce(lambda a, b: a | b, [_runtime(a) for a in args])
    return hint


def _split(hint) -> tuple:
    """(the type, [(member, check)]) of ``hint``: ``Annotated[T, checks]``, or a union with
    such members (``FilePath | Scene``, ``Annotated[T, checks] | None``): a member's checks
    hold for a value of that member's type (member None: for every value)."""
    if typing.get_origin(hint) is Annotated:
        return hint.__origin__, [(None, m) for m in hint.__metadata__ if isinstance(m, Check)]
    args = typing.get_args(hint)
    if args and (typing.get_origin(hint) is typing.Union or
                 type(hint).__name__ == "UnionType") and \
            any(typing.get_origin(a) is Annotated for a in args):
        parts = [_split(a) for a in args]
        bare = functools.reduce(lambda a, b: a | b, [t for t, _ in parts])
        return bare, [(_runtime(t), c) for t, cs in parts for _, c in cs]
    return hint, []


def checked(target):
    """Hold every call of ``target`` (a function, or a class: its ``__init__``) to its
    signature (module docstring). The wrapped callable keeps its name, docstring and
    signature, and has ``__facet_checked__``."""
    if inspect.isclass(target):
        target.__init__ = checked(target.__init__)
        target.__facet_checked__ = True
        return target
    from beartype import BeartypeConf
    from beartype.door import is_bearable

    conf = BeartypeConf(is_pep484_tower=True)
    signature = inspect.signature(target)
    qualname = target.__qualname__.removesuffix(".__init__")
    specs: dict | None = None

    parameters = signature.parameters
    names = list(parameters)
    simple = all(p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
                 for p in parameters.values())
    positional = [n for n in names if parameters[n].kind != inspect.Parameter.KEYWORD_ONLY]
    required = {n for n in names if parameters[n].default is inspect.Parameter.empty}

    def arguments(args, kwargs) -> dict:
        """{parameter: value} of one call (a call that does not fit: ArgumentError)."""
        if simple and len(args) <= len(positional):
            given_ = {**dict(zip(positional, args, strict=False)), **kwargs}
            if len(given_) == len(args) + len(kwargs) and given_.keys() <= parameters.keys() \
                    and required <= given_.keys():
                return given_
        try:
            return signature.bind(*args, **kwargs).arguments
        except TypeError as exc:
            raise ArgumentError(f"{qualname}: {exc}") from None

    @functools.wraps(target)
    def call(*args, **kwargs):
        nonlocal specs
        if specs is None:
            specs = _specs(target, signature)
        for name, value in arguments(args, kwargs).items():
            spec = specs.get(name)
            if spec is None or value is parameters[name].default:
                continue
            hint, checks = spec
            where = f"{qualname}: {name}"
            if hint is not None and not is_bearable(value, hint, conf=conf):
                raise ArgumentError(f"{where}: expected {_describe(hint)}, got "
                                    f"{given(value)}")
            if value is None and hint is not None:
                continue  # None where the type admits it: nothing to check
            for member, check in checks:
                if member is None or member in (object, typing.Any) or \
                        is_bearable(value, member, conf=conf):
                    check(value, where)
        return target(*args, **kwargs)

    call.__facet_checked__ = True
    call.unchecked = target  # for facet's own hot paths, whose values are checked already
    return call
