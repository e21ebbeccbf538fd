"""Conventions every layer shares: the sides of the body and gravity.

One definition each (the rest of the package imports them from here):

- :class:`Side`: ``Side.LEFT`` / ``Side.RIGHT``. A :class:`~enum.StrEnum`, so it equals the strings
  ``"left"`` / ``"right"`` and prints as them; :attr:`Side.sign` gives paper B's +1 / −1
  (``w_l = +w``, ``w_r = −w``), :attr:`Side.index` the 0 / 1 of per-foot arrays (left first).
- :data:`GRAVITY`: the papers' g = 9.81 m/s² for the reduced models (LIP, ALIP). Where there is a
  MuJoCo model, its own ``opt.gravity`` is used instead (9.80665 in ``digit_like`` and Digit v3).
"""

from __future__ import annotations

import enum

import numpy as np

from .exceptions import InvalidInputError

__all__ = ["GRAVITY", "Side", "LEFT", "RIGHT", "other_side", "parse_side"]

#: gravity of the reduced models [m/s²] (the papers' value)
GRAVITY = 9.81


class Side(enum.StrEnum):
    """A side of the body: the stance or swing foot."""

    LEFT = "left"
    RIGHT = "right"

    @property
    def sign(self) -> int:
        """+1 for left, −1 for right (the lateral direction of the foot, paper B's w_{l/r})."""
        return 1 if self is Side.LEFT else -1

    @property
    def index(self) -> int:
        """0 for left, 1 for right (the row of per-foot arrays)."""
        return 0 if self is Side.LEFT else 1

    @property
    def other(self) -> "Side":
        """The other foot."""
        return Side.RIGHT if self is Side.LEFT else Side.LEFT


LEFT = Side.LEFT
RIGHT = Side.RIGHT


def other_side(side: str) -> Side:
    """The other foot: left ↔ right (accepts a :class:`Side` or its string)."""
    return parse_side(side).other


def parse_side(side: object) -> Side:
    """A :class:`Side` from ``"left"``/``"l"``/``+1`` or ``"right"``/``"r"``/``−1``.

    Raises:
        InvalidInputError: anything else (the value is named in the message).
    """
    if isinstance(side, Side):
        return side
    if isinstance(side, str):
        s = side.strip().lower()
        if s in ("left", "l"):
            return Side.LEFT
        if s in ("right", "r"):
            return Side.RIGHT
    elif isinstance(side, (int, np.integer)) and not isinstance(side, (bool, np.bool_)) and int(side) in (1, -1):
        return Side.LEFT if int(side) == 1 else Side.RIGHT
    raise InvalidInputError("side", side, "'left' (+1) or 'right' (-1)")
