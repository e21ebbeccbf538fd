"""lipmpcc.planners.mpcc_timed: the MPCC with step durations as decision variables.

It reduces to the fixed-T MPCC, SQP and IPOPT agree, the plan keeps every constraint with its own
durations, durations answer pushes as in paper B's Fig. 7, it overtakes an obstacle that fixed T cannot,
and it fails, falls back and refuses bad input as the MPCC does.
"""

import math
from dataclasses import replace

import casadi as ca
import numpy as np
import pytest

from lipmpcc.exceptions import NoFallbackPlanError, ParameterError, StateError
from lipmpcc.models.lip import lip_solution
from lipmpcc.models.lip3d import Lip3dModel
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import ArcPath, LinePath
from lipmpcc.planners.base import FootstepSource, PlannerInput, StepPlan
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.planners.mpcc_timed import NHEAD, TimedMpccParams, TimedMpccPlanner, TimedMpccResult, timed_lip_step


def _range(mpcc: MpccParams, lo: float = 0.3, hi: float = 0.5, **kw) -> TimedMpccParams:
    return TimedMpccParams(mpcc=mpcc, T_min=lo, T_max=hi, **kw)


# ---- parameters -------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "kw, name",
    [
        ({"T_min": 0.0}, "T_min"),
        ({"T_min": -0.1}, "T_min"),
        ({"T_min": 0.45, "T_max": 0.35}, "T_min"),
        ({"T_min": math.nan}, "T_min"),
        ({"T_max": math.inf}, "T_max"),
        ({"T_min": "0.3"}, "T_min"),
        ({"T_min": 0.45, "T_max": 0.5}, "mpcc.model.T"),  # the nominal T = 0.4 is outside
        ({"duration_weight": -1.0}, "duration_weight"),
        ({"min_time_to_touchdown": 0.5}, "min_time_to_touchdown"),
        ({"anchor_slack_weight": -1.0}, "anchor_slack_weight"),
        ({"anchor_slack_weight": math.nan}, "anchor_slack_weight"),
        ({"mpcc": "circle"}, "mpcc"),
    ],
)
def test_bad_parameters_are_named(kw, name):
    with pytest.raises(ParameterError) as exc:
        TimedMpccParams(**kw)
    assert exc.value.name == name


def test_parameters_accept_numpy_scalars_and_a_fixed_range():
    p = TimedMpccParams(T_min=np.float32(0.3), T_max=np.float64(0.5))
    assert isinstance(p.T_min, float) and p.T_min == pytest.approx(0.3) and p.T_nom == 0.4
    f = TimedMpccParams.fixed(MpccParams.circle())
    assert f.T_min == f.T_max == 0.4 and f.d_gain == 0.0
    assert float(f.duration(0.7)) == 0.4  # the duration variable has no effect
    assert float(p.duration(p.offset(0.45))) == pytest.approx(0.45)
    with pytest.raises(ParameterError):
        TimedMpccPlanner(ArcPath.circle(2.0), MpccParams())  # not a TimedMpccParams


def test_symbolic_step_map_is_lip3d():
    m = Lip3dModel(T=0.37, H=0.9)
    x, u, T = ca.SX.sym("x", 5), ca.SX.sym("u", 3), ca.SX.sym("T")
    f = ca.Function("f", [x, u, T], [timed_lip_step(x, u, T, m.omega)])
    xv, uv = np.array([0.1, 0.4, -0.2, 0.1, 0.3]), np.array([0.2, -0.15, 0.05])
    assert np.allclose(np.asarray(f(xv, uv, 0.37)).ravel(), m.step(xv, uv), atol=1e-12)


