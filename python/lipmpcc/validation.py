"""Checks of user input shared by every layer: each raises an :class:`~lipmpcc.exceptions.InvalidInputError`
(or the subclass passed as ``error``) that names the value and what was expected.

One definition per concept:

- numbers: :func:`finite_number` (numpy scalars accepted; booleans, strings and None refused),
  :func:`positive_number`, :func:`non_negative_number`, :func:`number_in` (a range, with the unit
  in the message);
- counts: :func:`count` (``int`` and numpy integers, booleans and floats refused);
- flags and names: :func:`flag`, :func:`choice`;
- arrays: :func:`finite_array` (a float array of a given shape, ``None`` for any size along an
  axis), :func:`finite_vector` (a tuple of ``n`` finite floats), :func:`ordered_pair` (lb <= ub);
- files: :func:`read_text_file` (an existing, readable text file; a binary file gets a clear error).

They only read: a valid value comes back as the same number (``float(x)`` of a numpy scalar is that
number), so results of valid runs do not change.
"""

from __future__ import annotations

import math
import numbers
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from .exceptions import InvalidInputError

__all__ = [
    "finite_number",
    "positive_number",
    "non_negative_number",
    "number_in",
    "count",
    "flag",
    "choice",
    "finite_array",
    "finite_vector",
    "ordered_pair",
    "read_text_file",
    "check_field_types",
    "is_finite_number",
]

#: the error classes the helpers raise (InvalidInputError or one of its subclasses)
ErrorClass = type[InvalidInputError]


def _unit(unit: str) -> str:
    return f" [{unit}]" if unit else ""


def _is_real(value: object) -> bool:
    """True for a real number: Python or numpy ints and floats, not booleans, strings or arrays."""
    if isinstance(value, (bool, np.bool_)):
        return False
    return isinstance(value, numbers.Real)


def is_finite_number(value: object) -> bool:
    """True for a finite real number (numpy scalars too; not booleans or strings): the test of
    :func:`finite_number`, for code that collects problems instead of raising at the first."""
    return _is_real(value) and math.isfinite(float(value))  # type: ignore[arg-type]


def finite_number(name: str, value: object, unit: str = "", *, error: ErrorClass = InvalidInputError) -> float:
    """``value`` as a float, or ``error`` naming ``name`` when it is not a finite real number.

    Numpy scalars (``np.float32``, ``np.int64``, ...) are numbers; booleans, strings, None, lists and
    arrays are not.
    """
    if type(value) is float and math.isfinite(value):  # the common case, without the abstract-class test
        return value
    if not _is_real(value):
        raise error(name, value, f"a finite number{_unit(unit)}")
    v = float(value)  # type: ignore[arg-type]
    if not math.isfinite(v):
        raise error(name, value, f"a finite number{_unit(unit)}")
    return v


def number_in(
    name: str,
    value: object,
    lo: float | None = None,
    hi: float | None = None,
    unit: str = "",
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    error: ErrorClass = InvalidInputError,
    detail: str = "",
    what: str = "a finite number",
) -> float:
    """``value`` as a finite float in the range [lo, hi] (``lo_open``/``hi_open``: that end excluded;
    None: no bound on that side); the message states the range and the unit."""
    parts = []
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {lo:g}")
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {hi:g}")
    expected = what + (" " + " and ".join(parts) if parts else "") + _unit(unit)
    if not _is_real(value):
        raise error(name, value, expected, detail)
    v = float(value)  # type: ignore[arg-type]
    ok = math.isfinite(v)
    if ok and lo is not None:
        ok = v > lo if lo_open else v >= lo
    if ok and hi is not None:
        ok = v < hi if hi_open else v <= hi
    if not ok:
        raise error(name, value, expected, detail)
    return v


def positive_number(name: str, value: object, unit: str = "", *, hi: float | None = None,
                    error: ErrorClass = InvalidInputError, what: str = "a finite number") -> float:
    """A finite float > 0 (and <= ``hi`` when given)."""
    return number_in(name, value, 0.0, hi, unit, lo_open=True, error=error, what=what)


def non_negative_number(name: str, value: object, unit: str = "", *, hi: float | None = None,
                        error: ErrorClass = InvalidInputError, what: str = "a finite number") -> float:
    """A finite float >= 0 (and <= ``hi`` when given)."""
    return number_in(name, value, 0.0, hi, unit, error=error, what=what)


