"""ALIP-MPC (paper B §III): preset, constraints, eqs. (9) and (10), SQP vs IPOPT parity,
fallback on failure, bad inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, NoFallbackPlanError, ParameterError, StateError
from lipmpcc.models.alip import AlipParams
from lipmpcc.planners.alip_mpc import AlipMpc, AlipMpcParams
from lipmpcc.terrain import Stone

PRM = AlipMpcParams.paper()
LAM = PRM.lam
SIG = math.exp(LAM * PRM.T_nom)
STANCE = np.array([0.0, 0.14])  # left foot


def straight_stones(n=6, L=0.4, W=0.0, w=0.28, start=STANCE):
    """Stones of a periodic gait, the first for the right foot."""
    out, p, side = [], np.array(start, float), -1
    for _ in range(n):
        p = p + np.array([L, side * w + W])
        out.append(Stone(tuple(p)))
        side = -side
    return out


def periodic_dcm(L=0.4, W=0.0, w=0.28):
    """World DCM at touch-down of a right-swing step in the periodic gait."""
    return STANCE + np.array([L / (SIG - 1), -w / (SIG + 1) + W / (SIG - 1)])


@pytest.fixture(scope="module")
def mpc():
    return AlipMpc()


def test_paper_preset():
    p = AlipMpcParams.paper()
    assert p.horizon == 4 and p.T_nom == 0.5 and (p.T_min, p.T_max) == (0.35, 0.65)
    assert p.alpha_z == p.alpha_u == (1e4, 2e4) and p.alpha_sigma == 1.0 and p.w == 0.28
    np.testing.assert_allclose(p.betas, [1000, 100, 10, 1])
    assert (p.limits.x_max, p.limits.y_min, p.limits.y_max) == (0.6, 0.1, 0.5)
    assert p.stone_size == (0.2, 0.1) and p.replan_period == pytest.approx(0.04)
    assert AlipMpcParams.paper(horizon=6).horizon == 6


@pytest.mark.parametrize("W", [0.0, 0.15, -0.1])
def test_periodic_state_gives_the_periodic_plan(mpc, W):
    mpc.reset()
    stones = straight_stones(W=W)
    res = mpc.solve(periodic_dcm(W=W), STANCE, "left", 0.0, stones)
    assert res.success and not res.fallback
    np.testing.assert_allclose(res.footholds, [s.center for s in stones[:4]], atol=1e-5)
    np.testing.assert_allclose(res.durations, PRM.T_nom, atol=1e-4)
    assert res.cost == pytest.approx(0.0, abs=1e-3)


def test_plan_respects_every_constraint(mpc):
    mpc.reset()
    stones = straight_stones(L=0.45, W=0.1)
    xi = periodic_dcm(L=0.45, W=0.1) + np.array([0.04, -0.01])  # faster and off to the side
    res = mpc.solve(xi, STANCE, "left", 0.0, stones)
    assert res.success
    assert stones[0].contains(res.next_foothold, tol=1e-7)
    assert np.all(res.durations >= PRM.T_min - 1e-7) and np.all(res.durations <= PRM.T_max + 1e-7)
    b = PRM.dcm_bounds
    for k, z in enumerate(res.z):
        swing_next = 1 if k % 2 == 0 else -1  # step k+1 swings the left foot first
        assert b.contains(z, swing_next, tol=1e-7)
    # bilinear dynamics (8)
    zp = res.z0
    for k in range(PRM.horizon):
        np.testing.assert_allclose(res.z[k], res.sigma[k] * zp - res.u[k], atol=1e-7)
        zp = res.z[k]
    assert mpc.dynamics_residual(np.column_stack([res.sigma, res.u, res.z]).ravel(), res.z0) < 1e-7


def test_initial_dcm_back_projection_and_duration_floor(mpc):
    """Eq. (10): z^0 = xi(t) e^{-lambda t}; the current step cannot end before t."""
    mpc.reset()
    t = 0.5
    z0 = periodic_dcm() - STANCE + np.array([-0.03, 0.0])  # slower: wants a long step
    xi = STANCE + z0 * math.exp(LAM * t)
    res = mpc.solve(xi, STANCE, "left", t, straight_stones())
    np.testing.assert_allclose(res.z0, z0, atol=1e-12)
    assert res.step_duration >= t - 1e-9
    assert res.time_to_touchdown == pytest.approx(res.step_duration - t)


def test_desired_steps_use_the_previous_plan(mpc):
    """Eq. (9): u_des^k = p_stone^k - p_TD^{k-1}, the previous plan's footholds."""
    mpc.reset()
    stones = straight_stones()
    xi = periodic_dcm() + np.array([0.05, 0.0])
    first = mpc.solve(xi, STANCE, "left", 0.0, stones)
    data = mpc.problem_data(xi, STANCE, "left", 0.04, stones)
    np.testing.assert_allclose(data["u_des"][0], np.array(stones[0].center) - STANCE)
    for k in range(1, PRM.horizon):
        np.testing.assert_allclose(data["u_des"][k], np.array(stones[k].center) - first.footholds[k - 1])
    # after the touch-down on stone 1 the previous plan shifts by one footstep
    data2 = mpc.problem_data(xi, first.footholds[0], "right", 0.0, stones[1:])
    np.testing.assert_allclose(data2["u_des"][1], np.array(stones[2].center) - first.footholds[1])
    # without a previous plan: stone centres
    fresh = AlipMpc()
    d0 = fresh.problem_data(xi, STANCE, "left", 0.0, stones)
    np.testing.assert_allclose(d0["u_des"][1], np.array(stones[1].center) - np.array(stones[0].center))


