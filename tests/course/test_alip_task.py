"""lipmpcc.course.alip_task: paper B's ALIP-MPC on a student's touch-down DCM prediction. The right prediction plans
as the library's ALIP-MPC and walks the push test with a sole as it does; the CoP offset's sign flipped falls; a
bad function is a one-line error. Notebook 06's own check grades the shipped solution full, the stub and a library
shortcut 0 and the flipped offset 2/5 with a message naming the sign. Short ALIP loops, about 3 s."""

from __future__ import annotations

from typing import Callable

import casadi as ca
import numpy as np
import pytest

from lipmpcc.course import CheckResult
from lipmpcc.course.alip_task import StudentAlipMpc, touchdown_function
from lipmpcc.exceptions import InvalidInputError, LipmpccError
from lipmpcc.loops.alip import AlipLoopConfig, loop_metrics, run_alip_loop
from lipmpcc.models import alip
from lipmpcc.planners.alip_mpc import AlipMpc, AlipMpcParams
from lipmpcc.studies import stepping_stones as study
from lipmpcc.terrain import Stone

from .notebook_exercise import NOTEBOOKS, grade, solution

P = alip.AlipParams()
SOLE = (0.06, 0.025)


def right(xi, t, sigma, d, lam):  # noqa: ANN001, ANN201
    return d + sigma * ca.exp(-lam * t) * (xi - d)


def d_flipped(xi, t, sigma, d, lam):  # noqa: ANN001, ANN201
    return -d + sigma * ca.exp(-lam * t) * (xi + d)


def _push_test(planner) -> dict:  # noqa: ANN001
    seq, _ = study.make_course(study.push_stones(22))
    approach = study.make_planner("alip-mpc", P, cop_range=SOLE)
    return loop_metrics(run_alip_loop(planner, seq, config=AlipLoopConfig(alip=P, pushes=study.paper_pushes()),
                                      progress=False, approach_planner=approach, approach_steps=study.N_APPROACH))


def test_the_right_prediction_plans_and_walks_as_the_library_and_a_flipped_offset_falls() -> None:
    prm = AlipMpcParams.paper(alip=P, cop_range=SOLE)
    stones = [Stone((0.4 * (j + 1), -0.14 if j % 2 == 0 else 0.14)) for j in range(5)]
    args = (np.array([0.3, 0.05]), np.array([0.0, 0.14]), "left", 0.12, stones)
    lib, mine = AlipMpc(prm).solve(*args), StudentAlipMpc(right, prm).solve(*args)
    assert mine.success and np.allclose(mine.footholds, lib.footholds, atol=1e-7)
    assert np.allclose(mine.durations, lib.durations, atol=1e-7)
    assert np.allclose(mine.cop_offset, lib.cop_offset, atol=1e-7)
    good = _push_test(StudentAlipMpc(right, prm))
    assert good["completed"] and not good["fell"] and good["solver_failures"] == 0, good
    assert good["step_rmse_m"] == pytest.approx(_push_test(AlipMpc(prm))["step_rmse_m"], abs=1e-9)
    bad = _push_test(StudentAlipMpc(d_flipped, prm))
    assert bad["fell"] and not bad["completed"], bad


def test_a_bad_prediction_is_a_one_line_error() -> None:
    with pytest.raises(InvalidInputError, match="a function"):
        StudentAlipMpc(42)
    with pytest.raises(InvalidInputError, match="a CasADi 2-vector"):
        StudentAlipMpc(lambda xi, t, s, d, lam: xi[0])
    with pytest.raises(InvalidInputError, match="use ca.exp"):
        touchdown_function(lambda xi, t, s, d, lam: s * float(t) * xi, 3.3)
    with pytest.raises(NotImplementedError):  # the stub stays "not yet solved"
        touchdown_function(_stub, 3.3)
    as_array = touchdown_function(lambda xi, t, s, d, lam: np.array([s * xi[0], s * xi[1]]), 3.3)  # accepted
    assert np.allclose(np.asarray(as_array([0.1, 0.2], 0.0, 2.0, [0.0, 0.0])).ravel(), [0.2, 0.4])


def _solution() -> Callable:
    return solution("06_alip_stepping_stones", "touchdown_dcm")


def _grade_06(student: Callable) -> CheckResult:
    """Notebook 06's Exercise 3 (its own stub and check cells, with the globals they use) on ``student``."""
    return grade("06_alip_stepping_stones", "touchdown_dcm", student, {
        "np": np, "study": study, "loop_metrics": loop_metrics, "run_alip_loop": run_alip_loop, "P": P,
        "AlipMpcParams": AlipMpcParams, "LipmpccError": LipmpccError})


def _stub(xi, t, sigma, d, lam):  # noqa: ANN001, ANN202
    raise NotImplementedError


def _library(xi, t, sigma, d, lam):  # noqa: ANN001, ANN202 - the step map of the library, for a point foot
    return alip.step_to_step(xi, sigma, np.zeros(2))


def test_notebook_06s_prediction_grades_solution_stub_library_and_a_wrong_sign(monkeypatch) -> None:
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)
    monkeypatch.delenv("LIPMPCC_GRADE_LOG", raising=False)
    solved = _grade_06(_solution())
    assert solved.status == "solved" and solved.fraction == 1.0, solved
    assert (_grade_06(_stub).status, _grade_06(_stub).fraction) == ("unsolved", 0.0)
    lazy = _grade_06(_library)
    assert lazy.status == "wrong" and lazy.fraction == 0.0 and "step_to_step" in lazy.message, lazy
    flipped = _grade_06(d_flipped)  # the point-foot numbers right, the offset and the loop wrong
    assert flipped.status == "wrong" and flipped.fraction == pytest.approx(2 / 5), flipped
    assert flipped.message.startswith("with a CoP offset") and "check its sign" in flipped.message, flipped.message
    from lipmpcc.course.alip_task import ALIP_MPC_LIBRARY
    from lipmpcc.course.grader import exercise_specs

    spec = exercise_specs(NOTEBOOKS / "06_alip_stepping_stones.ipynb")["touchdown_dcm"]
    assert (spec.stars, spec.minutes, spec.points) == (2, 20, 3.0)
    assert all(name in spec.check_source for name in ALIP_MPC_LIBRARY)
