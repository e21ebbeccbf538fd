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
from ...conftest import package_env, default_sigint

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

    from lipmpcc.loops.fullbody import references as loop_references

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(StepTrajectory, "evaluate", evaluate)
        mp.setattr(loop_references, "compiled_tick_references", lambda: None)  # the Python path calls evaluate
        loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.6), params=LoopParams(helper_thread=True))
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
    else is refused with the value in the message (a push timed from a footstep is armed by the loop:
    tests/loops/test_base.py)."""
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.loops.fullbody import FullBodyLoop

    loop = FullBodyLoop(robot)
    with pytest.raises(InvalidInputError, match=r"pushes = \(0\.2, \(60\.0, 0\.0, 0\.0\)\)"):
        loop.run(duration=0.1, pushes=[(0.2, (60.0, 0.0, 0.0))])
    with pytest.raises(InvalidInputError, match="pushes = 3"):
        loop.run(duration=0.1, pushes=3)

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


@pytest.mark.parametrize("where", ["after_start", "in_step"])
def test_keyboard_interrupt_leaves_the_loop_cleanly(robot, where: str) -> None:
    """Ctrl-C lands between the helper's start and its result (the race of the issue: it became
    ``RuntimeError: release unlocked lock``) or while MuJoCo steps: the KeyboardInterrupt itself
    reaches the caller and the helper thread has ended."""
    import threading

    from lipmpcc.loops.fullbody import overlap
    from lipmpcc.loops.fullbody.loop import FullBodyLoop, LoopParams
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.sim.robot_sim import RobotSim

    calls = {"n": 0}
    target = (overlap.Overlap, "start") if where == "after_start" else (RobotSim, "step")
    original = getattr(*target)

    def interrupted(self, *args, **kwargs):
        out = original(self, *args, **kwargs)
        calls["n"] += 1
        if calls["n"] == 50:
            raise KeyboardInterrupt
        return out

    loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.3), params=LoopParams(helper_thread=True))
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(*target, interrupted)
        with pytest.raises(KeyboardInterrupt):
            loop.run(duration=2.0)
    assert calls["n"] == 50
    assert not any(t.name == overlap.THREAD_NAME for t in threading.enumerate())


_SIGINT_SCRIPT = """
import sys, threading
from lipmpcc.loops.fullbody.loop import FullBodyLoop
from lipmpcc.planners.capture_point import CapturePointPlanner
from lipmpcc.robots import load_robot
loop = FullBodyLoop(load_robot("digit_like"), planner=CapturePointPlanner(speed=0.3))
print("READY", flush=True)
try:
    loop.run(duration=20.0, progress=True)
except KeyboardInterrupt:
    print("INTERRUPTED", sorted(t.name for t in threading.enumerate()), flush=True)
    sys.exit(0)
