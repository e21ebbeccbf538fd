"""The run contract (lipmpcc.loops.base): Course, PushSchedule, RunRecord, and every loop given a course and a
schedule, handing the course's obstacles to the planner and giving back a RunRecord (issue 24)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.loops.base import Course, PathProgress, PushSchedule, RunRecord, TimedRecord
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import LinePath
from lipmpcc.planners.base import PlannerInput, StepPlan
from lipmpcc.push import Push


class SeeingStepper:
    """A capture-point stepper (the student planner of tests/loops/test_student_planner.py) that keeps what it
    was given: the obstacles and the course of each call."""

    name, rate_hz = "seeing", 20.0

    def __init__(self, step: float = 0.15, width: float = 0.25, T: float = 0.4) -> None:
        self.step, self.width, self.T = step, width, T
        self.seen: list[tuple[tuple, object]] = []

    def reset(self) -> None:
        self.seen = []

    def plan(self, inp: PlannerInput) -> StepPlan:
        self.seen.append((tuple(inp.obstacles), inp.course))
        sigma = math.exp(inp.omega * self.T)
        p = np.asarray(inp.stance_pos, dtype=float)[:2]
        left = max(self.T - inp.time_since_touchdown, 0.0)
        xi_end = p + (np.asarray(inp.dcm, dtype=float) - p) * math.exp(inp.omega * left)
        b = np.array([self.step / (sigma - 1.0), -inp.swing_side.sign * self.width / (sigma + 1.0)])
        return StepPlan(xi_end - b, 0.0, self.T)


def _moving_obstacle() -> Obstacle:
    """A disk 0.2 m across moving at 0.1 m/s, 1 m to the left of the walk."""
    return Obstacle(axes=(0.2, 0.2), position=(2.0, 1.0), velocity=(0.1, 0.0))


def test_course_and_schedule_check_their_parts():
    with pytest.raises(InvalidInputError, match="course.obstacles"):
        Course(obstacles=[1.0])
    with pytest.raises(InvalidInputError, match="course.path"):
        Course(path="line")
    with pytest.raises(InvalidInputError, match="schedule.pushes"):
        PushSchedule((Push((1.0, 0.0), 0.0), "push"))


def test_a_schedule_arms_the_pushes_of_a_footstep_at_its_touch_down():
    s = PushSchedule((Push((10.0, 0.0), 1.0), Push((0.0, 5.0), 0.1, 0.1, step=2, body="torso"), Push((1.0, 1.0), 0.0, step=3)))
    assert [p.t_start for p in s.absolute] == [1.0] and len(s.step_timed) == 2
    assert s.arm(0, 0.5) == []
    (armed,) = s.arm(2, 1.2)
    assert armed.step is None and armed.body == "torso" and armed.force == (0.0, 5.0)
    assert armed.t_start == pytest.approx(1.3) and armed.t_end == pytest.approx(1.4)


def test_a_run_record_measures_landing_and_timing_errors():
    r = RunRecord([0.4, 0.8], [1, -1], [[0.1, 0.1], [0.2, -0.1]], [[0.1, 0.13], [0.2, -0.1]], [0.4, 0.4], [0.4, 0.45])
    np.testing.assert_allclose(r.landing_error, [0.03, 0.0], atol=1e-12)
    np.testing.assert_allclose(r.timing_error, [0.0, 0.05], atol=1e-12)
    assert r.summary()["steps"] == 2 and r.summary()["landing_error_max_m"] == pytest.approx(0.03)
    with pytest.raises(InvalidInputError, match="RunRecord.sides"):
        RunRecord([0.4], [1, -1], [[0, 0]], [[0, 0]], [0.4], [0.4])
    assert r.yaws is None and RunRecord([0.4], [1], [[0, 0]], [[0, 0]], [0.4], [0.4], yaws=[0.1]).yaws.shape == (1,)
    with pytest.raises(InvalidInputError, match="RunRecord.yaws"):
        RunRecord([0.4], [1], [[0, 0]], [[0, 0]], [0.4], [0.4], yaws=[0.1, 0.2])


def test_the_lip_loop_takes_a_course_and_a_schedule_as_it_took_path_obstacles_pushes():
    from lipmpcc.loops.lip import run_lip_loop

    path, ob = LinePath((0.0, 0.0), (10.0, 0.0)), _moving_obstacle()
    pushes = (Push((20.0, -10.0), 0.05, 0.1, step=3), Push((-15.0, 5.0), 1.9, 0.1))
    old_planner, new_planner = SeeingStepper(), SeeingStepper()
    old = run_lip_loop(old_planner, np.zeros(5), 12, path=path, obstacles=[ob], pushes=pushes, progress=False)
    new = run_lip_loop(new_planner, np.zeros(5), 12, course=Course(path, (ob,)), schedule=PushSchedule(pushes),
                       progress=False)
    np.testing.assert_array_equal(old.states, new.states)
    np.testing.assert_array_equal(old.com, new.com)
    assert [p.t_start for p in old.pushes] == [p.t_start for p in new.pushes] == [1.9, pytest.approx(3 * 0.4 + 0.05)]
    assert all(obs == (ob,) and course is path for obs, course in new_planner.seen)  # every call sees them
    rec = new.record
    assert rec.n_steps == new.steps == 12 and np.all(rec.landing_error == 0)
    np.testing.assert_allclose(rec.timing_error, 0.0, atol=1e-12)
    assert [k for _, k, _ in rec.plans] == list(range(12)) and rec.pushes == tuple(new.pushes)
    assert math.isnan(new.v_max)  # a planner with no params.v_max
    with pytest.raises(InvalidInputError, match="course"):
        run_lip_loop(SeeingStepper(), np.zeros(5), 2, path=path, course=Course(path))
    with pytest.raises(InvalidInputError, match="schedule"):
        run_lip_loop(SeeingStepper(), np.zeros(5), 2, pushes=pushes, schedule=PushSchedule(pushes))


def test_the_alip_loop_takes_a_course_with_obstacles_and_a_schedule():
    from lipmpcc.loops.alip import AlipLoopConfig, run_alip_loop
    from lipmpcc.terrain import approach_footholds

    seq, ob = approach_footholds(), _moving_obstacle()
    pushes = (Push((8.0, 0.0), 0.1, 0.1, step=2),)
    old = run_alip_loop(SeeingStepper(0.15, 0.28, 0.5), seq, config=AlipLoopConfig(pushes=pushes), progress=False)
    planner = SeeingStepper(0.15, 0.28, 0.5)
    new = run_alip_loop(planner, course=Course(stones=seq, obstacles=(ob,)), schedule=PushSchedule(pushes), progress=False)
    np.testing.assert_array_equal(old.com, new.com)
    np.testing.assert_array_equal(old.footholds, new.footholds)
    assert old.push_windows == new.push_windows and len(new.push_windows) == 1
    assert all(obs == (ob,) for obs, _ in planner.seen) and len(planner.seen[0][1]) == len(seq)
    rec = new.record
    assert rec.n_steps == new.n_steps > 2 and np.all(rec.landing_error == 0)
    np.testing.assert_allclose(rec.timing_error, 0.0, atol=1e-9)
    assert rec.pushes[0].t_start == pytest.approx(new.td_times[1] + 0.1)  # footstep 2 starts at touch-down 2
    with pytest.raises(InvalidInputError, match="course"):
        run_alip_loop(SeeingStepper(), seq, course=Course(stones=seq))
    with pytest.raises(InvalidInputError, match="schedule"):
        run_alip_loop(SeeingStepper(), seq, config=AlipLoopConfig(pushes=pushes), schedule=PushSchedule(pushes))


def test_the_loops_read_planner_records_by_protocol():
    """Paper A's and paper B's plan records follow the protocols the loops read (no isinstance on planners)."""
    from lipmpcc.planners.alip_common import AlipPlanResult
    from lipmpcc.planners.mpcc import MpccResult

    assert set(PathProgress.__annotations__) | {"v_avg"} <= set(dir(MpccResult)) | set(MpccResult.__dataclass_fields__)
    assert set(TimedRecord.__annotations__) <= set(AlipPlanResult.__dataclass_fields__)


@pytest.mark.slow
def test_the_full_body_gives_the_planner_the_course_and_arms_footstep_pushes():
    """digit_like: every planner call sees the course's obstacles and path (the full-body loop used to give
    none), a push timed from footstep 2 is armed at the touch-down that starts footstep 2's swing, and the
    result's record pairs each planned foothold with the landed one."""
    from lipmpcc.loops.fullbody import FullBodyLoop
    from lipmpcc.robots import load_robot

    path, ob = LinePath((0.0, 0.0), (10.0, 0.0)), _moving_obstacle()
    push = Push((30.0, 0.0), 0.05, 0.1, step=2)
    planner = SeeingStepper()
    loop = FullBodyLoop(load_robot("digit_like"), planner=planner)
    res = loop.run(n_steps=3, course=Course(path, (ob,)), schedule=PushSchedule((push,)))
    assert not res.fell and res.n_steps == 3
    assert planner.seen and all(obs == (ob,) and course is path for obs, course in planner.seen)
    (armed,) = loop.armed_pushes
    assert armed.t_start == pytest.approx(res.touchdowns[1].t + 0.05, abs=1e-12) and res.pushes == (armed,)
    rec = res.record
    assert rec.n_steps == 3 and np.all(rec.landing_error < 0.02)
    np.testing.assert_array_equal(rec.footholds, [td.pos[:2] for td in res.touchdowns])
    assert sorted({k for _, k, _ in rec.plans}) == [0, 1, 2]
    with pytest.raises(InvalidInputError, match="schedule"):
        loop.run(n_steps=1, pushes=[push], schedule=PushSchedule((push,)))