# ---- reduction to the fixed-T MPCC --------------------------------------------------------------
@pytest.mark.parametrize("case", ["circle", "obstacle", "cartesian"])
def test_fixed_range_gives_the_fixed_T_mpcc(case):
    """T_min = T_max = T: the same footsteps as MpccPlanner, step after step, within solver tolerance
    (the Cartesian MPC, Q̄ = αI, included)."""
    if case == "circle":
        path, prm, obstacles, n = ArcPath.circle(2.0), MpccParams.circle(), [], 8
    elif case == "cartesian":
        path, prm = LinePath((0, 0), (30, 0)), MpccParams.overtake_cartesian()
        obstacles, n = [Obstacle.circle(0.25, path=path, s0=1.5, speed=0.1)], 10
    else:
        path, prm = LinePath((0, 0), (30, 0)), MpccParams.overtake_mpcc()
        obstacles, n = [Obstacle.circle(0.25, path=path, s0=1.2, speed=0.3)], 12
    fixed, timed = MpccPlanner(path, prm), TimedMpccPlanner(path, TimedMpccParams.fixed(prm))
    x, side, m = np.zeros(5), 1, prm.model
    for k in range(n):
        a = fixed.solve(x, side, obstacles, t_now=k * m.T)
        b = timed.solve(x, side, obstacles, t_now=k * m.T)
        assert a.found and b.found
        np.testing.assert_allclose(b.footsteps, a.footsteps, atol=1e-4)
        np.testing.assert_allclose(b.states, a.states, atol=1e-4)
        np.testing.assert_allclose(b.v, a.v, atol=1e-4)
        assert np.all(b.durations == m.T) and b.remaining == 0.0
        assert b.cost == pytest.approx(a.cost, abs=1e-5 * max(1.0, abs(a.cost)))
        x, side = m.step(x, a.u0), -side


# ---- the plan ---------------------------------------------------------------------------------
def _walk(planner, n, obstacles=(), x=None):
    x, side, t, r = np.zeros(5) if x is None else x, 1, 0.0, None
    for _ in range(n):
        r = planner.solve(x, side, obstacles, t_now=t)
        x, t, side = r.states[1], t + float(r.durations[0]), -side
    return x, side, t, r


def test_plan_keeps_every_constraint_with_its_durations():
    path = LinePath((0, 0), (30, 0))
    ob = Obstacle.circle(0.25, path=path, s0=1.5, speed=0.6)
    prm = _range(MpccParams.overtake_mpcc())
    m, N = prm.mpcc, prm.N
    pl = TimedMpccPlanner(path, prm)
    x, side, t, _ = _walk(pl, 6, [ob])
    r = pl.solve(x, side, [ob], t_now=t)
    assert r.found and isinstance(r, TimedMpccResult)
    assert np.all(r.durations >= prm.T_min - 1e-9) and np.all(r.durations <= prm.T_max + 1e-9)
    np.testing.assert_allclose(r.exchange_times, t + np.r_[0.0, np.cumsum(r.durations)], atol=1e-12)
    for k in range(N):
        step = replace(m.model, T=float(r.durations[k])).step(r.states[k], r.inputs[k])
        np.testing.assert_allclose(r.states[k + 1], step, atol=1e-9)
        s = side * (1 if k % 2 == 0 else -1)
        assert m.rectangle.contains(r.inputs[k], r.states[k, 4] + r.inputs[k, 2], s, tol=1e-6)
        d = np.hypot(*(r.states[k + 1, [0, 2]] - r.states[k, [0, 2]]))
        assert m.delta_min - 1e-6 <= d <= m.delta_max + 1e-6
    # the CBF with the obstacle where it is at the planned times (not at k T)
    tk = r.exchange_times
    r_inf = ob.axes[0] + m.obstacle_inflation
    bb = np.sum((r.states[:, [0, 2]] - ob.center(tk)) ** 2, axis=1) / r_inf**2 - 1
    assert np.all(bb[1:] >= (1 - m.gamma) * bb[:-1] - 1e-6)
    assert np.all(ob.clearance(r.footsteps[:, :2], tk[:-1], m.foot_radius + m.obstacle_margin) >= -1e-6)
    assert np.all(r.v >= -1e-9) and np.all(r.v <= m.v_max + 1e-9)


