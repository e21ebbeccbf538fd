"""lipmpcc.course.stone_task: the MILP stone choice on a student's one-stone-per-foot rows. Notebook 13's own check
grades the shipped solution full, the stub and a library shortcut 0, and rows without the one-stone sum partly,
naming it; a malformed answer is a one-line error."""

from __future__ import annotations

from typing import Callable

import numpy as np
import pytest

from lipmpcc.course import CheckResult
from lipmpcc.course.stone_task import STONE_LIBRARY, StudentStoneFieldPlanner, checked_rows
from lipmpcc.exceptions import InvalidInputError, LipmpccError
from lipmpcc.planners.alip_mpc import AlipMpcParams
from lipmpcc.planners.stone_field import StoneFieldParams
from lipmpcc.planners.stone_milp import one_stone_rows
from lipmpcc.stone_field import make_stone_field
from lipmpcc.studies.stone_field import run_field

from .notebook_exercise import NOTEBOOKS, grade, solution

FOOT = StoneFieldParams(mpc=AlipMpcParams.paper(cop_range=(0.06, 0.025)))


def _solution() -> Callable:
    return solution("13_stone_field", "one_stone_rows")


def _grade_13(student: Callable) -> CheckResult:
    """Notebook 13's exercise (its own stub and check cells, with the globals they use) on ``student``."""
    return grade("13_stone_field", "one_stone_rows", student, {
        "np": np, "make_stone_field": make_stone_field, "run_field": run_field, "FOOT": FOOT,
        "LipmpccError": LipmpccError})


def _stub(centers, half_sizes, big_m):  # noqa: ANN001, ANN202
    raise NotImplementedError


def _library(centers, half_sizes, big_m):  # noqa: ANN001, ANN202
    return one_stone_rows(centers, half_sizes, big_m)


def _no_sum(centers, half_sizes, big_m):  # noqa: ANN001, ANN202 - the stone rows right, "one stone" left out
    m = len(centers)
    A, b = np.zeros((4 * m, 2 + m)), np.zeros(4 * m)
    for j in range(m):
        for axis in (0, 1):
            for k, sign in enumerate((1.0, -1.0)):
                r = 4 * j + 2 * axis + k
                A[r, axis], A[r, 2 + j] = sign, big_m
                b[r] = sign * centers[j, axis] + half_sizes[j, axis] + big_m
    return A, b


def test_notebook_13s_check_grades_solution_stub_library_and_a_missing_sum(monkeypatch) -> None:
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)
    monkeypatch.delenv("LIPMPCC_GRADE_LOG", raising=False)
    solved = _grade_13(_solution())
    assert solved.status == "solved" and solved.fraction == 1.0, solved
    assert (_grade_13(_stub).status, _grade_13(_stub).fraction) == ("unsolved", 0.0)
    lazy = _grade_13(_library)
    assert lazy.status == "wrong" and lazy.fraction == 0.0 and "one_stone_rows" in lazy.message, lazy
    loose = _grade_13(_no_sum)  # z = 0 "on no stone" is allowed: the sum's expectation fails
    assert loose.status == "wrong" and 0.0 < loose.fraction < 1.0 and "sum z = 1" in loose.message, loose
    from lipmpcc.course.grader import exercise_specs

    spec = exercise_specs(NOTEBOOKS / "13_stone_field.ipynb")["one_stone_rows"]
    assert (spec.stars, spec.minutes, spec.points) == (2, 20, 3.0)
    assert all(name in spec.check_source for name in STONE_LIBRARY)


def test_a_malformed_answer_is_a_one_line_error() -> None:
    with pytest.raises(InvalidInputError, match="a function"):
        checked_rows(42)
    with pytest.raises(InvalidInputError, match="a pair"):
        checked_rows(lambda c, h, m: np.zeros((4, 5)))(np.zeros((3, 2)), np.ones((3, 2)), 1.0)
    with pytest.raises(InvalidInputError, match=r"\(rows, 5\)"):
        checked_rows(lambda c, h, m: (np.zeros((4, 4)), np.zeros(4)))(np.zeros((3, 2)), np.ones((3, 2)), 1.0)
    with pytest.raises(InvalidInputError, match="finite"):
        checked_rows(lambda c, h, m: (np.full((1, 5), np.nan), np.zeros(1)))(np.zeros((3, 2)), np.ones((3, 2)), 1.0)
    pl = StudentStoneFieldPlanner(_solution(), make_stone_field(0), FOOT)
    assert pl.name == "stone-field-student"