def test_desired_steps_from_the_stones():
    """``step_reference="stones"``: u_des^k from the stone centres (the first from the stance foot), whatever
    the previous plan; the dynamics, bounds and solution of a first call are paper B's."""
    stones = straight_stones(W=0.05)
    xi = periodic_dcm(W=0.05) + np.array([0.05, -0.02])
    mpc = AlipMpc(AlipMpcParams.paper(step_reference="stones"))
    first = mpc.solve(xi, STANCE, "left", 0.0, stones)
    paper = AlipMpc().solve(xi, STANCE, "left", 0.0, stones)
    np.testing.assert_allclose(first.footholds, paper.footholds, atol=1e-9)
    data = mpc.problem_data(xi, STANCE, "left", 0.04, stones)
    centres = np.array([STANCE] + [s.center for s in stones[: PRM.horizon]])
    np.testing.assert_allclose(data["u_des"], np.diff(centres, axis=0))
    # paper B's eq. (9) starts them from that first plan's footholds, which left the stone centres
    plan_ref = AlipMpc()
    plan_ref.solve(xi, STANCE, "left", 0.0, stones)
    moved = plan_ref.problem_data(xi, STANCE, "left", 0.04, stones)["u_des"] - np.diff(centres, axis=0)
    assert np.abs(moved[1:]).max() > 1e-3
    with pytest.raises(ParameterError, match="step_reference"):
        AlipMpcParams.paper(step_reference="previous")


@pytest.mark.parametrize("shift", [(0.0, 0.0), (0.04, -0.01), (-0.03, 0.02), (0.08, 0.0)])
def test_sqp_matches_ipopt(shift):
    stones = straight_stones(L=0.35, W=0.05)
    xi = periodic_dcm(L=0.35, W=0.05) + np.array(shift)
    a = AlipMpc(solver="sqp").solve(xi, STANCE, "left", 0.08, stones)
    b = AlipMpc(solver="ipopt").solve(xi, STANCE, "left", 0.08, stones)
    assert a.success and b.success
    assert a.solver == "sqp" and b.solver == "ipopt"
    np.testing.assert_allclose(a.next_foothold, b.next_foothold, atol=1e-5)
    assert a.step_duration == pytest.approx(b.step_duration, abs=1e-4)
    assert a.cost == pytest.approx(b.cost, rel=1e-5, abs=1e-6)


def test_world_stone_bounds():
    stones = straight_stones(W=0.1)
    world = AlipMpc(AlipMpcParams.paper(stone_bounds="world"))
    a = world.solve(periodic_dcm(W=0.1), STANCE, "left", 0.0, stones)
    b = AlipMpc().solve(periodic_dcm(W=0.1), STANCE, "left", 0.0, stones)
    np.testing.assert_allclose(a.footholds, b.footholds, atol=1e-5)
    world.reset()
    c = world.solve(periodic_dcm(W=0.1) + np.array([0.03, 0.01]), STANCE, "left", 0.0, stones)
    assert c.success
    for k in range(PRM.horizon):  # every previewed foothold lands on its stone
        assert stones[k].contains(c.footholds[k], tol=1e-6)


def test_fewer_stones_are_padded(mpc):
    mpc.reset()
    stones = straight_stones(n=1)
    res = mpc.solve(periodic_dcm(), STANCE, "left", 0.0, stones)
    assert res.success and res.footholds.shape == (4, 2)
    assert stones[0].contains(res.next_foothold, tol=1e-7)


