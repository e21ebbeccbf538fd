"""lipmpcc.planners.sources.mpcc.TimedMpccFootstepSource (formerly sources.mpcc_timed): the timed MPCC as a full-body footstep source, without the simulator
(tests/studies/test_path_following_timed.py walks digit_like with it)."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.conventions import RIGHT
from lipmpcc.exceptions import NoFallbackPlanError, ParameterError
from lipmpcc.models.lip import lip_solution
from lipmpcc.models.lip3d import Lip3dModel
from lipmpcc.paths import LinePath
from lipmpcc.planners.base import FootstepSource, PlannerInput, StepPlan
from lipmpcc.planners.mpcc import MpccParams
from lipmpcc.planners.mpcc_timed import TimedMpccParams
from lipmpcc.planners.sources.mpcc import MpccPlanRecord
from lipmpcc.planners.sources.mpcc import WITHIN_STEP_RATE_HZ, TimedMpccFootstepSource

LINE = LinePath((0, 0), (10, 0))


def _params(**kw) -> TimedMpccParams:
    from lipmpcc.studies.path_following import FULLBODY_RECTANGLE

    prm = MpccParams.overtake_mpcc(model=Lip3dModel(T=0.4, H=0.95), rectangle=FULLBODY_RECTANGLE)
    return TimedMpccParams(mpcc=prm, T_min=0.3, T_max=0.5, **kw)


def _inp(t: float, t_td: float, step: int, com, vel, stance_pos) -> PlannerInput:
    com, vel = np.asarray(com, dtype=float), np.asarray(vel, dtype=float)
    return PlannerInput(
        t=t, com_pos=com, com_vel=vel, dcm=com[:2] + vel[:2] / 3.2, omega=3.2, stance_side=RIGHT,
        stance_pos=np.asarray(stance_pos, dtype=float), stance_yaw=0.0, swing_pos=np.zeros(3), swing_yaw=0.0,
        time_since_touchdown=t - t_td, step_index=step, torso_yaw=0.0, course=LINE,
    )


def test_plans_within_the_step_from_the_measured_state() -> None:
    src = TimedMpccFootstepSource(LINE, _params())
    assert isinstance(src, FootstepSource) and src.rate_hz == WITHIN_STEP_RATE_HZ == 25.0
    foot = [0.0, -0.12, 0.0]
    a = src.plan(_inp(1.1, 1.0, 3, [0.02, -0.05, 0.95], [0.5, 0.1, 0.0], foot))
    b = src.plan(_inp(1.2, 1.0, 3, [0.07, -0.04, 0.95], [0.55, 0.05, 0.0], foot))
    for plan, t_since in ((a, 0.1), (b, 0.2)):
        assert isinstance(plan, StepPlan) and plan.ok
        rec = plan.record
        assert isinstance(rec, MpccPlanRecord) and rec.status == "converged"
        assert plan.duration == pytest.approx(t_since + rec.result.remaining)  # t̃ + τ
        assert 0.3 - 1e-9 <= plan.duration <= 0.5 + 1e-9
        assert rec.t_exchange == pytest.approx(rec.t + rec.result.remaining)
        # x0: the LIP about the stance foot for τ, from the measured state
        c, v, _ = lip_solution(np.array([rec.result.x_now[0], rec.result.x_now[2]]),
                               np.array([rec.result.x_now[1], rec.result.x_now[3]]), np.array(foot[:2]),
                               src.params.model.omega, rec.result.remaining)
        np.testing.assert_allclose(rec.x0[:4], [c[0], v[0], c[1], v[1]], atol=1e-9)
    assert len(src.records) == 2 and src.solver_failures == 0 and len(src.solve_times) == 2


def test_no_plan_at_all_steps_in_place_and_counts_it(monkeypatch) -> None:
    src = TimedMpccFootstepSource(LINE, _params())

    def fail(inp):
        raise NoFallbackPlanError("mpcc-timed", "infeasible", 0)

    monkeypatch.setattr(src.planner, "plan", fail)
    plan = src.plan(_inp(0.6, 0.5, 0, [0.0, -0.05, 0.95], [0.0, 0.0, 0.0], [0.0, -0.12, 0.0]))
    assert not plan.ok and plan.status.startswith("failed") and src.solver_failures == 1
    assert plan.foothold[1] > 0.0  # towards the swing (left) side
    assert plan.duration >= 0.1 + 1.0 / 25.0


def test_bad_parameters_are_named() -> None:
    with pytest.raises(ParameterError, match="TimedMpccParams"):
        TimedMpccFootstepSource(LINE, MpccParams.overtake_mpcc())  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="min_time_to_touchdown"):
        TimedMpccFootstepSource(LINE, _params(min_time_to_touchdown=0.1))  # above 1/25 s
    with pytest.raises(ParameterError, match="rate_hz"):
        TimedMpccFootstepSource(LINE, _params(), rate_hz=0.0)


def test_plans_around_its_obstacles_though_the_loop_gives_none() -> None:
    """The full-body loop's PlannerInput carries no obstacles: the source must plan with its own (before
    the fix, the timed MPCC walked digit_like straight through the 0.8 m/s obstacle)."""
    from lipmpcc.obstacles import Obstacle

    ob = Obstacle(axes=(0.25, 0.25), path=LINE, s0=1.2, speed=0.0)
    foot = [0.0, -0.12, 0.0]
    inp = _inp(0.1, 0.0, 0, [0.02, -0.05, 0.95], [0.8, 0.1, 0.0], foot)
    assert inp.obstacles == ()
    plans = {}
    for name, obs in (("with", [ob]), ("without", [])):
        src = TimedMpccFootstepSource(LINE, _params(), obs)
        plans[name] = src.plan(inp).record.result
    infl = 0.25 + _params().mpcc.obstacle_inflation
    dist = {k: np.hypot(r.states[:, 0] - 1.2, r.states[:, 2]) for k, r in plans.items()}
    assert dist["without"].min() < infl  # on the line, through the obstacle
    assert dist["with"].min() >= infl - 1e-3  # around it


def test_learns_the_early_touch_down_and_asks_the_clock_for_it() -> None:
    """The loop's foot meets the ground before its clock ends: the source asks the clock for the planned
    t̃ + τ minus the learned (executed − requested) offset, so that the foot lands at the planned time."""
    foot = [0.0, -0.12, 0.0]
    out = {}
    for gain in (0.0, 0.5):
        src = TimedMpccFootstepSource(LINE, _params(), timing_gain=gain)
        a = src.plan(_inp(1.1, 1.0, 3, [0.02, -0.05, 0.95], [0.5, 0.1, 0.0], foot))
        assert a.duration == pytest.approx(a.record.duration)  # nothing learned yet
        t_td = 1.0 + a.duration - 0.03  # the foot lands 30 ms before the clock's end
        b = src.plan(_inp(t_td + 0.01, t_td, 4, [0.2, -0.02, 0.95], [0.6, -0.1, 0.0], [0.25, 0.12, 0.0]))
        out[gain] = (src.timing_offset, b.duration - b.record.duration)
        assert b.record.duration == pytest.approx(b.record.time_since_touchdown + b.record.result.remaining)
    assert out[0.0] == (0.0, 0.0)  # no compensation: the clock is asked for the plan as it is
    assert out[0.5][0] == pytest.approx(-0.015)  # half of the 30 ms learned
    assert out[0.5][1] == pytest.approx(0.015)  # the clock ends 15 ms after the planned touch-down
    with pytest.raises(ParameterError, match="timing_gain"):
        TimedMpccFootstepSource(LINE, _params(), timing_gain=2.0)


def test_a_plan_that_asks_to_land_now_does_not_put_the_touch_down_off() -> None:
    """Issue 31, ``digit_like`` timed scene 11: with the early touch-down learned (offset < 0), a foot not down
    at the planned time left the re-plans asking to land now (τ = 0, its bound), and each asked the clock for
    t̃ − offset: every re-plan moved the swing's end on by the re-planning period, the foot landed 0.2 s late
    (0.598 s, T_max 0.5 s) with the COM past it at 1.25 m/s, no plan existed from there and the robot fell.
    Now the re-plans that ask to land now keep the end where the step's request before them put it."""
    src = TimedMpccFootstepSource(LINE, _params(), timing_gain=1.0)
    foot = [0.0, -0.12, 0.0]
    a = src.plan(_inp(1.1, 1.0, 3, [0.02, -0.05, 0.95], [0.5, 0.1, 0.0], foot))
    t_td = 1.0 + a.duration - 0.07  # the foot landed 70 ms before the clock's end: offset −0.07 s learned
    stance = np.array([0.25, -0.12])
    c0, v0 = np.array([0.2, -0.03]), np.array([0.6, 0.1])
    ends, tau = [], []
    for k in range(15):  # re-plans every 40 ms, the foot never meeting the ground, to t̃ = 0.56 s
        ts = 0.04 * k
        c, v, _ = lip_solution(c0, v0, stance, src.params.model.omega, ts)
        plan = src.plan(_inp(t_td + ts, t_td, 4, [c[0], c[1], 0.95], [v[0], v[1], 0.0], [*stance, 0.0]))
        assert plan.ok
        ends.append(t_td + plan.duration)  # the clock's end asked of the loop
        tau.append(plan.record.result.remaining)
    assert src.timing_offset == pytest.approx(-0.07)
    due = next(k for k, x in enumerate(tau) if x <= 1e-6)  # the first plan asking to land now
    assert 0 < due < 14 and all(x <= 1e-6 for x in tau[due:])
    assert max(ends[due:]) <= ends[due - 1] + 1e-12  # the end stays where the request before it put it
    for k in range(due):  # before it, each plan's own time t̃ + τ − offset, as it was
        assert ends[k] == pytest.approx(t_td + 0.04 * k + tau[k] + 0.07, abs=1e-9)
