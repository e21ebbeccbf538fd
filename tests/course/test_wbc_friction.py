"""lipmpcc.course.wbc_task with a student's friction-pyramid rows (notebook 08, Exercise 3). The right rows give the
library's QP (to rounding); the normal force's sign flipped makes single support infeasible and stops the run;
bad rows are one-line errors. Notebook 08's own check grades the shipped solution full, the stub and a library
shortcut 0, the flipped sign 2/7 with a message naming it, and the pyramid in world axes 5/7 (the robot
steps on flat ground all the same; the turned sole's stored numbers name the frame). Three short stepping
loops, about 8 s."""

from __future__ import annotations

from typing import Callable

import numpy as np
import pytest

from lipmpcc.control.reference_qp import ReferenceWbcQp, contact_wrench_rows
from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.course import CheckResult
from lipmpcc.course.wbc_task import StudentWbcQp
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.loops.fullbody.loop import FullBodyLoop
from lipmpcc.planners.capture_point import CapturePointPlanner
from lipmpcc.robots import load_robot
from lipmpcc.sim.robot_sim import RobotSim

from .notebook_exercise import NOTEBOOKS, grade, solution


def _solution() -> Callable:
    return solution("08_footsteps_to_torques", "friction_pyramid_rows")


def _fz_flipped(R_sole, mu):  # noqa: ANN001, ANN202 - +μ f_z: the pyramid turned inside out
    return _solution()(R_sole, -mu)


@pytest.fixture(scope="module")
def robot():  # noqa: ANN201
    return load_robot("digit_like")


def test_the_right_rows_give_the_librarys_qp_and_bad_rows_are_one_line_errors(robot) -> None:  # noqa: ANN001
    wbc = WholeBodyController(robot)
    q, v = RobotSim(robot).pinocchio_state()
    for contact in ((True, True), (False, True)):
        ref = wbc.hold_reference(q, contact=contact)
        lib = ReferenceWbcQp(wbc.model.spec, wbc.params).build(q, v, ref)
        mine = StudentWbcQp(wbc.model.spec, wbc.params, friction_pyramid_rows=_solution()).build(q, v, ref)
        for k in ("H", "g", "A", "b", "C", "l", "u"):
            assert np.allclose(mine[k], lib[k], rtol=1e-12, atol=1e-12), (contact, k)
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    assert np.allclose(_solution()(R, 0.6), contact_wrench_rows(R, (0.0, 0.0), 0.6, 0.1, 0.04)[:4])
    bad = StudentWbcQp(wbc.model.spec, wbc.params, friction_pyramid_rows=lambda R_sole, mu: np.zeros((4, 3)))
    with pytest.raises(InvalidInputError, match=r"a finite array \(4, 6\)"):
        bad.build(q, v, wbc.hold_reference(q))
    with pytest.raises(InvalidInputError, match="at least one"):
        StudentWbcQp(wbc.model.spec, wbc.params)


def _grade(student: Callable, robot) -> CheckResult:  # noqa: ANN001
    """Notebook 08's Exercise 3 (its own stub and check cells, with the globals they use) on ``student``."""
    return grade("08_footsteps_to_torques", "friction_pyramid_rows", student, {
        "np": np, "robot": robot, "FullBodyLoop": FullBodyLoop, "CapturePointPlanner": CapturePointPlanner})


def _library(R_sole, mu):  # noqa: ANN001, ANN202
    return contact_wrench_rows(R_sole, (0.0, 0.0), mu, 0.1, 0.04)[:4]


def _stub(R_sole, mu):  # noqa: ANN001, ANN202
    raise NotImplementedError


def _world_frame(R_sole, mu):  # noqa: ANN001, ANN202 - the pyramid in world axes: right on a flat sole only
    return _solution()(np.eye(3), mu)


def test_notebook_08s_friction_rows_grade_solution_stub_library_and_a_wrong_sign(monkeypatch, robot) -> None:  # noqa
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)
    monkeypatch.delenv("LIPMPCC_GRADE_LOG", raising=False)
    solved = _grade(_solution(), robot)
    assert solved.status == "solved" and solved.fraction == 1.0, solved
    assert (_grade(_stub, robot).status, _grade(_stub, robot).fraction) == ("unsolved", 0.0)
    lazy = _grade(_library, robot)
    assert lazy.status == "wrong" and lazy.fraction == 0.0 and "contact_wrench_rows" in lazy.message, lazy
    flipped = _grade(_fz_flipped, robot)  # the f_x, f_y and τ columns right; the turned sole and the run wrong
    assert flipped.status == "wrong" and flipped.fraction == pytest.approx(2 / 7), flipped
    assert flipped.message.startswith("a flat sole: the f_z column"), flipped.message
    assert "check its sign" in flipped.message
    assert "the robot on your rows" in flipped.message
    world = _grade(_world_frame, robot)  # the robot steps on flat ground all the same: the stored numbers tell
    assert world.status == "wrong" and world.fraction == pytest.approx(5 / 7), world
    assert world.message.startswith("a turned, tilted sole") and "sole frame" in world.message, world.message
    from lipmpcc.course.grader import exercise_specs

    spec = exercise_specs(NOTEBOOKS / "08_footsteps_to_torques.ipynb")["friction_pyramid_rows"]
    assert (spec.stars, spec.minutes, spec.points) == (3, 30, 3.0)