print("FINISHED", flush=True)
"""


@pytest.mark.parametrize("threads", ["1", "0"])
def test_sigint_during_a_walk_stops_it_promptly(threads: str) -> None:
    """SIGINT during a 20 s digit_like walk, with the loop's helper thread and the WBC's worker on or
    off: the KeyboardInterrupt reaches the caller within a second or two, no RuntimeError, no thread
    left, and the process exits at once."""
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    env = {**package_env(), "LIPMPCC_LOOP_THREAD": threads, "LIPMPCC_WBC_THREAD": threads}
    for delay in (1.0, 1.37):
        p = subprocess.Popen([sys.executable, "-c", _SIGINT_SCRIPT], preexec_fn=default_sigint, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env=env)
        try:
            assert p.stdout.readline().strip() == "READY"
            time.sleep(delay)
            p.send_signal(signal.SIGINT)
            t0 = time.monotonic()
            out, err = p.communicate(timeout=30)
        finally:
            if p.poll() is None:
                p.kill()
        assert time.monotonic() - t0 < 3.0
        assert p.returncode == 0, err[-2000:]
        assert out.startswith("INTERRUPTED") and "lipmpcc-loop-helper" not in out, out
        assert "release unlocked lock" not in err and "Traceback" not in err, err[-2000:]


@pytest.mark.parametrize("path", ["compiled", "python", "no_autoreset"])
def test_a_diverging_simulation_stops_the_run_as_a_fall_at_the_right_time(robot, path: str, tmp_path,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """A 1e9 N push at 0.5 s: MuJoCo's state blows up and MuJoCo resets itself to t = 0 (before, the run
    went on from there, reported a fall at 0.13 s and its log ran backwards in time). The run stops in
    the tick of the divergence, as a fall ("simulation diverged") at ~0.5 s, with one line in its
    warnings; the log never goes back. Both paths of the simulator's tick, and without MuJoCo's reset."""
    import mujoco

    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.sim import _tick
    from lipmpcc.sim.robot_sim import RobotSim

    if path == "compiled" and _tick.TICK is None:
        pytest.skip("lipmpcc._mjtick is not built")
    monkeypatch.chdir(tmp_path)  # MuJoCo writes its warning to MUJOCO_LOG.TXT in the working directory
    with monkeypatch.context() as mp:
        if path == "python":
            mp.setattr(_tick, "TICK", None)
        sim = RobotSim(robot)
    if path == "no_autoreset":
        sim.model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_AUTORESET)
    loop = FullBodyLoop(robot, sim=sim)
    res = loop.run(duration=1.0, pushes=[Push(force=(1e9, 0.0, 0.0), t_start=0.5, duration=0.1)])
    assert res.fell and res.fall_reason == "simulation diverged"
    assert 0.5 <= res.fall_time <= 0.51 and res.sim_time == pytest.approx(res.fall_time)
    assert np.all(np.diff(res.log.t) > 0) and res.log.t[-1] <= res.fall_time
    (line,) = [w for w in res.warnings if "diverged" in w]
    assert line.startswith("MuJoCo: simulation diverged (") and "at t=0.50" in line


def test_a_fall_has_its_reason_and_a_run_without_problems_no_warnings(robot) -> None:
    from lipmpcc.loops.fullbody.loop import FullBodyLoop

    loop = FullBodyLoop(robot)
    calm = loop.run(duration=0.3)
    assert (calm.fell, calm.fall_reason, calm.warnings, calm.relaxed_solves) == (False, None, [], 0)
    pushed = loop.run(duration=1.5, pushes=[Push(force=(3000.0, 0.0, 0.0), t_start=0.1, duration=0.2)])
    assert pushed.fell and pushed.fall_reason and pushed.fall_reason != "simulation diverged"
    assert pushed.warnings == []


def test_a_motor_without_torque_limit_is_warned_about(tmp_path, caplog: pytest.LogCaptureFixture) -> None:
    """``ctrlrange="0 0"`` makes a motor unlimited in MuJoCo: the loop warns (log and result) naming it."""
    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.robots import digit_like_paths, load_robot

    robot_xml, scene_xml = digit_like_paths()
    text = robot_xml.read_text()
    line = next(s for s in text.splitlines() if '<motor name="left_knee"' in s)
    start = line.index('ctrlrange="')
    end = line.index('"', start + len('ctrlrange="')) + 1
    (tmp_path / robot_xml.name).write_text(text.replace(line, line[:start] + 'ctrlrange="0 0"' + line[end:]))
    (tmp_path / scene_xml.name).write_text(scene_xml.read_text())
    robot = load_robot(tmp_path / robot_xml.name)
    assert robot.unlimited_motors() == ("left_knee",)
    with caplog.at_level("WARNING", logger="lipmpcc.loops.fullbody.loop"):
        loop = FullBodyLoop(robot)
    assert any("motor left_knee has no torque limit" in r.getMessage() for r in caplog.records)
    res = loop.run(duration=0.05)
    assert [w for w in res.warnings if "torque limit" in w] == [loop.model_warnings[0]]
    assert "left_knee" in loop.model_warnings[0] and len(loop.model_warnings) == 1
    assert load_robot("digit_like").unlimited_motors() == ()


def test_relaxed_re_solves_are_counted(robot) -> None:
    """Planner answers that came from a relaxed re-solve (status "relaxed: ...", as the ALIP footstep
    source answers a failed solve) are counted in the result's ``relaxed_solves``."""
    import dataclasses

    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.planners.capture_point import CapturePointPlanner

    class Relaxing(CapturePointPlanner):
        calls = 0

        def plan(self, inp):
            plan = super().plan(inp)
            Relaxing.calls += 1
            if Relaxing.calls % 3 == 0:
                Relaxing.last = dataclasses.replace(plan, status="relaxed: solved")
                return Relaxing.last
            if Relaxing.calls % 3 == 1 and Relaxing.calls > 1:
                return Relaxing.last  # the same answer again (held): not a new re-solve
            return plan

    res = FullBodyLoop(robot, planner=Relaxing(speed=0.3)).run(duration=1.5)
    n_relaxed = sum(1 for _, p in res.plans if p.status.startswith("relaxed"))
    assert n_relaxed > res.relaxed_solves == len(res.plans) // 3 > 0


@pytest.fixture
def bar_text(monkeypatch: pytest.MonkeyPatch):
    """The text the loop's progress bar writes (tqdm forced on, into a string)."""
    import io

    import tqdm

    out = io.StringIO()
    original = tqdm.tqdm

    def forced(*args, **kwargs):
        kwargs.update(disable=False, file=out, mininterval=0.0)
        return original(*args, **kwargs)

    monkeypatch.setattr(tqdm, "tqdm", forced)
    return out


