"""Issue 24, 'Done means': one student planner of a dozen lines, written against the planner contract only
(no adapter of its own), runs unchanged in the LIP loop, the ALIP loop and digit_like's full-body loop on a
course with a moving obstacle; it is handed the obstacles in each, and on digit_like its footholds land
within 2 cm and its touch-downs within 20 ms of its plan (the loop owns the clock:
``LoopParams.touchdown_timing = "auto"``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.loops.base import Course, compensates_touchdown, touchdown_timing
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import LinePath
from lipmpcc.planners.base import PlannerInput, StepPlan


class Student:
    """Capture point along +x, steps ``step`` long and ``width`` apart every ``T`` [s]; keeps each call's
    (time [s], obstacle centres (n, 2) [m])."""

    name, rate_hz = "student", 20.0

    def __init__(self, step: float = 0.15, width: float = 0.25, T: float = 0.4) -> None:
        self.step, self.width, self.T, self.seen = step, width, T, []

    def reset(self) -> None:
        self.seen = []

    def plan(self, inp: PlannerInput) -> StepPlan:
        self.seen.append((inp.t, [np.asarray(ob.center(inp.t), dtype=float) for ob in inp.obstacles]))
        sigma, p = math.exp(inp.omega * self.T), np.asarray(inp.stance_pos[:2], dtype=float)
        xi_end = p + (inp.dcm - p) * math.exp(inp.omega * max(self.T - inp.time_since_touchdown, 0.0))
        offset = (self.step / (sigma - 1.0), -inp.swing_side.sign * self.width / (sigma + 1.0))
        return StepPlan(xi_end - np.array(offset), 0.0, self.T)


def _course(stones=None) -> Course:
    """A line along +x with a disk 0.3 m across walking beside it at 0.2 m/s, 1.2 m to the left."""
    ob = Obstacle(axes=(0.3, 0.3), position=(1.5, 1.2), velocity=(0.2, 0.0))
    return Course(None if stones is not None else LinePath((0.0, 0.0), (10.0, 0.0)), (ob,), stones)


def _saw_the_obstacle_move(planner: Student) -> None:
    """Every call was given the one obstacle, at its place at the call's time: it moved between calls."""
    assert len(planner.seen) > 3 and all(len(centres) == 1 for _, centres in planner.seen)
    t = np.array([ti for ti, _ in planner.seen])
    x = np.array([c[0][0] for _, c in planner.seen])
    np.testing.assert_allclose(x, 1.5 + 0.2 * t, atol=1e-12)
    assert x[-1] - x[0] > 0.2


def test_the_loop_times_the_touch_down_of_a_planner_that_does_not():
    from lipmpcc.planners.capture_point import CapturePointPlanner

    assert not compensates_touchdown(Student()) and compensates_touchdown(CapturePointPlanner())
    cp = CapturePointPlanner()
    assert touchdown_timing("auto", Student()) == "loop" and touchdown_timing("auto", cp) == "planner"
    assert touchdown_timing("planner", Student()) == "planner" and touchdown_timing("loop", cp) == "loop"


def test_the_student_planner_sees_the_moving_obstacle_on_the_lip_and_the_alip():
    from lipmpcc.loops.alip import run_alip_loop
    from lipmpcc.loops.lip import run_lip_loop
    from lipmpcc.terrain import approach_footholds

    lip = Student()
    log = run_lip_loop(lip, np.zeros(5), 12, course=_course(), progress=False)
    assert log.steps == 12 and not log.fell
    _saw_the_obstacle_move(lip)
    alip = Student(0.15, 0.28, 0.5)
    log = run_alip_loop(alip, course=_course(approach_footholds()), progress=False)
    assert log.n_steps > 3 and not log.fell
    _saw_the_obstacle_move(alip)


@pytest.mark.slow
def test_on_digit_like_the_student_planner_lands_where_and_when_it_plans():
    from lipmpcc.loops.fullbody import FullBodyLoop
    from lipmpcc.robots import load_robot

    planner = Student(0.2, 0.25, 0.35)
    res = FullBodyLoop(load_robot("digit_like"), planner=planner).run(n_steps=6, course=_course())
    assert not res.fell and res.n_steps == 6
    _saw_the_obstacle_move(planner)
    rec = res.record
    assert np.all(rec.landing_error < 0.02) and np.all(np.abs(rec.timing_error) < 0.02)
    assert np.all(np.diff(rec.footholds[:, 0]) > 0.1)  # it walked forward
    np.testing.assert_array_equal(rec.yaws, [td.yaw for td in res.touchdowns])  # the landed soles' yaw


def test_no_loop_tests_isinstance_on_a_concrete_planner_or_result_type():
    """The loops tell planners and their records apart by the contracts (planners.base, the protocols and
    attributes of loops.base), never by a class of a planner module (issue 24)."""
    import ast
    from pathlib import Path as FilePath

    import lipmpcc.loops
    import lipmpcc.planners

    planners = FilePath(lipmpcc.planners.__file__).parent
    concrete = {n.name for f in planners.rglob("*.py") if f.name != "base.py"
                for n in ast.walk(ast.parse(f.read_text())) if isinstance(n, ast.ClassDef)}
    tested = set()
    for f in FilePath(lipmpcc.loops.__file__).parent.rglob("*.py"):
        for n in ast.walk(ast.parse(f.read_text())):
            if isinstance(n, ast.Call) and getattr(n.func, "id", "") == "isinstance" and len(n.args) == 2:
                kinds = n.args[1].elts if isinstance(n.args[1], ast.Tuple) else [n.args[1]]
                tested |= {k.id if isinstance(k, ast.Name) else getattr(k, "attr", "") for k in kinds}
    assert {"MpccResult", "AlipPlanResult", "MpccPlanner"} <= concrete  # the scan sees the planner classes
    assert "StepPlan" in tested and not tested & concrete, tested & concrete