@pytest.mark.parametrize("case", ["circle", "obstacle"])
def test_sqp_and_ipopt_solve_the_same_problem(case):
    """IPOPT's solution of the lifted formulation is a fixed point of the condensed SQP (same problem),
    and the SQP's local minimum is at least as good."""
    if case == "circle":
        path, prm, obstacles = ArcPath.circle(2.0), _range(MpccParams.circle()), []
    else:
        path = LinePath((0, 0), (30, 0))
        prm, obstacles = _range(MpccParams.overtake_mpcc()), [Obstacle.circle(0.25, path=path, s0=1.5, speed=0.8)]
    fast = TimedMpccPlanner(path, prm)
    ref = TimedMpccPlanner(path, prm.with_(mpcc=prm.mpcc.with_(solver="ipopt")))
    x, side, t = np.zeros(5), 1, 0.0
    same = 0
    for k in range(8):
        rf = fast.solve(x, side, obstacles, t_now=t)
        ri = ref.solve(x, side, obstacles, t_now=t)
        assert rf.found and ri.found
        scale = max(1.0, abs(ri.cost))
        # non-convex (−ρv², the durations): the two may stop in different local minima of similar quality
        assert rf.cost <= ri.cost + 0.05 * scale
        same += abs(rf.cost - ri.cost) < 1e-5 * scale
        # the SQP started at IPOPT's solution stays there
        call = fast._call(x, side, t, None, None, ri.theta_init, True)
        Zi = np.concatenate([np.zeros(NHEAD), np.column_stack([ri.inputs, ri.v, prm.offset(ri.durations)]).ravel()])
        p = fast.parameters(call, obstacles, fast._times(call, Zi))
        sol = fast._get(len(obstacles))["sqp"].solve(Zi, (p,))
        assert sol.found and sol.iterations <= 3
        assert sol.cost == pytest.approx(ri.cost, abs=1e-5 * scale)
        np.testing.assert_allclose(prm.duration(sol.u[NHEAD + 4 :: 5]), ri.durations, atol=1e-3)
        x, t, side = ri.states[1], t + float(ri.durations[0]), -side
    assert same >= 4


def test_sqp_and_ipopt_agree_within_a_step():
    """Mid-step, with an obstacle: the SQP started at IPOPT's solution stays there (τ, v_pre included)."""
    prm = _range(MpccParams.overtake_mpcc())
    path, x_now, foot, side, t = _steady_mid_step(prm, 0.12)
    obstacles = [Obstacle.circle(0.25, path=path, s0=x_now[0] + 0.6 - 0.8 * t, speed=0.8)]
    fast = TimedMpccPlanner(path, prm, within_step=True)
    ref = TimedMpccPlanner(path, prm.with_(mpcc=prm.mpcc.with_(solver="ipopt")), within_step=True)
    kw = dict(t_now=t, time_since_touchdown=0.12, stance_foot=foot)
    rf, ri = fast.solve(x_now, side, obstacles, **kw), ref.solve(x_now, side, obstacles, **kw)
    assert rf.found and ri.found
    scale = max(1.0, abs(ri.cost))
    assert rf.cost <= ri.cost + 0.05 * scale
    call = fast._call(x_now, side, t, 0.12, foot, ri.theta_now, True)
    head = [call.d_tau(ri.remaining), ri.theta[0] - ri.theta_now, ri.anchor_slack]
    Zi = np.concatenate([head, np.column_stack([ri.inputs, ri.v, prm.offset(ri.durations)]).ravel()])
    p = fast.parameters(call, obstacles, fast._times(call, Zi))
    sol = fast._get(1)["sqp"].solve(Zi, (p,))
    assert sol.found and sol.iterations <= 3
    assert sol.cost == pytest.approx(ri.cost, abs=1e-5 * scale)
    assert call.tau(sol.u[0]) == pytest.approx(ri.remaining, abs=1e-3)


def _steady_mid_step(prm: TimedMpccParams, t_since: float):
    """A steady walk on a line, then the state t_since after the next touch-down: (x_now, foot, side, t)."""
    path = LinePath((0, 0), (30, 0))
    pl = TimedMpccPlanner(path, prm)
    x, side, t, _ = _walk(pl, 12)
    r = pl.solve(x, side, t_now=t)
    foot = r.footsteps[0, :2]
    c, v, _ = lip_solution(x[[0, 2]], x[[1, 3]], foot, prm.omega, t_since)
    return path, np.array([c[0], v[0], c[1], v[1], x[4]]), foot, -side, t + t_since


