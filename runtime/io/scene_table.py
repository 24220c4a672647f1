"""A table of scene input being read, and the one-line messages of its mistakes.

Scene files are written by hand, so every mistake must come back as one sentence that says
where it is: the file, the body (name and 1-based position among the ``[[body]]`` tables) and
the field.  :class:`Table` wraps a mapping with that context and reads typed values from it
(finite numbers within range, vectors, flags, printable names), failing with a SceneError.
"""

from __future__ import annotations

import math
import numbers
import reprlib
import sys
import unicodedata
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, NoReturn

import numpy as np

from runtime.io.scene_hints import unknown_key_hint
from runtime.settings import LARGEST, SMALLEST

__all__ = [
    "REQUIRED",
    "SceneError",
    "SceneWarning",
    "Table",
    "body_label",
    "describe",
    "is_sequence",
    "unprintable",
]


class SceneError(ValueError):
    """Invalid scene input; the message names the file, the body and the field."""


class SceneWarning(UserWarning):
    """Valid scene input that is probably not what was meant (an angle in degrees); the
    message has the form of a SceneError's."""


def body_label(index: int, name: str | None = None) -> str:
    """``body 'disc' (#2)`` for the body at 0-based ``index``; messages count from 1."""
    if name is None:
        return f"body #{index + 1}"
    return f"body {name!r} (#{index + 1})"


_SHORT = reprlib.Repr()  # bounded depth and length: a value nested 5,000 deep is "[[[...]]]"
_SHORT.maxlevel, _SHORT.maxstring, _SHORT.maxother = 3, 40, 40


def describe(value: Any) -> str:
    """A short description of a bad value for an error message."""
    if isinstance(value, str):
        return f"the string {_SHORT.repr(value)}"
    if isinstance(value, Mapping):
        return "a table"
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    text = _SHORT.repr(value.tolist() if isinstance(value, np.ndarray) else value)
    return text if len(text) <= 60 else text[:57] + "..."


def unprintable(text: str) -> str | None:
    """The first control, format or line-separator character of ``text``, if any."""
    return next(
        (c for c in text if unicodedata.category(c) in ("Cc", "Cf", "Cs", "Zl", "Zp")), None
    )


def _is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


def is_sequence(value: Any) -> bool:
    return isinstance(value, Sequence | np.ndarray) and not isinstance(value, str | bytes)


