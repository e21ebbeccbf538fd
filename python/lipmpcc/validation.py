"""Checks of user input shared by every layer: each raises a :class:`~lipmpcc.exceptions.InvalidInputError`
that names the value and what was expected."""

from __future__ import annotations

import math

from .exceptions import InvalidInputError

__all__ = ["finite_number"]


def finite_number(name: str, value: object) -> float:
    """``value`` as a float, or :class:`InvalidInputError` naming ``name`` when it is not a finite number
    (numpy scalars are numbers)."""
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InvalidInputError(name, value, "a finite number") from None
    if not math.isfinite(v):
        raise InvalidInputError(name, value, "a finite number")
    return v