def test_failure_holds_then_shifts_the_previous_plan():
    m = AlipMpc()
    stones = straight_stones()
    first = m.solve(periodic_dcm(), STANCE, "left", 0.0, stones)
    # a DCM far outside the viable set: infeasible problem
    bad = STANCE + np.array([1.5, 0.0])
    held = m.solve(bad, STANCE, "left", 0.04, stones)
    assert held.fallback and not held.success and m.failures == 1
    np.testing.assert_allclose(held.next_foothold, first.next_foothold)
    assert held.step_duration == pytest.approx(first.step_duration)
    assert "fallback" in held.status and math.isnan(held.cost)
    # after touching down on stone 1 the fallback is the shifted plan
    shifted = m.solve(bad, first.footholds[0], "right", 0.0, stones[1:])
    assert shifted.fallback and m.failures == 2
    np.testing.assert_allclose(shifted.next_foothold, first.footholds[1])
    assert shifted.step_duration == pytest.approx(first.durations[1])
    # a good state afterwards solves again
    ok = m.solve(first.footholds[0] + (periodic_dcm() - STANCE) * np.array([1, -1]), first.footholds[0], "right", 0.0, stones[1:])
    assert ok.success


def test_first_failure_has_no_fallback():
    with pytest.raises(NoFallbackPlanError) as e:
        AlipMpc().solve(STANCE + np.array([1.5, 0.0]), STANCE, "left", 0.0, straight_stones())
    assert "no previous plan" in str(e.value)


@pytest.mark.parametrize(
    "call, err, word",
    [
        (lambda: AlipMpcParams(horizon=0), ParameterError, "horizon"),
        (lambda: AlipMpcParams(T_min=0.7), ParameterError, "T_min"),
        (lambda: AlipMpcParams(alpha_z=(1.0, -1.0)), ParameterError, "alpha_z"),
        (lambda: AlipMpcParams(alpha_u="big"), ParameterError, "alpha_u"),
        (lambda: AlipMpcParams(solver="snopt"), ParameterError, "solver"),
        (lambda: AlipMpcParams(stone_bounds="both"), ParameterError, "stone_bounds"),
        (lambda: AlipMpcParams(dcm_target="later"), ParameterError, "dcm_target"),
        (lambda: AlipMpcParams(min_time_to_touchdown=-0.1), ParameterError, "min_time_to_touchdown"),
        (lambda: AlipMpcParams(alip="digit"), ParameterError, "alip"),
        (lambda: AlipMpc(params="paper"), ParameterError, "params"),
        (lambda: AlipMpc().solve((np.nan, 0.0), STANCE, "left", 0.0, straight_stones()), StateError, "dcm_world"),
        (lambda: AlipMpc().solve((0.1, 0.0), (0.0,), "left", 0.0, straight_stones()), InvalidInputError, "stance_world"),
        (lambda: AlipMpc().solve((0.1, 0.0), STANCE, "up", 0.0, straight_stones()), InvalidInputError, "side"),
        (lambda: AlipMpc().solve((0.1, 0.0), STANCE, "left", -0.1, straight_stones()), StateError, "t_since_touchdown"),
        (lambda: AlipMpc().solve((0.1, 0.0), STANCE, "left", 0.0, []), InvalidInputError, "stones"),
        (lambda: AlipMpc().solve((0.1, 0.0), STANCE, "left", 0.0, [[1.0, 2.0, 3.0]]), InvalidInputError, "stones"),
        (lambda: AlipMpc().solve((0.1, 0.0), STANCE, "left", 0.0, [Stone((0.4, -0.14), (0.2, -0.1))]), InvalidInputError, "size"),  # refused by Stone itself
    ],
)
def test_bad_inputs_are_named(call, err, word):
    with pytest.raises(err) as e:
        call()
    assert word in str(e.value)


def test_params_are_hashable_and_shared_builds():
    a, b = AlipMpc(), AlipMpc()
    assert a._solver is b._solver  # one CasADi build per parameter set
    assert hash(AlipMpcParams.paper()) == hash(AlipMpcParams.paper(alip=AlipParams()))


# ----------------------------------------------------------------------------- a foot (CoP offset)
FOOT = (0.06, 0.025)


def test_point_foot_is_the_paper_nlp_and_plans_no_cop_offset(mpc):
    from lipmpcc.planners.alip_mpc import build_alip_nlp

    assert not PRM.uses_cop and PRM.n_x == 5 * PRM.horizon
    nlp = build_alip_nlp(PRM)
    assert nlp["x"].numel() == 20 and nlp["p"].numel() == 2 + 16 + 1
    foot = AlipMpcParams.paper(cop_range=FOOT)
    assert foot.uses_cop and foot.n_x == 22 and build_alip_nlp(foot)["p"].numel() == 20
    mpc.reset()
    res = mpc.solve(periodic_dcm() + np.array([0.03, -0.02]), STANCE, "left", 0.1, straight_stones())
    np.testing.assert_array_equal(res.cop_offset, [0.0, 0.0])