def test_progress_bar_shows_rounded_seconds_or_steps_and_ends_full(robot, bar_text) -> None:
    """Issue 15: the bar showed float noise (``22.595000000002333/65.0``) and stopped at 35–44 % when the
    run was bounded by steps. Now: rounded simulated seconds (or steps), full at the end of a run that
    did what it was asked, and a note where a run stopped early."""
    import re

    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.planners.capture_point import CapturePointPlanner

    FullBodyLoop(robot).run(duration=0.3, progress=True)
    text = bar_text.getvalue()
    assert "100%" in text and "0.30/0.30 sim s" in text
    assert not re.search(r"\d\.\d{4,}", text), text[-300:]
    bar_text.truncate(0)
    bar_text.seek(0)
    res = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.3)).run(n_steps=2, progress=True)
    text = bar_text.getvalue()
    assert res.n_steps == 2 and "100%" in text and "2/2 steps" in text and "sim s" not in text
    bar_text.truncate(0)
    bar_text.seek(0)
    fell = FullBodyLoop(robot).run(duration=1.5, progress=True,
                                   pushes=[Push(force=(3000.0, 0.0, 0.0), t_start=0.1, duration=0.2)])
    text = bar_text.getvalue()
    assert fell.fell and "100%" not in text and f"at t={fell.fall_time:.2f} s" in text
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


def test_the_per_tick_hook_is_called_at_its_rate_and_changes_nothing(robot) -> None:
    """``run(on_tick=...)``: called after the first tick and then at most ``on_tick_hz`` times per simulated
    second, with the time, the simulator and the gait; the walk is the same, to the bit, as without it."""
    from lipmpcc.exceptions import InvalidInputError

    calls: list[tuple[float, int, int]] = []

    def hook(t, sim, gait) -> None:
        assert t == pytest.approx(sim.time)
        calls.append((t, len(gait.touchdowns), len(gait.plans)))

    push = [Push(t_start=0.5, force=(30.0, 0.0, 0.0), duration=0.1)]
    a = _loop(robot, 0.4).run(duration=1.5, pushes=push)
    b = _loop(robot, 0.4).run(duration=1.5, pushes=push, on_tick=hook, on_tick_hz=20.0)
    for name in set(a.log.__dataclass_fields__) - {"wbc_time"}:
        np.testing.assert_array_equal(np.asarray(getattr(a.log, name)), np.asarray(getattr(b.log, name)), err_msg=name)
    assert [(td.t, td.side) for td in a.touchdowns] == [(td.t, td.side) for td in b.touchdowns]
    times = np.array([c[0] for c in calls])
    assert times[0] == pytest.approx(0.0025, abs=1e-9)  # after the first tick (400 Hz)
    assert len(times) == 31  # then on the 20 Hz grid from the start, to 1.5 s
    np.testing.assert_allclose(times[1:], 0.05 * np.arange(1, 31), atol=1e-9)
    assert calls[-1][1] == len(b.touchdowns) and calls[-1][2] >= 1
    loop = _loop(robot, 0.4)
    with pytest.raises(InvalidInputError, match="on_tick"):
        loop.run(duration=0.1, on_tick="not callable")
    with pytest.raises(InvalidInputError, match="on_tick_hz"):
        loop.run(duration=0.1, on_tick=hook, on_tick_hz=0.0)


@slow
def test_a_planner_rate_that_is_not_a_number_or_past_the_wbc_rate_is_refused(robot) -> None:
    from lipmpcc.exceptions import InvalidInputError, ParameterError
    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.planners.capture_point import CapturePointPlanner

    loop = FullBodyLoop(robot)
    for bad in ("25", 1e9, float("nan"), 0.0):
        planner = CapturePointPlanner()
        planner.rate_hz = bad
        with pytest.raises(ParameterError, match=r"planner\.rate_hz = .*<= 400 Hz"):
            FullBodyLoop(robot, planner=planner, sim=loop.sim, wbc=loop.wbc)
    planner = CapturePointPlanner()
    planner.name = 42
    with pytest.raises(InvalidInputError, match=r"planner\.name = 42"):
        FullBodyLoop(robot, planner=planner, sim=loop.sim, wbc=loop.wbc)
    planner = CapturePointPlanner()
    planner.rate_hz = 400.0  # once per WBC tick: the most the loop can do
    assert FullBodyLoop(robot, planner=planner, sim=loop.sim, wbc=loop.wbc).planner is planner