def test_no_loop_imports_a_concrete_planner():
    """The loops know planners only through the contracts (planners.base and the protocols of loops.base):
    no module of lipmpcc.loops imports a planner's module at run time."""
    import ast
    from pathlib import Path as FilePath

    import lipmpcc.loops

    root = FilePath(lipmpcc.loops.__file__).parent
    bad = []
    for f in root.rglob("*.py"):
        tree = ast.parse(f.read_text())
        typing_only = {id(n) for node in ast.walk(tree) if isinstance(node, ast.If)
                       and getattr(node.test, "id", "") == "TYPE_CHECKING" for n in ast.walk(node)}
        for node in ast.walk(tree):
            module = getattr(node, "module", None) or ""
            if isinstance(node, ast.ImportFrom) and id(node) not in typing_only and "planners" in module \
                    and not module.endswith("planners.base"):
                bad.append(f"{f.name}: {module}")
    assert not bad, bad

class StraightStepper:
    """A student's planner: walks along +x, the swing foot where the DCM at the end of the step is that of the
    periodic gait with steps ``step`` long and ``width`` apart, every ``T`` [s] (capture point, heading 0)."""

    name, rate_hz = "straight", 20.0

    def __init__(self, step: float = 0.15, width: float = 0.25, T: float = 0.4) -> None:
        self.step, self.width, self.T = step, width, T

    def reset(self) -> None:
        pass

    def plan(self, inp: PlannerInput) -> StepPlan:
        sigma, p = math.exp(inp.omega * self.T), np.asarray(inp.stance_pos[:2], dtype=float)
        left = max(self.T - inp.time_since_touchdown, 0.0)
        xi_end = p + (np.asarray(inp.dcm, dtype=float) - p) * math.exp(inp.omega * left)
        offset = (self.step / (sigma - 1.0), -inp.swing_side.sign * self.width / (sigma + 1.0))
        return StepPlan(xi_end - np.array(offset), 0.0, self.T)