def test_durations_answer_pushes_as_paper_b_fig7():
    """Mid-step (t̃ = 0.15 s), a forward push (the DCM ahead) makes the planner end the step sooner, a
    backward push later, than without the push; the first foothold moves with the DCM. (Paper A's cost
    and the duration term only: the speed reward would keep these weights' steps at T_min anyway.)"""
    prm = _range(MpccParams.overtake_mpcc(), reward_speed=False)
    ts = 0.15
    path, x_now, foot, side, t = _steady_mid_step(prm, ts)
    out = {}
    pl = TimedMpccPlanner(path, prm, within_step=True)
    for name, dv in (("none", 0.0), ("forward", 0.3), ("backward", -0.3)):  # 150 N for 0.1 s on 48 kg
        x = x_now + np.array([0.0, dv, 0.0, 0.0, 0.0])
        pl.reset()  # each from a cold start (the built solvers are kept)
        r = pl.solve(x, side, t_now=t, time_since_touchdown=ts, stance_foot=foot)
        assert r.found and r.remaining >= prm.min_time_to_touchdown
        out[name] = r
    T = {k: r.step_duration for k, r in out.items()}
    assert T["forward"] < T["none"] - 0.03 and T["backward"] > T["none"] + 0.02, T
    fx = {k: r.footsteps[0, 0] for k, r in out.items()}
    assert fx["forward"] > fx["none"] > fx["backward"]


def test_within_step_plan_starts_from_the_measured_state():
    prm = _range(MpccParams.overtake_mpcc(), min_time_to_touchdown=0.05)
    path, x_now, foot, side, t = _steady_mid_step(prm, 0.1)
    pl = TimedMpccPlanner(path, prm, within_step=True)
    r = pl.solve(x_now, side, t_now=t, time_since_touchdown=0.1, stance_foot=foot)
    # the exchange state is the LIP about the stance foot for the planned remaining time
    c, v, _ = lip_solution(x_now[[0, 2]], x_now[[1, 3]], foot, prm.omega, r.remaining)
    np.testing.assert_allclose(r.states[0, :4], [c[0], v[0], c[1], v[1]], atol=1e-9)
    assert prm.T_min - 1e-9 <= r.step_duration <= prm.T_max + 1e-9
    assert r.theta[0] >= r.theta_now - 1e-9 and r.exchange_times[0] == pytest.approx(t + r.remaining)
    # late in the step the remaining time is at least min_time_to_touchdown, but the step ends by T_max
    late = pl.solve(x_now, side, t_now=t, time_since_touchdown=0.4, stance_foot=foot, shift=False)
    assert prm.min_time_to_touchdown - 1e-9 <= late.remaining <= 0.1 + 1e-9
    last = pl.solve(x_now, side, t_now=t, time_since_touchdown=0.48, stance_foot=foot, shift=False)
    assert last.remaining == pytest.approx(0.02) and last.step_duration == pytest.approx(prm.T_max)
    with pytest.raises(StateError):
        pl.solve(x_now, side, t_now=t, time_since_touchdown=0.1)  # no stance foot
    with pytest.raises(StateError):
        pl.solve(x_now, side, t_now=t, time_since_touchdown=-0.1, stance_foot=foot)


