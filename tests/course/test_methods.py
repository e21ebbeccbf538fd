"""lipmpcc.course.methods: a one-step stone planner assembled from a student's functions; the ALIP loop walks
on them (right pieces: every stone; the foothold's sign flipped in the step map: a fall), and bad pieces are
one-line errors. Paper A's MPCC on a student's contouring and lag cost: the right cost follows the circle as the
library's MPCC does, the lag term with a minus sign stalls; notebook 03's Exercise 3 grades the shipped solution
full, the stub and a library call 0 and a flipped lag sign partly (the message names the sign). Two short ALIP
loops and four short LIP loops, about 8 s."""

from __future__ import annotations

import math
from typing import Callable

import casadi as ca
import numpy as np
import pytest

from lipmpcc.course import CheckResult, Exercises, library_calls
from lipmpcc.contouring import casadi_errors
from lipmpcc.course.methods import CONTOURING_LIBRARY, StudentMpccPlanner, StudentStonePlanner, student_terms
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.loops.alip import AlipLoopConfig, loop_metrics, run_alip_loop
from lipmpcc.loops.lip import simulate, summarize
from lipmpcc.models import alip
from lipmpcc.paths import ArcPath
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.studies import stone_course as study
from lipmpcc.terrain import make_profile

from .notebook_exercise import NOTEBOOKS, grade, solution


def step_map(z, sigma, u):
    return sigma * np.asarray(z, float) - np.asarray(u, float)


def sigma_bounds(lam, lo, hi):
    return math.exp(lam * lo), math.exp(lam * hi)


def stone_box(u_nom, size, klo, khi):
    lo = np.maximum(np.asarray(u_nom) - np.asarray(size) / 2, klo)
    hi = np.minimum(np.asarray(u_nom) + np.asarray(size) / 2, khi)
    return lo, np.maximum(hi, lo)


def _walk(planner: StudentStonePlanner, profile: str = "IV") -> dict:
    a = alip.AlipParams()
    seq, _ = study.make_course(make_profile(profile, seed=0, n=6))
    log = run_alip_loop(planner, seq, config=AlipLoopConfig(alip=a), approach_planner=study.make_planner("alip-mpc", a),
                        approach_steps=study.N_APPROACH, progress=False)
    return loop_metrics(log)


def test_the_right_pieces_walk_the_stones_and_a_flipped_sign_falls() -> None:
    good = _walk(StudentStonePlanner(step_map, sigma_bounds, stone_box))
    assert good["completed"] and not good["fell"] and good["stones_violated"] == 0, good
    flipped = _walk(StudentStonePlanner(lambda z, s, u: s * np.asarray(z) + np.asarray(u), sigma_bounds, stone_box))
    assert flipped["fell"] and not flipped["completed"], flipped


def test_bad_pieces_are_one_line_errors() -> None:
    with pytest.raises(InvalidInputError, match="three functions"):
        StudentStonePlanner(step_map, None, stone_box)
    pl = StudentStonePlanner(step_map, lambda lam, lo, hi: (math.exp(lam * hi), math.exp(lam * lo)), stone_box)
    stones = make_profile("I", seed=0, n=3)
    with pytest.raises(InvalidInputError, match="sigma_lo <= sigma_hi"):
        pl.solve([0.05, -0.1], [0.0, -0.1], "left", 0.05, stones)


def test_a_step_map_that_calls_the_library_scores_zero(monkeypatch) -> None:
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)

    def lazy(z, sigma, u):
        return alip.step_to_step(z, sigma, u)

    assert library_calls(lazy, ("step_to_step",)) == ["step_to_step"] and library_calls(step_map, ("step_to_step",)) == []
    ex = Exercises("probe")
    res = ex.check(lazy, stars=1, minutes=5, own_code=("step_to_step",))(lambda f: None)
    assert res.status == "wrong" and "calls the library's step_to_step" in res.message


# ---- paper A: the MPCC on a student's contouring and lag cost (notebook 03, Exercise 3) -----------------------

def contouring_lag_cost(position, path_point, phi, q_bar):
    e = position - path_point
    e_c = ca.sin(phi) * e[0] - ca.cos(phi) * e[1]
    e_l = -ca.cos(phi) * e[0] - ca.sin(phi) * e[1]
    return q_bar[0] * e_c**2 + q_bar[1] * e_l**2, e_c, e_l


def _circle_run(planner, n: int = 40) -> dict:  # noqa: ANN001
    circle = planner.path
    return summarize(simulate(planner, np.array([0.0, 0.0, 0.0, 0.0, circle.slope(0.0)]), n), settle_time=2.0)