@pytest.mark.slow
def test_with_the_loop_timing_touch_downs_a_student_planner_lands_where_and_when_it_asks():
    """digit_like, touchdown_timing="loop": StraightStepper, which knows nothing of the robot, lands within
    2 cm and 20 ms of every plan (to a WBC tick, 2.5 ms); with the default ("planner") the contact ends
    each swing early, by about 15 ms."""
    from lipmpcc.exceptions import ParameterError
    from lipmpcc.loops.fullbody import FullBodyLoop, LoopParams
    from lipmpcc.robots import load_robot

    robot = load_robot("digit_like")
    runs = {timing: FullBodyLoop(robot, planner=StraightStepper(0.2, 0.25, 0.35),
                                 params=LoopParams(touchdown_timing=timing)).run(n_steps=6)
            for timing in ("loop", "planner")}
    for res in runs.values():
        assert not res.fell and res.n_steps == 6 and np.all(res.record.landing_error < 0.02)
    loop, planner = runs["loop"].record, runs["planner"].record
    assert np.all(np.abs(loop.timing_error) < 0.02) and np.all(np.abs(loop.timing_error) <= 0.0025 + 1e-9)
    assert np.all(planner.timing_error < -0.005)  # the contact came first, every step
    pos = loop.footholds
    assert np.all(np.diff(pos[:, 0]) > 0.1) and np.all(np.abs(np.abs(np.diff(pos[:, 1])) - 0.25) < 0.08)
    with pytest.raises(ParameterError, match="touchdown_timing"):
        LoopParams(touchdown_timing="late")


def test_the_fast_protocol_tests_agree_with_isinstance():
    """has_path_progress / read_timed give isinstance's answer on the shipped records and on others."""
    from types import SimpleNamespace

    from lipmpcc.loops.base import has_path_progress, read_timed

    progress = SimpleNamespace(theta_init=0.0, theta=np.zeros(3), status="ok", v_avg=0.1)
    timed = SimpleNamespace(plan_time=0.001, status="ok")
    for rec in (progress, timed, None, SimpleNamespace(status="ok"), 3.0):
        assert has_path_progress(rec) == isinstance(rec, PathProgress)
        assert (read_timed(rec) is not None) == isinstance(rec, TimedRecord)
    assert read_timed(timed) == (0.001, "ok")
