"""lipmpcc.loops.fullbody.loop: full-body walking on digit_like, MuJoCo 2 kHz + C++ whole-body QP
400 Hz + capture-point steps.

The four runs of the issue — standing under pushes, 10 m straight at ≥ 0.5 m/s, a full 2 m-radius
circle, 20 steps in place — none may fall; the swing re-timing, the WBC rate, the threads, the pushes,
bad inputs and the old module path. (The gait state machine and the references on hand-made
measurements: test_gait.py, test_references.py; the walk/stand CLI: tests/studies/test_walking_cli.py.)
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lipmpcc.push import Push

from .walking_checks import check_full_circle, check_steps_in_place, check_walked_10m_straight

slow = pytest.mark.slow


@pytest.fixture(scope="module")
def robot():
    from lipmpcc.robots import load_robot

    return load_robot("digit_like")


def _loop(robot, speed: float | None, yaw_rate: float = 0.0):
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.loops.fullbody.loop import FullBodyLoop

    planner = None if speed is None else CapturePointPlanner(speed=speed, yaw_rate=yaw_rate)
    return FullBodyLoop(robot, planner=planner)


@slow
def test_stand_5s_with_four_50N_pushes(robot) -> None:
    from lipmpcc.studies.walking import stand_pushes

    pushes = stand_pushes(t_first=1.0, spacing=1.0)
    assert {tuple(np.sign(p.force[:2])) for p in pushes} == {(1, 0), (-1, 0), (0, 1), (0, -1)}
    assert all(np.linalg.norm(p.force) == 50.0 and p.duration == 0.1 for p in pushes)
    res = _loop(robot, None).run(duration=5.0, pushes=pushes)
    log = res.log
    assert not res.fell
    assert res.sim_time == pytest.approx(5.0, abs=0.01)
    # the base stays up and the feet never leave the ground
    h0 = log.base_height[0]
    assert res.min_base_height > h0 - 0.05
    assert np.all(log.contact)
    feet_drift = np.linalg.norm(log.left_foot[-1] - log.left_foot[0]) + np.linalg.norm(log.right_foot[-1] - log.right_foot[0])
    assert feet_drift < 0.01
    # each push moves the COM, which comes back
    c = log.com[:, :2] - log.com[0, :2]
    assert np.max(np.linalg.norm(c, axis=1)) > 1e-3
    assert np.linalg.norm(c[-1]) < 0.01
    assert res.qp_failures == 0


@slow
def test_walk_straight_10m_at_least_half_a_metre_per_second(robot) -> None:
    check_walked_10m_straight(_loop(robot, 0.6).run(duration=19.0))


@slow
def test_walk_full_circle_of_radius_2m(robot) -> None:
    v, R = 0.5, 2.0
    check_full_circle(_loop(robot, v, yaw_rate=v / R).run(duration=28.0), R)


@slow
def test_twenty_steps_in_place(robot) -> None:
    check_steps_in_place(_loop(robot, 0.0).run(n_steps=20), 20)


class _RetimingSource:
    """A paper-B-like source at 25 Hz: capture-point footholds, but the step duration it asks for
    drops from 0.45 s to 0.36 s once the swing is 0.15 s old (a mid-swing re-timing every step)."""

    name = "retiming"
    rate_hz = 25.0

    def __init__(self) -> None:
        from lipmpcc.planners.capture_point import CapturePointParams, CapturePointPlanner

        fixed = dict(min_duration=0.3, max_duration=0.5, speed_gain=0.0, timing_gain=0.0)
        self.long = CapturePointPlanner(CapturePointParams(step_duration=0.45, **fixed), speed=0.3)
        self.short = CapturePointPlanner(CapturePointParams(step_duration=0.36, **fixed), speed=0.3)
        self.asked: list[tuple[float, float]] = []

    def reset(self) -> None:
        self.long.reset()
        self.short.reset()
        self.asked.clear()

    def plan(self, inp):
        a, b = self.long.plan(inp), self.short.plan(inp)
        plan = a if inp.time_since_touchdown < 0.15 else b
        self.asked.append((inp.time_since_touchdown, plan.duration))
        return plan


@slow
def test_loop_retimes_the_swing_when_the_planned_duration_changes(robot) -> None:
    from lipmpcc.loops.fullbody.loop import FullBodyLoop

    source = _RetimingSource()
    loop = FullBodyLoop(robot, planner=source)
    res = loop.run(n_steps=10)
    assert not res.fell
    assert res.planner_rate_hz == 25.0
    assert {round(d, 2) for _, d in source.asked} >= {0.45, 0.36}
    # every step ends near the *latest* duration (0.36 s, minus an early ground contact), not 0.45 s
    durations = np.array([td.duration for td in res.touchdowns[1:]])
    assert np.all(durations <= 0.365) and np.all(durations >= 0.3)
    # the swing-foot reference stays continuous through the re-timings (no jump between ticks)
    log = res.log
    same_swing = (log.stance[1:] == log.stance[:-1]) & (log.stance[1:] < 2)
    jumps = np.linalg.norm(np.diff(log.swing_ref, axis=0), axis=1)[same_swing]
    assert np.nanmax(jumps) < 3.0 / 400.0  # below 3 m/s at 400 Hz


@slow
def test_wbc_rate_is_configurable_up_to_sim_rate(robot) -> None:
    from lipmpcc.studies.walking import stand_pushes
    from lipmpcc.loops.fullbody.loop import FullBodyLoop, LoopParams

    res = FullBodyLoop(robot, params=LoopParams(sim_steps_per_wbc=1)).run(duration=1.5, pushes=stand_pushes(0.5, 0.25))
    assert res.wbc_rate_hz == pytest.approx(2000.0)
    assert len(res.log.t) == pytest.approx(3000, abs=2)
    assert not res.fell and res.qp_failures == 0


@slow
@pytest.mark.parametrize("helper_thread, wbc_thread", [(True, True), (True, False), (False, True)])
def test_threads_walk_the_same_steps(robot, helper_thread: bool, wbc_thread: bool) -> None:
    """The loop's helper thread (the tick's log and the next tick's references while MuJoCo steps)
    and the WBC's worker (its dynamics stage while the loop builds the reference): with either or
    both, the walk, its pushes, touch-downs and re-plans are the same, to the bit, as on one thread."""
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.loops.fullbody.loop import FullBodyLoop, LoopParams
    from lipmpcc.control.wbc import WholeBodyController

    results = []
    for helper, threaded in ((False, False), (helper_thread, wbc_thread)):
        loop = FullBodyLoop(
            robot,
            planner=CapturePointPlanner(speed=0.6),
            params=LoopParams(helper_thread=helper),
            wbc=WholeBodyController(robot, threaded=threaded),
        )
        res = loop.run(duration=2.0, pushes=[Push(t_start=1.0, force=(40.0, 20.0, 0.0), duration=0.1)])
        assert not res.fell and len(res.touchdowns) >= 3
        results.append(res)
    a, b = results
    for name in set(a.log.__dataclass_fields__) - {"wbc_time"}:  # all but the measured durations
        np.testing.assert_array_equal(np.asarray(getattr(a.log, name)), np.asarray(getattr(b.log, name)), err_msg=name)
    assert [(td.t, td.side) for td in a.touchdowns] == [(td.t, td.side) for td in b.touchdowns]
    assert [t for t, _ in a.plans] == [t for t, _ in b.plans]


@slow
def test_helper_thread_errors_reach_the_caller(robot) -> None:
    """An exception raised on the helper thread (here by the swing trajectory) is raised by run()."""
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.loops.fullbody.loop import FullBodyLoop, LoopParams
    from lipmpcc.control.references import StepTrajectory

    class Boom(RuntimeError):
        pass

    calls = {"n": 0}
    original = StepTrajectory.evaluate

    def evaluate(self, t):
        calls["n"] += 1
        if calls["n"] == 40:
            raise Boom("swing evaluation failed")
        return original(self, t)

    loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.6), params=LoopParams(helper_thread=True))
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(StepTrajectory, "evaluate", evaluate)
        with pytest.raises(Boom, match="swing evaluation failed"):
            loop.run(duration=2.0)
    import threading

    assert not any(t.name == "lipmpcc-loop-helper" for t in threading.enumerate())


@slow
def test_loop_rejects_bad_inputs(robot) -> None:
    from lipmpcc.exceptions import InvalidInputError, ParameterError
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.loops.fullbody.loop import FullBodyLoop, LoopParams

    with pytest.raises(ParameterError, match="sim_steps_per_wbc"):
        LoopParams(sim_steps_per_wbc=0)
    with pytest.raises(ParameterError, match="first_stance"):
        LoopParams(first_stance="middle")
    with pytest.raises(ParameterError, match="helper_thread"):
        LoopParams(helper_thread="yes")
    loop = FullBodyLoop(robot)
    with pytest.raises(InvalidInputError, match="duration"):
        loop.run()
    with pytest.raises(InvalidInputError, match="n_steps"):
        loop.run(n_steps=3)
    with pytest.raises(InvalidInputError, match="duration"):
        loop.run(duration=-1.0)
    with pytest.raises(InvalidInputError, match="planner"):
        FullBodyLoop(robot, planner=object(), sim=loop.sim, wbc=loop.wbc)
    with pytest.raises(InvalidInputError, match="sim"):
        FullBodyLoop(robot, sim=object(), wbc=loop.wbc)
    with pytest.raises(InvalidInputError, match="wbc"):
        FullBodyLoop(robot, sim=loop.sim, wbc=object())
    walker = FullBodyLoop(robot, planner=CapturePointPlanner(), sim=loop.sim, wbc=loop.wbc)
    with pytest.raises(InvalidInputError, match="n_steps"):
        walker.run(n_steps=0)


@slow
def test_pushes_are_the_one_push_and_anything_else_is_named(robot) -> None:
    """``run(pushes=...)`` takes :class:`lipmpcc.push.Push` (planar or 3D force); the old
    ``lipmpcc.sim.fullbody_loop.Push(t_start, force, duration)`` makes one, with a warning; anything
    else, and a push timed from a footstep, is refused with the value in the message."""
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.loops.fullbody import FullBodyLoop

    loop = FullBodyLoop(robot)
    with pytest.raises(InvalidInputError, match=r"pushes = \(0\.2, \(60\.0, 0\.0, 0\.0\)\)"):
        loop.run(duration=0.1, pushes=[(0.2, (60.0, 0.0, 0.0))])
    with pytest.raises(InvalidInputError, match="pushes = 3"):
        loop.run(duration=0.1, pushes=3)
    with pytest.raises(InvalidInputError, match="step=None"):
        loop.run(duration=0.1, pushes=[Push(force=(60.0, 0.0), t_start=0.0, step=2)])

    from lipmpcc.sim.fullbody_loop import Push as OldPush

    with pytest.warns(DeprecationWarning, match="lipmpcc.push.Push"):
        old = OldPush(0.2, (60.0, 0.0, 0.0))  # the old positional order: t_start, force
    assert isinstance(old, Push) and old == Push(force=(60.0, 0.0, 0.0), t_start=0.2, duration=0.1)
    spatial = loop.run(duration=0.6, pushes=[old])
    planar = loop.run(duration=0.6, pushes=(Push(force=(60.0, 0.0), t_start=0.2),))
    still = loop.run(duration=0.6)
    np.testing.assert_array_equal(spatial.log.com, planar.log.com)
    x = planar.log.com[:, 0] - still.log.com[:, 0]
    assert np.all(x[planar.log.t < 0.2] == 0.0) and x[-1] > 1e-3  # pushed forwards from t = 0.2 s


def test_old_module_path_forwards_with_a_warning() -> None:
    """``lipmpcc.sim.fullbody_loop`` hands out each old name from its new home, with a warning."""
    import lipmpcc.sim.fullbody_loop as old
    from lipmpcc.conventions import LEFT
    from lipmpcc.loops.fullbody import FullBodyLoop, LoopParams
    from lipmpcc.planners.base import FootstepSource, PlannerInput

    for name, new, home in (
        ("FullBodyLoop", FullBodyLoop, "lipmpcc.loops.fullbody.loop"),
        ("LoopParams", LoopParams, "lipmpcc.loops.fullbody.loop"),
        ("PlannerInput", PlannerInput, "lipmpcc.planners.base"),
        ("FootstepSource", FootstepSource, "lipmpcc.planners.base"),
        ("LEFT", LEFT, "lipmpcc.conventions"),
    ):
        with pytest.warns(DeprecationWarning, match=f"{home}.{name}"):
            assert getattr(old, name) is new
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(AttributeError):
            old.NoSuchName  # noqa: B018


def test_run_arguments_of_the_wrong_type_or_size_are_named(robot) -> None:
    """Issue 14: ``duration``/``n_steps`` of the wrong type or absurd size, a robot or params that
    are not the loop's types: one lipmpcc error naming the value, before anything runs."""
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.loops.fullbody.params import MAX_RUN_DURATION
    from lipmpcc.planners.capture_point import CapturePointPlanner

    loop = FullBodyLoop(robot)
    with pytest.raises(InvalidInputError, match=r"duration = 'long': expected a simulated time > 0"):
        loop.run(duration="long")
    with pytest.raises(InvalidInputError, match=rf"duration = 1000000000.0: .*<= {MAX_RUN_DURATION:g} \[s\]"):
        loop.run(duration=1e9)
    walker = FullBodyLoop(robot, planner=CapturePointPlanner(), sim=loop.sim, wbc=loop.wbc)
    with pytest.raises(InvalidInputError, match=r"n_steps = 'x'"):
        walker.run(n_steps="x")
    with pytest.raises(InvalidInputError, match=r"n_steps = 100000000000: expected a number of steps >= 1 and <= 5000"):
        walker.run(n_steps=10**11)
    with pytest.raises(InvalidInputError, match=r"robot = 'digit_like': expected a lipmpcc.robots.RobotDescription"):
        FullBodyLoop("digit_like", sim=loop.sim, wbc=loop.wbc)
    with pytest.raises(InvalidInputError, match=r"params = "):
        FullBodyLoop(robot, params={"com_height": 0.9}, sim=loop.sim, wbc=loop.wbc)