def test_periodic_state_needs_no_ankle():
    mpc = AlipMpc(AlipMpcParams.paper(cop_range=FOOT))
    stones = straight_stones()
    res = mpc.solve(periodic_dcm(), STANCE, "left", 0.0, stones)
    assert res.success
    np.testing.assert_allclose(res.cop_offset, 0.0, atol=1e-6)
    np.testing.assert_allclose(res.footholds, [s.center for s in stones[:4]], atol=1e-5)


@pytest.mark.parametrize("shift, t", [((-0.03, 0.0), 0.2), ((0.0, -0.03), 0.2), ((0.02, 0.015), 0.1)])
def test_ankle_pushes_the_dcm_back_and_the_plan_obeys_the_shifted_dynamics(shift, t):
    """A DCM displaced by a push: the CoP moves the same way as the displacement (behind a DCM that
    fell back, towards the outside of a DCM pushed out), within the box, and the first step's
    dynamics are z^1 = sigma^1 (z^0 - e^{-lambda t} d) + d - u^1."""
    mpc = AlipMpc(AlipMpcParams.paper(cop_range=FOOT))
    point = AlipMpc()
    stones = straight_stones()
    xi = periodic_dcm() + np.array(shift) * math.exp(LAM * t)
    res = mpc.solve(xi, STANCE, "left", t, stones)
    assert res.success and not res.fallback
    d = res.cop_offset
    assert np.all(np.abs(d) <= np.array(FOOT) + 1e-9)
    for i in range(2):
        if shift[i] != 0.0:
            assert np.sign(d[i]) == np.sign(shift[i]) and abs(d[i]) > 0.005
    z1 = res.sigma[0] * (res.z0 - math.exp(-LAM * t) * d) + d - res.u[0]
    np.testing.assert_allclose(res.z[0], z1, atol=1e-7)
    # with the ankle the plan is closer to the nominal gait than the point foot's (when the point
    # foot has one at all: from a DCM 3 cm off it finds none)
    try:
        ref = point.solve(xi, STANCE, "left", t, stones)
    except NoFallbackPlanError:
        assert max(abs(x) for x in shift) >= 0.03
    else:
        assert res.cost < ref.cost


def test_foot_sqp_matches_ipopt():
    stones = straight_stones(L=0.35, W=0.05)
    xi = periodic_dcm(L=0.35, W=0.05) + np.array([-0.05, 0.03])
    p = AlipMpcParams.paper(cop_range=FOOT)
    a = AlipMpc(p, solver="sqp").solve(xi, STANCE, "left", 0.12, stones)
    b = AlipMpc(p, solver="ipopt").solve(xi, STANCE, "left", 0.12, stones)
    assert a.success and b.success
    np.testing.assert_allclose(a.cop_offset, b.cop_offset, atol=1e-5)
    np.testing.assert_allclose(a.next_foothold, b.next_foothold, atol=1e-5)
    assert a.cost == pytest.approx(b.cost, rel=1e-5, abs=1e-6)


@pytest.mark.parametrize("bad", [(-0.01, 0.02), (0.05,), (math.nan, 0.02), "wide"])
def test_bad_cop_range_is_named(bad):
    with pytest.raises(ParameterError, match="cop_range"):
        AlipMpcParams.paper(cop_range=bad)


def test_buffered_call_is_call_nlp_and_each_planner_has_its_own():
    """The solve goes through a CasADi FunctionBuffer (no DM conversions): the same numbers as
    ``call_nlp`` on the same data, and two planners sharing one cached NLP keep their own solver
    memory and statistics (interleaved calls change neither's plans)."""
    from lipmpcc.planners.alip_mpc import call_nlp

    stones = straight_stones(L=0.45, W=0.1)
    xi = periodic_dcm(L=0.45, W=0.1) + np.array([0.04, -0.01])
    a, b, alone = AlipMpc(), AlipMpc(), AlipMpc()
    assert a._solver is b._solver
    data = a.problem_data(xi, STANCE, "left", 0.05, stones)
    x0, lx0, lg0 = a._warm_start(data, False)
    ref = call_nlp(a._solver, data, x0, lx0, lg0)
    res = a.solve(xi, STANCE, "left", 0.05, stones)
    assert res.success
    np.testing.assert_array_equal(res.next_foothold, STANCE + ref["x"][1:3])
    # b solves another problem (many iterations) between a's calls; a matches a planner run alone
    plans = []
    for t in (0.1, 0.15, 0.2):
        rb = b.solve(periodic_dcm(W=0.15) + np.array([0.02, 0.0]), STANCE, "left", 0.0, straight_stones(W=0.15))
        assert rb.success and rb.iterations > 0
        plans.append(a.solve(xi, STANCE, "left", t, stones))
    alone.solve(xi, STANCE, "left", 0.05, stones)
    for t, p in zip((0.1, 0.15, 0.2), plans):
        q = alone.solve(xi, STANCE, "left", t, stones)
        np.testing.assert_array_equal(p.footholds, q.footholds)
        np.testing.assert_array_equal(p.durations, q.durations)
        assert p.iterations == q.iterations


