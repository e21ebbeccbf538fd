"""lipmpcc.course.wbc_task: the whole-body QP with a student's COM task row. The right row gives the library's
matrices (to rounding) and stands through a 150 N side push as the C++ controller does; a flipped stiffness
stops the run (COM 0.1 m off); a bad block is a one-line error. Notebook 08's own check grades the shipped
solution full, the stub and a library shortcut 0 and a flipped kp 2/6 with a message naming the sign. Four short
loops, about 10 s."""

from __future__ import annotations

from typing import Callable

import numpy as np
import pytest

from lipmpcc.control.reference_qp import ReferenceWbcQp
from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.control.wbc_types import WbcReference
from lipmpcc.course import CheckResult
from lipmpcc.course.wbc_task import StudentComWbc, StudentRunStopped, StudentWbcQp
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.loops.fullbody.loop import FullBodyLoop
from lipmpcc.push import Push
from lipmpcc.robots import load_robot
from lipmpcc.sim.robot_sim import RobotSim

from .notebook_exercise import grade, solution

PUSH = [Push((0.0, 150.0), 0.3, 0.1)]


def com_row(terms, ref, kp, kd):  # noqa: ANN001, ANN201
    a = (np.asarray(ref.com_acc) + kp * (np.asarray(ref.com_pos) - terms["com"])
         + kd * (np.asarray(ref.com_vel) - terms["vcom"]))
    return np.asarray(terms["J_com"]), a - terms["drift_com"]


@pytest.fixture(scope="module")
def robot():  # noqa: ANN201
    return load_robot("digit_like")


def test_the_right_row_gives_the_librarys_qp_and_a_bad_block_is_a_one_line_error(robot) -> None:  # noqa: ANN001
    wbc = WholeBodyController(robot)
    sim = RobotSim(robot)
    q, v = sim.pinocchio_state()
    v = v + np.random.default_rng(1).normal(0.0, 0.05, v.shape)
    ref = wbc.hold_reference(q, contact=(False, True))
    ref.com_pos = ref.com_pos + np.array([0.01, -0.02, 0.005])
    lib = ReferenceWbcQp(wbc.model.spec, wbc.params).build(q, v, ref)
    mine = StudentWbcQp(wbc.model.spec, wbc.params, com_row).build(q, v, ref)
    for k in ("H", "g", "A", "b", "C", "l", "u"):
        assert np.allclose(mine[k], lib[k], rtol=1e-12, atol=1e-9), k
    flipped = StudentWbcQp(wbc.model.spec, wbc.params, lambda t, r, kp, kd: com_row(t, r, -kp, kd)).build(q, v, ref)
    assert not np.allclose(flipped["g"], lib["g"], atol=1e-6)
    bad = StudentWbcQp(wbc.model.spec, wbc.params, lambda t, r, kp, kd: (t["J_com"][:2], np.zeros(3)))
    with pytest.raises(InvalidInputError, match=r"finite arrays \(3, 26\) and \(3,\)"):
        bad.build(q, v, ref)
    with pytest.raises(InvalidInputError, match="a function"):
        StudentWbcQp(wbc.model.spec, wbc.params, None)


def test_the_right_row_stands_through_a_push_as_the_cpp_wbc_and_a_flipped_kp_stops(robot) -> None:  # noqa: ANN001
    lib = FullBodyLoop(robot, None).run(duration=1.0, pushes=PUSH)
    mine = FullBodyLoop(robot, None, wbc=StudentComWbc(robot, com_row)).run(duration=1.0, pushes=PUSH)
    assert not mine.fell and not lib.fell and mine.qp_failures == 0
    assert np.max(np.abs(mine.log.com - lib.log.com)) < 1e-3, np.max(np.abs(mine.log.com - lib.log.com))
    assert np.max(np.abs(lib.log.com[:, 1] - lib.log.com[0, 1])) > 0.02  # the push moved the COM: a real test
    with pytest.raises(StudentRunStopped, match="from its reference"):
        FullBodyLoop(robot, None, wbc=StudentComWbc(robot, lambda t, r, kp, kd: com_row(t, r, -kp, kd))).run(
            duration=1.0, pushes=PUSH)


def _solution() -> Callable:
    return solution("08_footsteps_to_torques", "com_task_row")


def _grade_08(student: Callable, robot) -> CheckResult:  # noqa: ANN001
    """Notebook 08's Exercise 5 (its own stub and check cells, with the globals they use) on ``student``."""
    return grade("08_footsteps_to_torques", "com_task_row", student, {
        "np": np, "robot": robot, "WbcReference": WbcReference, "FullBodyLoop": FullBodyLoop})


def _library(terms, ref, kp, kd):  # noqa: ANN001, ANN202 - a shortcut through the library's QP
    qp = ReferenceWbcQp.build
    return qp, kp


def _stub(terms, ref, kp, kd):  # noqa: ANN001, ANN202
    raise NotImplementedError


def _kp_flipped(terms, ref, kp, kd):  # noqa: ANN001, ANN202
    return _solution()(terms, ref, -kp, kd)


def test_notebook_08s_com_row_grades_solution_stub_library_and_wrong_sign(monkeypatch, robot) -> None:  # noqa: ANN001
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)
    monkeypatch.delenv("LIPMPCC_GRADE_LOG", raising=False)
    solved = _grade_08(_solution(), robot)
    assert solved.status == "solved" and solved.fraction == 1.0, solved
    assert (_grade_08(_stub, robot).status, _grade_08(_stub, robot).fraction) == ("unsolved", 0.0)
    lazy = _grade_08(_library, robot)
    assert lazy.status == "wrong" and lazy.fraction == 0.0 and "ReferenceWbcQp" in lazy.message, lazy
    flipped = _grade_08(_kp_flipped, robot)  # J, the drift and (here) nothing else right; the robot does not stand
    assert flipped.status == "wrong" and flipped.fraction == pytest.approx(2 / 6), flipped
    assert "check its sign" in flipped.message and "kp (c_ref − c)" in flipped.message, flipped.message