def count(name: str, value: object, minimum: int | None = 0, maximum: int | None = None, *,
          error: ErrorClass = InvalidInputError, what: str = "an integer") -> int:
    """``value`` as an int in [minimum, maximum] (None: no bound): Python and numpy integers, not
    booleans or floats."""
    expected = what + (f" >= {minimum}" if minimum is not None else "")
    expected += (" and" if minimum is not None else "") + f" <= {maximum}" if maximum is not None else ""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise error(name, value, expected)
    v = int(value)
    if (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
        raise error(name, value, expected)
    return v


def check_field_types(obj: object, *, error: ErrorClass = InvalidInputError, skip: Iterable[str] = ()) -> None:
    """Check the fields of the dataclass ``obj`` annotated ``float`` (a finite real number), ``int``
    (an integer, numpy integers too) and ``bool`` (True/False), so that a ``None`` or a string is named
    before any range check of the dataclass's own ``__post_init__`` compares it."""
    import dataclasses

    skipped = set(skip)
    for f in dataclasses.fields(obj):  # type: ignore[arg-type]
        if f.name in skipped or not f.init:
            continue
        kind = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", "")
        value = getattr(obj, f.name)
        if kind == "float":
            finite_number(f.name, value, error=error)
        elif kind == "int":
            count(f.name, value, None, error=error)
        elif kind == "bool":
            flag(f.name, value, error=error)


def flag(name: str, value: object, *, error: ErrorClass = InvalidInputError) -> bool:
    """``value`` as a bool: True/False (numpy booleans too), nothing else."""
    if not isinstance(value, (bool, np.bool_)):
        raise error(name, value, "True or False")
    return bool(value)


def choice(name: str, value: object, choices: Iterable[str], *, error: ErrorClass = InvalidInputError) -> str:
    """``value`` when it is one of the names ``choices``."""
    options = list(choices)
    if not isinstance(value, str) or value not in options:
        raise error(name, value, "one of " + ", ".join(repr(c) for c in options))
    return value


def _shape_text(shape: Sequence[int | None]) -> str:
    dims = ["n" if d is None else str(d) for d in shape]
    return "(" + ", ".join(dims) + ("," if len(dims) == 1 else "") + ")"


def finite_array(name: str, value: object, shape: Sequence[int | None] | None = None, unit: str = "", *,
                 error: ErrorClass = InvalidInputError, what: str = "", finite: bool = True) -> np.ndarray:
    """``value`` as a float array of ``shape`` (None along an axis: any size; ``shape`` None: any
    shape) with finite entries (``finite=False``: NaN and inf let through, for values a caller
    checks itself). Strings, booleans and ragged lists are refused. A float64 array is checked in
    place, without a copy (a few microseconds: planners call this in their loops)."""
    if type(value) is np.ndarray and value.dtype == np.float64:
        arr = value
    else:
        if isinstance(value, (str, bytes, bool, np.bool_)) or (isinstance(value, np.ndarray) and value.dtype == np.bool_):
            raise _array_error(name, value, shape, unit, error, what, finite)
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise _array_error(name, value, shape, unit, error, what, finite) from None
    if shape is not None and (arr.ndim != len(shape) or any(d is not None and d != s for d, s in zip(shape, arr.shape))):
        raise _array_error(name, value, shape, unit, error, what, finite, f"got shape {arr.shape}")
    if finite and not np.isfinite(arr).all():
        raise _array_error(name, value, shape, unit, error, what, finite, "it holds NaN or inf")
    return arr


def _array_error(name: str, value: object, shape: Sequence[int | None] | None, unit: str, error: ErrorClass,
                 what: str, finite: bool, detail: str = "") -> InvalidInputError:
    """The error of :func:`finite_array`, built only when a value fails."""
    desc = what or ("an array of shape " + _shape_text(shape) if shape is not None else "an array")
    kind = "finite numbers" if finite else "numbers"
    expected = (desc if "number" in desc else f"{desc} of {kind}") + _unit(unit)
    shown = value.tolist() if isinstance(value, np.ndarray) else value  # a one-line message
    return error(name, shown, expected, detail)


def finite_vector(name: str, value: object, n: int, unit: str = "", *,
                  error: ErrorClass = InvalidInputError) -> tuple[float, ...]:
    """``value`` as a tuple of ``n`` finite floats (a list, tuple or array of numbers)."""
    words = {2: "two", 3: "three"}
    arr = finite_array(name, value, (n,), unit, error=error, what=f"a list of {words.get(n, n)} finite numbers")
    return tuple(float(x) for x in arr)


def ordered_pair(name: str, value: object, unit: str = "", *, error: ErrorClass = InvalidInputError) -> tuple[float, float]:
    """``value`` as (lb, ub), two finite floats with lb <= ub."""
    lo, hi = finite_vector(name, value, 2, unit, error=error)
    if lo > hi:
        raise error(name, value, f"(lower, upper) bounds with lower <= upper{_unit(unit)}")
    return lo, hi


def read_text_file(name: str, path: object, what: str, *, error: ErrorClass = InvalidInputError) -> str:
    """The text of the file ``path``, or ``error`` naming ``name`` and what was expected.

    Args:
        name: what the argument is called (``"path"``, ``"obstacles"``, ...).
        path: the file name (``str`` or ``os.PathLike``).
        what: what the file should be, without an article, e.g. ``"CSV file of waypoints x,y"``.

    Raises:
        error: not a path, no such file, a folder, unreadable, or not UTF-8 text (a binary file).
    """
    if not isinstance(path, (str, Path)) and not hasattr(path, "__fspath__"):
        raise error(name, path, f"the path of a {what}")
    fp = Path(path)  # type: ignore[arg-type]
    if str(path) == "" or not fp.is_file():
        reason = "a folder" if fp.is_dir() and str(path) != "" else "no such file"
        raise error(name, str(path), f"an existing {what}", reason)
    try:
        data = fp.read_bytes()
    except OSError as exc:
        raise error(name, str(path), f"a readable {what}", exc.strerror or type(exc).__name__) from None
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = None
    if text is None or "\x00" in text:
        raise error(name, str(path), f"a {what} (UTF-8 text)", "the file is binary")
    return text