def test_current_step_barrier_is_soft_when_no_remaining_time_can_keep_it():
    """A state measured on digit_like (2026-12-03, the timed overtake at 0.8 m/s with a 0.415 m body disk),
    shifted to the obstacle: the COM 0.64 m ahead of the obstacle's centre and 0.39 m beside it, inside the
    grown obstacle (0.765 m), its stance foot just placed 0.08 m further out. About that foot the COM drifts
    further in whatever the remaining time τ: the hard row b(x_0) ≥ (1 − γ) b(x_now) has no solution (the QP
    was infeasible and the replayed old plans diverged). The soft row plans, relaxed by the least slack:
    the exchange as far out as the stance foot lets it (τ = T_max here); a row that can be kept is kept."""
    path = LinePath((-10, 0), (30, 0))
    mpcc = MpccParams.overtake_mpcc(model=Lip3dModel(T=0.4, H=0.953), robot_radius=0.415, obstacle_margin=0.1,
                                    heading_weight=20.0)
    mpcc = mpcc.with_(rectangle=replace(mpcc.rectangle, forward=(-0.35, 0.35), lateral=(0.10, 0.40)))
    ob = Obstacle.circle(0.25, path=path, s0=10.0, speed=0.8)  # its centre at x = 0 at t = 0
    x_now, foot = np.array([0.6353, 0.9411, -0.3870, 0.0460, 0.1112]), np.array([0.7802, -0.4715])
    kw = dict(t_now=0.0, time_since_touchdown=0.0, stance_foot=foot)
    hard = TimedMpccPlanner(path, _range(mpcc, anchor_slack_weight=math.inf), within_step=True)
    with pytest.raises(NoFallbackPlanError):
        hard.solve(x_now, 1, [ob], **kw)
    prm = _range(mpcc)
    assert prm.anchor_slack_weight == 1e4  # the default: soft
    pl = TimedMpccPlanner(path, prm, within_step=True)
    r = pl.solve(x_now, 1, [ob], **kw)
    assert r.found and pl.failures == 0 and r.anchor_slack > 0.01

    R = 0.25 + mpcc.obstacle_inflation

    def b(tau: float) -> float:
        c, _, _ = lip_solution(x_now[[0, 2]], x_now[[1, 3]], foot, prm.omega, tau)
        return float(np.sum((c - ob.center(tau)) ** 2) / R**2 - 1.0)

    b_now = b(0.0)
    assert b_now < 0.0 and max(b(tau) for tau in np.linspace(0.3, 0.5, 41)) < (1 - mpcc.gamma) * b_now
    assert r.remaining == pytest.approx(0.5, abs=1e-3) and b(r.remaining) + r.anchor_slack >= (1 - mpcc.gamma) * b_now - 1e-6
    # far from the obstacle the row holds: no slack
    far = TimedMpccPlanner(path, prm, within_step=True).solve(x_now, 1, [Obstacle.circle(0.25, path=path, s0=5.0, speed=0.8)], **kw)
    assert far.found and far.anchor_slack < 1e-6


# ---- overtaking -------------------------------------------------------------------------------
def test_overtakes_a_08_m_per_s_obstacle_that_fixed_T_cannot():
    """On the LIP loop, an obstacle at 0.8 m/s along the line: fixed T = 0.4 s tops out at
    v_max / T = 0.75 m/s and never passes it; with T ∈ [0.3, 0.5] s the planner shortens its steps and
    overtakes it without contact."""
    from lipmpcc.loops.lip import run_lip_loop, summarize

    path = LinePath((0, 0), (40, 0))
    obstacles = [Obstacle.circle(0.25, path=path, s0=1.0, speed=0.8)]
    prm = MpccParams.overtake_mpcc()
    out = {}
    for name, pl in (("fixed", MpccPlanner(path, prm)), ("timed", TimedMpccPlanner(path, _range(prm)))):
        log = run_lip_loop(pl, np.zeros(5), 45, path, obstacles, robot_radius=prm.robot_radius, foot_radius=prm.foot_radius)
        out[name] = (log, summarize(log, obstacles))
    log_f, s_f = out["fixed"]
    log_t, s_t = out["timed"]
    assert not s_f["overtook"] and not log_f.fell
    assert s_t["overtook"] and not log_t.fell and s_t["min_clearance_m"] > 0.0
    assert np.median(np.diff(log_t.t)) < 0.35  # it walks with shorter steps
    # the executed durations are the planned ones
    np.testing.assert_allclose(np.diff(log_t.t), [p.durations[0] for p in log_t.plans], atol=1e-12)


# ---- the planner contract, failures -----------------------------------------------------------
def _input(x, k, t, stance_side, path, t_since=0.4, stance=(0.0, 0.0), obstacles=()):
    return PlannerInput(
        t=t, com_pos=np.array([x[0], x[2], 0.9]), com_vel=np.array([x[1], x[3], 0.0]), dcm=np.zeros(2), omega=3.3,
        stance_side=stance_side, stance_pos=np.array([stance[0], stance[1], 0.0]), stance_yaw=float(x[4]),
        swing_pos=np.zeros(3), swing_yaw=0.0, time_since_touchdown=t_since, step_index=k, torso_yaw=float(x[4]),
        course=path, obstacles=tuple(obstacles),
    )


