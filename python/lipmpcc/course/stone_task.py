"""The stone choice on a student's one-stone-per-foot rows (notebook 13).

The mixed-integer stone choice (:mod:`lipmpcc.planners.stone_milp`) rests on one block of linear rows per
footstep: with the foothold ``u`` (2,) [m] and one binary ``z_j`` per stone, ``A @ [u_x, u_y, z_1..z_m] <= b``
must hold exactly when the binaries pick one stone and the foothold is on it. The student writes it::

    A, b = one_stone_rows(centers, half_sizes, big_m)

with ``centers`` and ``half_sizes`` (m, 2) [m] and the big-M constant ``big_m`` [m]. :class:`StudentStoneFieldPlanner`
is :class:`~lipmpcc.planners.stone_milp.MilpStoneFieldPlanner` (the costs, limits, HiGHS, the placement by paper
B's ALIP-MPC: the library's) on the student's rows; wrong rows choose stones the foot is not on, or none.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..exceptions import InvalidInputError
from ..planners.stone_field import StoneFieldParams
from ..planners.stone_milp import MilpStoneFieldPlanner
from ..stone_field import StoneField

__all__ = ["STONE_LIBRARY", "checked_rows", "StudentStoneFieldPlanner"]

#: the library names a student's ``one_stone_rows`` must not call (the exercise asks to write the rows)
STONE_LIBRARY = ("lipmpcc.planners.stone_milp.one_stone_rows", "lipmpcc.planners.stone_milp.hull_rows",
                 "lipmpcc.planners.stone_milp.footstep_milp", "lipmpcc.planners.stone_milp.MilpStoneFieldPlanner")


def checked_rows(one_stone_rows: Callable) -> Callable[[np.ndarray, np.ndarray, float], tuple[np.ndarray, np.ndarray]]:
    """The student's function, its output checked: two finite arrays ``A`` (r, 2 + m) and ``b`` (r,); anything
    else is an :class:`InvalidInputError` (the stub's NotImplementedError passes through)."""
    if not callable(one_stone_rows):
        raise InvalidInputError("one_stone_rows", one_stone_rows, "a function (centers, half_sizes, big_m) -> (A, b)")

    def rows(centers: np.ndarray, half_sizes: np.ndarray, big_m: float) -> tuple[np.ndarray, np.ndarray]:
        out = one_stone_rows(np.array(centers, float), np.array(half_sizes, float), float(big_m))
        if not (isinstance(out, tuple) and len(out) == 2):
            raise InvalidInputError("one_stone_rows(...)", type(out).__name__, "a pair (A, b)")
        A, b = np.asarray(out[0], dtype=float), np.asarray(out[1], dtype=float).ravel()
        m = len(centers)
        if A.ndim != 2 or A.shape[1] != 2 + m or A.shape[0] != len(b):
            raise InvalidInputError("one_stone_rows(...)", (A.shape, b.shape),
                                    f"A of shape (rows, {2 + m}) for {m} stones and b with one entry per row")
        if not (np.all(np.isfinite(A)) and np.all(np.isfinite(b))):
            raise InvalidInputError("one_stone_rows(...)", "NaN or inf", "finite numbers")
        return A, b

    rows.__name__ = getattr(one_stone_rows, "__name__", "one_stone_rows")
    return rows


class StudentStoneFieldPlanner(MilpStoneFieldPlanner):
    """The MILP stone choice (then paper B's ALIP-MPC) on the student's ``one_stone_rows`` (see the module doc)."""

    def __init__(self, one_stone_rows: Callable, stone_field: StoneField, params: StoneFieldParams | None = None) -> None:
        super().__init__(stone_field, params, rows=checked_rows(one_stone_rows))
        self.name = "stone-field-student"
