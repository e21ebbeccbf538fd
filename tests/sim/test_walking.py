"""Full-body walking on digit_like: MuJoCo 2 kHz + C++ whole-body QP 400 Hz + capture-point steps.

The four runs of the issue — standing under pushes, 10 m straight at ≥ 0.5 m/s, a full 2 m-radius
circle, 20 steps in place — and the CLI's summary.json. None may fall. Also the loop's parts without
MuJoCo: the gait state machine and the references it gives, on hand-made measurements.
"""

from __future__ import annotations

import json
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


@slow
def test_cli_walk_and_stand_write_full_body_summary(tmp_path) -> None:
    from lipmpcc.cli import main

    out = tmp_path / "walk"
    assert main(["run", "walk", "--robot", "digit_like", "--steps", "6", "--speed", "0.4", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"] == "walk" and s["planner"] == "capture-point" and s["robot"] == "digit_like"
    assert s["fell"] is False and s["steps"] == 6
    assert set(s["wbc_ms"]) == {"median", "p90", "max"}
    assert 0 < s["wbc_ms"]["median"] <= s["wbc_ms"]["p90"] <= s["wbc_ms"]["max"]
    assert isinstance(s["qp_failures"], int)
    assert s["real_time_factor"] > 0
    assert 0.5 < s["min_base_height_m"] < 1.2
    assert s["distance_walked_m"] > 0.3
    assert (out / "walk_top.png").stat().st_size > 0

    out = tmp_path / "stand"
    assert main(["run", "stand", "--robot", "digit_like", "--duration", "1.5", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"] == "stand" and s["fell"] is False
    for key in ("wbc_ms", "qp_failures", "real_time_factor", "min_base_height_m", "distance_walked_m"):
        assert key in s
    assert (out / "stand.png").stat().st_size > 0


@slow
def test_cli_rejects_bad_options(tmp_path, capsys) -> None:
    from lipmpcc.cli import main

    assert main(["run", "walk", "--robot", "lip", "--out", str(tmp_path)]) == 1
    assert "--robot" in capsys.readouterr().err
    assert main(["run", "walk", "--planner", "mpcc", "--out", str(tmp_path)]) == 1
    assert "capture-point" in capsys.readouterr().err
    assert main(["run", "walk", "--speed", "7", "--steps", "2", "--out", str(tmp_path)]) == 1
    assert "speed" in capsys.readouterr().err


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


# --------------------------------------------------------------------------------------------
# The gait state machine and the references, on hand-made measurements (no MuJoCo)
# --------------------------------------------------------------------------------------------
class _FixedSteps:
    """A footstep planner: 0.1 m ahead of the swing foot, 0.4 s steps, at 10 Hz; keeps its inputs."""

    name = "fixed"
    rate_hz = 10.0

    def __init__(self) -> None:
        self.inputs: list = []

    def reset(self) -> None:
        self.inputs.clear()

    def plan(self, inp):
        from lipmpcc.planners.base import StepPlan

        self.inputs.append(inp)
        return StepPlan(foothold=inp.swing_pos[:2] + np.array([0.1, 0.0]), yaw=0.0, duration=0.4)


def _measurement(t: float = 0.0, contact: tuple[bool, bool] = (True, True)):
    from lipmpcc.sim.types import FramePose, Measurement

    eye = np.eye(3)
    feet = (FramePose(np.array([0.0, 0.1, 0.0]), eye), FramePose(np.array([0.0, -0.1, 0.0]), eye))
    return Measurement(time=t, q=np.zeros(7), v=np.zeros(6), com=np.array([0.0, 0.0, 0.9]), com_vel=np.zeros(3),
                       torso=FramePose(np.array([0.0, 0.0, 1.0]), eye), feet=feet, contact=contact,
                       normal_force=(200.0, 200.0))


def test_gait_goes_shift_single_double_single_and_finishes() -> None:
    from lipmpcc.conventions import LEFT, RIGHT
    from lipmpcc.loops.fullbody import Gait, GaitMode, LoopParams

    planner = _FixedSteps()
    p = LoopParams(initial_shift=0.2, double_support=0.1, touchdown_min_phase=0.6)
    gait = Gait(planner, p, com_height=0.9, mass=40.0, max_steps=2)
    m = _measurement()
    gait.start(0.0, m)
    assert gait.mode is GaitMode.SHIFT and gait.stance is RIGHT and gait.stance_code == 2

    assert not gait.update(0.1, m) and gait.mode is GaitMode.SHIFT and not planner.inputs
    assert gait.update(0.2, m)  # the shift ends: the left foot lifts, the planner is asked
    assert gait.mode is GaitMode.SINGLE and gait.swing is LEFT and gait.stance_code == 1
    first = planner.inputs[0]
    assert first.stance_side == RIGHT and first.step_index == 0 and first.time_since_touchdown == 0.0
    assert gait.step.t_end == pytest.approx(0.6)

    assert not gait.update(0.25, m)  # a contact before touchdown_min_phase is no touch-down
    assert gait.update(0.3, m) and len(planner.inputs) == 2  # the planner again, at 10 Hz
    assert gait.next_plan_t == pytest.approx(0.4)

    assert gait.update(0.48, m)  # phase 0.7 with contact: touch-down, then double support
    td = gait.touchdowns[0]
    assert td.side == LEFT and td.by_contact and td.duration == pytest.approx(0.28)
    assert gait.mode is GaitMode.DOUBLE and gait.stance is LEFT and gait.stance_code == 2
    assert gait.t_lift == pytest.approx(0.58)
    assert not gait.update(0.5, m) and len(planner.inputs) == 2

    assert gait.update(0.58, m) and gait.mode is GaitMode.SINGLE and gait.swing is RIGHT
    assert planner.inputs[-1].step_index == 1 and planner.inputs[-1].time_since_touchdown == pytest.approx(0.1)
    t_end = gait.step.t_end
    assert gait.update(t_end, _measurement(t_end, contact=(True, False)))  # by the clock
    assert gait.finished and len(gait.touchdowns) == 2 and not gait.touchdowns[1].by_contact


def test_gait_stands_without_planner_and_lifts_at_once_without_shift() -> None:
    from lipmpcc.loops.fullbody import Gait, GaitMode, LoopParams

    standing = Gait(None, LoopParams(), com_height=0.9, mass=40.0)
    standing.start(0.0, _measurement())
    assert standing.mode is GaitMode.STAND and not standing.update(5.0, _measurement(5.0))

    planner = _FixedSteps()
    gait = Gait(planner, LoopParams(initial_shift=0.0, first_stance="left"), com_height=0.9, mass=40.0)
    gait.start(1.0, _measurement(1.0))
    assert gait.mode is GaitMode.DOUBLE
    assert gait.update(1.0, _measurement(1.0)) and gait.mode is GaitMode.SINGLE and gait.stance_code == 0
    assert planner.inputs[0].stance_side == "left" and planner.inputs[0].mass == 40.0


def test_references_follow_the_gait() -> None:
    """Standing: both feet, the standing COM; single support: the stance foot alone, the swing row
    written; with a load ramp the new stance foot's normal force is bounded just after touch-down."""
    from lipmpcc.conventions import GRAVITY
    from lipmpcc.loops.fullbody import Gait, LoopParams
    from lipmpcc.loops.fullbody.references import WholeBodyReferences

    gait = Gait(None, LoopParams(), com_height=0.9, mass=40.0)
    gait.start(0.0, _measurement())
    refs = WholeBodyReferences(gait, np.zeros(0), np.array([0.01, 0.02]), 0.9, weight=40.0 * GRAVITY, load_ramp=0.1)
    r = refs.evaluate(0.5, 0.3)
    assert refs.ref.contact == (True, True) and r.torso_yaw == 0.3 and np.isnan(r.phase)
    np.testing.assert_array_equal(r.com, [0.01, 0.02, 0.9])
    np.testing.assert_allclose(refs.ref.torso_rot[:2, 0], [np.cos(0.3), np.sin(0.3)])

    planner = _FixedSteps()
    gait = Gait(planner, LoopParams(initial_shift=0.0, double_support=0.05), com_height=0.9, mass=40.0)
    refs = WholeBodyReferences(gait, np.zeros(0), np.zeros(2), 0.9, weight=40.0 * GRAVITY, load_ramp=0.1)
    gait.start(0.0, _measurement())
    gait.update(0.0, _measurement())  # right stance, left foot swings
    r = refs.evaluate(0.1, gait.torso_yaw_ref)
    assert refs.ref.contact == (False, True) and 0.0 < r.phase < 1.0
    np.testing.assert_array_equal(refs.ref.foot_pos[0], r.swing_pos)
    assert refs.ref.max_normal_force == (np.inf, np.inf)  # no touch-down yet
    gait.update(0.3, _measurement(0.3))  # left foot lands (phase 0.75, in contact)
    refs.evaluate(0.32, gait.torso_yaw_ref)
    bound = refs.ref.max_normal_force
    assert bound[1] == np.inf and bound[0] == pytest.approx(0.2 * 1.5 * 40.0 * GRAVITY)
