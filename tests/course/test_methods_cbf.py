"""lipmpcc.course.methods: paper A's MPCC on a student's CBF rows (notebook 04, Exercise 3). The right row overtakes
the 0.6 m/s obstacle as the library's MPCC does (the same run), a (1 + γ) row makes the first solve infeasible;
the notebook's own check grades the shipped solution full, the stub and a library call 0 and the (1 + γ) row
partly, with a message that names the sign. Four 50-step LIP loops (one solver build each), about 12 s."""

from __future__ import annotations

from typing import Callable

import numpy as np
import pytest

from lipmpcc.course import CheckResult
from lipmpcc.course.methods import StudentMpccPlanner
from lipmpcc.exceptions import NoFallbackPlanError
from lipmpcc.loops.lip import simulate, summarize
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import LinePath
from lipmpcc.planners import mpcc
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.studies.path_scenarios import OBSTACLE_RADIUS, OBSTACLE_START, PAPER_SPEED, SETTLE_TIME

from .notebook_exercise import grade, solution

LINE = LinePath((0.0, 0.0), (40.0, 0.0))


def _obstacle(speed: float = PAPER_SPEED["mpcc"]) -> Obstacle:
    return Obstacle.circle(OBSTACLE_RADIUS, path=LINE, s0=OBSTACLE_START, speed=speed)


def _solution() -> Callable:
    return solution("04_overtaking", "cbf_row")


def _plus_gamma(p_now, p_next, ob_now, ob_next, gamma):  # noqa: ANN001, ANN202 - (1 + γ): a wrong sign
    return _solution()(p_now, p_next, ob_now, ob_next, -gamma)


def _run(planner) -> dict:  # noqa: ANN001
    obs = [_obstacle()]
    return summarize(simulate(planner, np.zeros(5), 50, obs), obs, settle_time=SETTLE_TIME)


def test_the_students_cbf_rows_overtake_as_the_librarys_and_a_plus_gamma_row_is_infeasible() -> None:
    lib = _run(MpccPlanner(LINE, MpccParams.overtake_mpcc()))
    mine = _run(StudentMpccPlanner(LINE, None, MpccParams.overtake_mpcc(), cbf_row=_solution()))
    assert mine["overtook"] and mine["min_clearance_m"] > 0 and mine["solver_failures"] == 0, mine
    for key in ("min_clearance_m", "progress_m", "contouring_error_max_m"):
        assert mine[key] == pytest.approx(lib[key], rel=1e-6, abs=1e-9), (key, mine[key], lib[key])
    assert mpcc.build_problem.__module__ == "lipmpcc.planners.mpcc"  # the hook is gone after the build
    with pytest.raises(NoFallbackPlanError):
        _run(StudentMpccPlanner(LINE, None, MpccParams.overtake_mpcc(), cbf_row=_plus_gamma))


def _grade_04(student: Callable) -> CheckResult:
    """Notebook 04's Exercise 3 (its own stub and check cells, with the globals they use) on ``student``."""
    return grade("04_overtaking", "cbf_row", student, {
        "np": np, "line": LINE, "obstacle": _obstacle, "x_start": np.zeros(5), "PAPER_SPEED": PAPER_SPEED,
        "MpccParams": MpccParams, "simulate": simulate, "summarize": summarize, "SETTLE_TIME": SETTLE_TIME})


def _library(p_now, p_next, ob_now, ob_next, gamma):  # noqa: ANN001, ANN202
    return mpcc._barrier(ob_now, 0, p_next[0], p_next[1], 0, 0)


def _stub(p_now, p_next, ob_now, ob_next, gamma):  # noqa: ANN001, ANN202
    raise NotImplementedError


def test_notebook_04s_cbf_exercise_grades_solution_stub_library_and_a_wrong_sign(monkeypatch) -> None:
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)
    monkeypatch.delenv("LIPMPCC_GRADE_LOG", raising=False)
    solved = _grade_04(_solution())
    assert solved.status == "solved" and solved.fraction == 1.0, solved
    assert (_grade_04(_stub).status, _grade_04(_stub).fraction) == ("unsolved", 0.0)
    lazy = _grade_04(_library)
    assert lazy.status == "wrong" and lazy.fraction == 0.0 and "_barrier" in lazy.message, lazy
    plus = _grade_04(_plus_gamma)  # right at γ = 0 only; infeasible in the loop
    assert plus.status == "wrong" and plus.fraction == pytest.approx(1 / 6), plus
    assert "its sign" in plus.message and "(1 − γ)" in plus.message, plus.message