def test_the_mpcc_on_the_students_cost_is_the_librarys_and_a_flipped_cost_sign_stalls() -> None:
    circle = ArcPath.circle(2.0, start=(0.0, 0.0), heading=0.0, turns=1.25)
    lib = _circle_run(MpccPlanner(circle, MpccParams.circle()))
    mine = _circle_run(StudentMpccPlanner(circle, contouring_lag_cost, MpccParams.circle()))
    for key in ("contouring_error_max_m", "progress_m", "lag_error_rms_m"):
        assert mine[key] == pytest.approx(lib[key], rel=1e-6, abs=1e-9), (key, mine[key], lib[key])
    assert mine["solver_failures"] == 0 and mine["steps"] == 40
    # the lag term with a minus sign rewards lagging: the robot does not leave the start
    def rewarded_lag(p, r, phi, q):  # noqa: ANN001, ANN202
        _, e_c, e_l = contouring_lag_cost(p, r, phi, q)
        return q[0] * e_c**2 - q[1] * e_l**2, e_c, e_l
    bad = _circle_run(StudentMpccPlanner(circle, rewarded_lag, MpccParams.circle()), 12)  # the library: 1.4 m
    assert bad["progress_m"] < 0.1, bad


def test_a_student_cost_of_the_wrong_kind_is_a_one_line_error() -> None:
    circle = ArcPath.circle(2.0, start=(0.0, 0.0), heading=0.0, turns=1.25)
    with pytest.raises(InvalidInputError, match="a function"):
        StudentMpccPlanner(circle, 42, MpccParams.circle())
    p, r, phi = ca.SX.sym("p", 2), ca.SX.sym("r", 2), ca.SX.sym("phi")
    with pytest.raises(InvalidInputError, match="three CasADi expressions"):
        student_terms(lambda p, r, phi, q: (p[0], p[1]), p, r, phi, (1.0, 1.0))
    with pytest.raises(InvalidInputError, match="three scalar CasADi"):
        student_terms(lambda p, r, phi, q: (p, p[0], 1.0), p, r, phi, (1.0, 1.0))
    assert library_calls(lambda p, r, phi, q: casadi_errors(p, r, phi), CONTOURING_LIBRARY) == ["casadi_errors"]


NOTEBOOK_03 = NOTEBOOKS / "03_lip_mpcc.ipynb"


def _grade_03(student: Callable) -> CheckResult:
    """Notebook 03's Exercise 3 (its own stub and check cells, run as the grader runs them) on ``student``."""
    return grade("03_lip_mpcc", "contouring_lag_cost", student, {
        "np": np, "ArcPath": ArcPath, "MpccParams": MpccParams, "simulate": simulate, "summarize": summarize})


def _lag_sign_flipped(position, path_point, phi, q_bar):  # noqa: ANN001, ANN202
    cost, e_c, e_l = contouring_lag_cost(position, path_point, phi, q_bar)
    return cost, e_c, -e_l


def _library(position, path_point, phi, q_bar):  # noqa: ANN001, ANN202
    e = casadi_errors(position, path_point, phi)
    return q_bar[0] * e[0] ** 2 + q_bar[1] * e[1] ** 2, e[0], e[1]


def _stub(position, path_point, phi, q_bar):  # noqa: ANN001, ANN202
    raise NotImplementedError


def test_notebook_03s_cost_exercise_grades_solution_stub_library_and_a_wrong_sign(monkeypatch) -> None:
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)
    monkeypatch.delenv("LIPMPCC_GRADE_LOG", raising=False)
    solved = _grade_03(solution("03_lip_mpcc", "contouring_lag_cost"))
    assert solved.status == "solved" and solved.fraction == 1.0, solved
    assert (_grade_03(_stub).status, _grade_03(_stub).fraction) == ("unsolved", 0.0)
    lazy = _grade_03(_library)
    assert lazy.status == "wrong" and lazy.fraction == 0.0 and "casadi_errors" in lazy.message, lazy
    flipped = _grade_03(_lag_sign_flipped)  # the cost is the same, the loop walks: the numbers name the sign
    assert flipped.status == "wrong" and flipped.fraction == pytest.approx(4 / 6), flipped
    assert flipped.message.startswith("lag error") and "sign" in flipped.message, flipped.message


def test_the_notebooks_check_refuses_the_library_by_its_objects_and_the_grader_reads_its_tags() -> None:
    from lipmpcc.course.grader import exercise_specs

    spec = exercise_specs(NOTEBOOK_03)["contouring_lag_cost"]
    assert (spec.stars, spec.minutes, spec.points) == (2, 25, 3.0)
    assert all(name in spec.check_source for name in CONTOURING_LIBRARY)
    from lipmpcc.contouring import casadi_errors as renamed  # noqa: F401 - an alias is found by its object

    assert library_calls(lambda p, r, phi, q: renamed(p, r, phi), CONTOURING_LIBRARY) == ["casadi_errors"]