def test_max_speed_gives_long_steps_their_own_nominal_duration():
    """``max_speed``: a desired step longer than max_speed x T_nom is planned at the duration |u_x| / max_speed (the
    periodic gait of that duration is the plan, at no cost); shorter steps keep paper B's problem exactly."""
    v, L = 0.9, 0.55
    T = L / v
    sig = math.exp(LAM * T)
    stones = straight_stones(L=L)
    xi = STANCE + np.array([L / (sig - 1), -0.28 / (sig + 1)])  # the periodic gait of duration T
    slow = AlipMpc(AlipMpcParams.paper(max_speed=v))
    res = slow.solve(xi, STANCE, "left", 0.0, stones)
    assert res.success and not res.fallback
    np.testing.assert_allclose(res.footholds, [s.center for s in stones[:4]], atol=1e-5)
    np.testing.assert_allclose(res.durations, T, atol=1e-4)
    assert res.cost == pytest.approx(0.0, abs=1e-3)
    paper = AlipMpc().solve(xi, STANCE, "left", 0.0, stones)  # paper B's T_nom: walks that DCM faster
    assert np.min(paper.durations) < T - 0.02
    short = straight_stones(L=0.4)
    d_slow = AlipMpc(AlipMpcParams.paper(max_speed=v)).problem_data(periodic_dcm(), STANCE, "left", 0.1, short)
    d_paper = AlipMpc().problem_data(periodic_dcm(), STANCE, "left", 0.1, short)
    for key in ("p", "lbx", "ubx", "lbg", "ubg"):
        np.testing.assert_array_equal(d_slow[key], d_paper[key])
    with pytest.raises(ParameterError, match="max_speed"):
        AlipMpcParams.paper(max_speed=-1.0)


def test_max_speed_keeps_paper_b_slack_above_a_slowed_step():
    """``max_speed``: a step slowed to T_k keeps paper B's slack T_max − T_nom above it (at L = 0.55 m, 0.9 m/s: up to
    0.761 s, not 0.65 s, which left 0.04 s), from the stones' spacing, not from a foothold lagging its stone; a DCM
    too slow for the course is then caught with steps longer than paper B's T_max."""
    v, L = 0.9, 0.55
    T = L / v
    prm = AlipMpcParams.paper(max_speed=v)
    N = prm.horizon
    mpc = AlipMpc(prm)
    d = mpc.problem_data(periodic_dcm(L=L), STANCE, "left", 0.1, straight_stones(L=L))
    np.testing.assert_allclose(np.log(d["ubx"][: 5 * N : 5]) / LAM, prm.T_max + T - prm.T_nom, rtol=1e-12)
    lag = straight_stones(L=0.4, start=STANCE + np.array([0.1, 0.0]))  # the stance foot 0.1 m behind its stone
    d = mpc.problem_data(periodic_dcm(), STANCE, "left", 0.1, lag)
    T_hi = np.log(d["ubx"][: 5 * N : 5]) / LAM
    assert T_hi[0] == pytest.approx(prm.T_max + 0.5 / v - prm.T_nom)  # the current step: 0.5 m from the stance foot
    np.testing.assert_allclose(T_hi[1:], prm.T_max)  # the course's pace: 0.4 m stones, paper B's bound
    sig = math.exp(LAM * T)
    slow = STANCE + np.array([0.75 * L / (sig - 1), -0.28 / (sig + 1)])  # 25 % short of the periodic forward DCM
    res = mpc.solve(slow, STANCE, "left", 0.0, straight_stones(L=L))
    assert res.success and not res.fallback
    assert prm.T_max + 0.1 < np.max(res.durations) <= prm.T_max + T - prm.T_nom + 1e-6