class Table:
    """A mapping being read, with the context that error messages need.

    ``where`` is the part of the message between the file and the field, e.g. ``[scene]`` or
    ``body 'disc' (#2)``; ``prefix`` is prepended to field names (``shape.`` inside a shape).
    """

    def __init__(self, data: Any, source: str, where: str, prefix: str = "", field: str = ""):
        self.source = source
        self.where = where
        self.prefix = ""  # the field of the table itself is named without the prefix
        if not isinstance(data, Mapping):
            self.fail(field, f"expected a table, got {describe(data)}")
        self.prefix = prefix
        self.data: Mapping[str, Any] = data

    # -- errors -------------------------------------------------------------------------
    def fail(self, field: str, message: str) -> NoReturn:
        raise SceneError(self._located(field, message)) from None  # one line, no chained trace

    def warn(self, field: str, message: str) -> None:
        """Warn (SceneWarning), attributed to the line that called the loader."""
        frame, level = sys._getframe(0), 1
        while frame.f_back is not None and frame.f_globals["__name__"].startswith("runtime.io"):
            frame, level = frame.f_back, level + 1
        warnings.warn(SceneWarning(self._located(field, message)), stacklevel=level)

    def _located(self, field: str, message: str) -> str:
        parts = [self.source]
        if self.where:
            parts.append(self.where)
        if field:
            parts.append(f"field {self.prefix + field!r}")
        parts.append(message)
        return ": ".join(parts)

    def check_keys(self, valid: Sequence[str]) -> None:
        """Reject keys that are not in ``valid``, saying why (runtime/io/scene_hints.py)."""
        for key in self.data:
            if key not in valid:  # an empty key is named as written, "" (else no field shows)
                self.fail(str(key) or '""', unknown_key_hint(str(key), valid))

    def has(self, key: str) -> bool:
        return key in self.data

    def _get(self, key: str, default: Any) -> Any:
        if key in self.data:
            return self.data[key]
        if default is REQUIRED:
            self.fail(key, "missing required field")
        return default

    # -- typed readers ------------------------------------------------------------------
    def number(
        self, key: str, default: Any = None, *, check: str = "finite", bounded: bool = True
    ) -> float:
        """A finite float; ``check`` is "finite", "positive", "nonnegative" or "unit";
        ``bounded``: also within [-LARGEST, LARGEST] and, if positive, at least SMALLEST."""
        return self.check_number(key, self._get(key, default), check, bounded=bounded)

    def check_number(
        self, key: str, value: Any, check: str = "finite", *, bounded: bool = True
    ) -> float:
        if not _is_number(value):
            self.fail(key, f"expected a number, got {describe(value)}")
        try:
            x = float(value)
        except OverflowError:  # a Python int beyond the float range
            self.fail(key, f"must be finite, got {describe(value)}")
        if not math.isfinite(x):
            self.fail(key, f"must be finite, got {x}")
        if check == "positive" and not x > 0:
            self.fail(key, f"must be > 0, got {x}")
        if check == "nonnegative" and not x >= 0:
            self.fail(key, f"must be >= 0, got {x}")
        if check == "unit" and not 0 <= x <= 1:
            self.fail(key, f"must be between 0 and 1, got {x}")
        if bounded and abs(x) > LARGEST:
            self.fail(key, f"must be at most {LARGEST:g} in magnitude, got {x:g}")
        if bounded and check == "positive" and x < SMALLEST:
            self.fail(key, f"must be at least {SMALLEST:g}, got {x:g}")
        return x

    def vector(self, key: str, default: Any = None) -> tuple[float, float]:
        """A pair of finite floats ``[x, y]``."""
        return self.check_vector(key, self._get(key, default))

    def check_vector(self, key: str, value: Any) -> tuple[float, float]:
        if not is_sequence(value) or len(value) != 2:
            self.fail(key, f"expected a list of 2 numbers [x, y], got {describe(value)}")
        x = self.check_number(f"{key}[0]", value[0])
        y = self.check_number(f"{key}[1]", value[1])
        return (x, y)

    def points(self, key: str) -> list[tuple[float, float]]:
        """A list of at least three ``[x, y]`` points."""
        value = self._get(key, REQUIRED)
        if not is_sequence(value) or len(value) < 3:
            self.fail(
                key, f"expected a list of at least 3 points [[x, y], ...], got {describe(value)}"
            )
        points = [self.check_vector(f"{key}[{i}]", p) for i, p in enumerate(value)]
        for i, p in enumerate(points):
            if p in points[:i]:
                j = points.index(p)
                self.fail(f"{key}[{i}]", f"repeats point {j}, {list(p)}; corners must be distinct")
        span = max(max(x for x, _ in points) - min(x for x, _ in points),
                   max(y for _, y in points) - min(y for _, y in points))  # fmt: skip
        if span < SMALLEST:
            self.fail(key, f"the points span only {span:g}; they must span at least {SMALLEST:g}")
        return points

    def string(self, key: str, default: Any = None) -> str:
        value = self._get(key, default)
        if not isinstance(value, str) or (key in self.data and not value.strip()):
            self.fail(key, f"expected a non-empty string, got {describe(value)}")
        return value

    def name(self, key: str, default: str) -> str:
        """A name: a non-empty string without control or format characters, which would
        reach a terminal raw (escape codes) or hide text (bidirectional overrides)."""
        value = self.string(key, default)
        bad = unprintable(value)
        if bad is not None:
            given = "" if self.has(key) else f" (the default, {_SHORT.repr(value)})"
            self.fail(key, f"contains the non-printing character U+{ord(bad):04X}{given}; "
                           "a name must be printable text")  # fmt: skip
        return value

    def boolean(self, key: str, default: Any = None) -> bool:
        value = self._get(key, default)
        if not isinstance(value, bool | np.bool_):
            self.fail(key, f"expected true or false, got {describe(value)}")
        return bool(value)

    def subtable(self, key: str, prefix: str = "") -> Table:
        return Table(self._get(key, REQUIRED), self.source, self.where, prefix, key)


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED: Any = _Required()