def test_plan_is_the_contract_at_exchanges_and_within_steps():
    path = LinePath((0, 0), (30, 0))
    prm = _range(MpccParams.overtake_mpcc())
    pl = TimedMpccPlanner(path, prm)
    assert isinstance(pl, FootstepSource) and pl.rate_hz == 15.0
    x = np.array([0.1, 0.3, -0.05, 0.0, 0.0])
    plan = pl.plan(_input(x, 0, 1.2, "right", path))
    assert isinstance(plan, StepPlan) and plan.ok and plan.record.stance_side == +1
    assert plan.duration == plan.record.durations[0]
    np.testing.assert_allclose(plan.foothold, x[[0, 2]] + plan.record.inputs[0, :2])
    np.testing.assert_allclose(plan.preview[:, 3], plan.record.durations)
    assert pl.plan(_input(x, 0, 1.25, "right", path)) is plan  # once per step at exchanges
    # within steps: re-planned at every call, the duration counted from the touch-down
    pw = TimedMpccPlanner(path, prm, within_step=True)
    assert pw.rate_hz == 25.0
    p1 = pw.plan(_input(x, 0, 1.2, "right", path, t_since=0.1, stance=(0.05, -0.1)))
    p2 = pw.plan(_input(x, 0, 1.24, "right", path, t_since=0.14, stance=(0.05, -0.1)))
    assert p1 is not p2 and p1.ok and p2.ok
    assert p2.duration == pytest.approx(0.14 + p2.record.remaining)
    assert p2.duration >= 0.14 + prm.min_time_to_touchdown


def test_fallback_and_failure_counts(monkeypatch):
    path = ArcPath.circle(2.0)
    pl = TimedMpccPlanner(path, _range(MpccParams.circle()))
    x, side, t, last = _walk(pl, 3)
    monkeypatch.setattr(pl, "_attempt", lambda *a, **k: None)  # every solve fails from now on
    r = pl.solve(x, side, t_now=t)
    assert r.used_fallback and not r.found and pl.failures == 1 and pl.solves == 4
    np.testing.assert_allclose(r.inputs[:-1], last.inputs[1:])  # the shifted previous plan
    np.testing.assert_allclose(r.durations[:-1], last.durations[1:])
    np.testing.assert_allclose(r.states[0], x)
    plan = pl.plan(_input(r.states[1], 9, t + 0.4, "left", path))
    assert not plan.ok and plan.status.startswith("fallback") and pl.failures == 2
    fresh = TimedMpccPlanner(path, _range(MpccParams.circle()))
    monkeypatch.setattr(fresh, "_attempt", lambda *a, **k: None)
    with pytest.raises(NoFallbackPlanError):
        fresh.solve(np.zeros(5), 1)


def test_bad_state_and_side_are_refused():
    pl = TimedMpccPlanner(ArcPath.circle(2.0), _range(MpccParams.circle()))
    with pytest.raises(StateError):
        pl.solve(np.array([0.0, math.nan, 0.0, 0.0, 0.0]), 1)
    with pytest.raises(ParameterError):
        pl.solve(np.zeros(5), 0)


@pytest.mark.parametrize("inp", [None, "state", {"t": 0.0}])
def test_plan_of_something_else_than_a_planner_input_is_named(inp):
    pl = TimedMpccPlanner(ArcPath.circle(2.0), _range(MpccParams.circle()))
    with pytest.raises(StateError, match=r"inp = .*expected a lipmpcc.planners.base.PlannerInput"):
        pl.plan(inp)


def test_within_step_loop_on_the_lip_overtakes_without_contact():
    """A small closed loop re-planning at 25 Hz within each step (the point foot lands at the latest planned
    time, as paper B's loop): it passes the 0.8 m/s obstacle with a positive clearance, in steps that end by
    T_max, without a solver failure."""
    path = LinePath((0, 0), (40, 0))
    ob = Obstacle.circle(0.25, path=path, s0=1.0, speed=0.8)
    prm = _range(MpccParams.overtake_mpcc())
    pl = TimedMpccPlanner(path, prm, within_step=True)
    x, foot, side, t, t_td, shift = np.zeros(5), np.zeros(2), 1, 0.0, 0.0, True
    steps, clear = [], np.inf
    while t < 12.0:
        inp = PlannerInput(
            t=t, com_pos=np.array([x[0], x[2], 0.9]), com_vel=np.array([x[1], x[3], 0.0]), dcm=np.zeros(2),
            omega=prm.omega, stance_side="right" if side == 1 else "left", stance_pos=np.r_[foot, 0.0],
            stance_yaw=float(x[4]), swing_pos=np.zeros(3), swing_yaw=0.0, time_since_touchdown=t - t_td,
            step_index=len(steps), torso_yaw=float(x[4]), course=path, obstacles=(ob,),
        )
        plan = pl.plan(inp)
        assert plan.ok
        r = plan.record
        h = min(0.04, r.remaining)
        c, v, _ = lip_solution(x[[0, 2]], x[[1, 3]], foot, prm.omega, h)
        x, t = np.array([c[0], v[0], c[1], v[1], x[4]]), t + h
        clear = min(clear, float(ob.clearance(x[[0, 2]], t, prm.mpcc.robot_radius)[0]))
        if h >= r.remaining - 1e-12:  # touch-down where and when planned
            assert t - t_td == pytest.approx(plan.duration)
            steps.append(t - t_td)
            foot, x[4], t_td, side = plan.foothold.copy(), plan.yaw, t, -side
    assert pl.failures == 0 and clear > 0.0
    assert all(prm.T_min - 1e-9 <= s <= prm.T_max + 1e-9 for s in steps[1:])
    assert x[0] > ob.center(t)[0] + 0.5  # ahead of it


def test_compiled_rollout_is_the_python_reference_bit_for_bit():
    """lipmpcc._sqp.timed_lip_rollout (the planner's roll-out when it imports) gives rollout_reference's numbers to
    the bit (the same operations on doubles, the C library's cosh and sinh, no fused multiply-adds): on the calls
    and plans of a short pushed run, on random variables (durations down to T <= 0, where a step is none) and with
    ϑ capped."""
    import lipmpcc.planners.mpcc_timed as timed_module
    from lipmpcc.loops import lip as lip_loop

    from lipmpcc.solvers.sqp_compiled import compiled_function

    if compiled_function("timed_lip_rollout") is None:
        pytest.skip("lipmpcc._sqp is not built")
    path = LinePath((0, 0), (30, 0))  # test_sqp_compiled's problem: compiled once per cache
    prm = TimedMpccParams(mpcc=MpccParams.overtake_mpcc(), T_min=0.3, T_max=0.5)
    pl = TimedMpccPlanner(path, prm)
    form = pl.formulation
    seen = []
    original = form.rollout

    def spy(call, Z):
        seen.append((call, np.array(Z, dtype=float)))
        return original(call, Z)

    form.rollout = spy
    lip_loop.run_lip_loop(pl, np.zeros(5), 8, path, [], lip_loop.random_pushes(4.0, np.random.default_rng(2)),
                          robot_radius=prm.mpcc.robot_radius, foot_radius=prm.mpcc.foot_radius)
    form.rollout = original
    assert len(seen) >= 8
    rng = np.random.default_rng(5)
    for call, Z in seen:
        for scale in (0.0, 1e-3, 1.0):
            Zr = Z + scale * rng.normal(size=Z.shape)
            Zr[NHEAD + 4 :: 5] -= scale * 2.0 * prm.T_min / prm.d_gain  # some T_k = T_min + gain d_k <= 0
            ref = form.rollout_reference(call, Zr)
            got = form.rollout(call, Zr)
            assert got.shape == ref.shape == (prm.N + 1, 6) and np.array_equal(got, ref)
    call, Z = seen[-1]
    Zc = Z.copy()
    Zc[NHEAD + 3 :: 5] = 20.0  # ϑ runs into the (extended) path's end: capped
    assert np.array_equal(form.rollout(call, Zc), form.rollout_reference(call, Zc))
    assert form.rollout(call, Zc)[-1, 5] == form.problem_path.length
    with pytest.raises(ValueError, match="z must hold"):
        timed_module._TIMED_ROLLOUT(np.zeros(6), np.zeros(4), NHEAD, 5, prm.N, 3.0, 0.3, 0.1, 1.0)
