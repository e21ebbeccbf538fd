"""lipmpcc.planners.mpcc: constraints hold, SQP matches IPOPT, warm start, fallback, bad input."""

import math

import numpy as np
import pytest

from lipmpcc.exceptions import NoFallbackPlanError, ParameterError, StateError
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import ArcPath, LinePath
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner


def _walk(planner, x, side, n, obstacles=()):
    m = planner.params.model
    res = None
    for k in range(n):
        res = planner.solve(x, side, obstacles, t_now=k * m.T)
        x = m.step(x, res.u0)
        side = -side
    return x, side, res


def test_plan_satisfies_constraints():
    path = ArcPath.circle(2.0)
    prm = MpccParams.circle()
    pl = MpccPlanner(path, prm)
    x, side, _ = _walk(pl, np.zeros(5), 1, 6)
    r = pl.solve(x, side)
    assert r.found and r.status == "converged"
    m = prm.model
    for k in range(prm.N):
        # dynamics
        assert np.allclose(r.states[k + 1], m.step(r.states[k], r.inputs[k]), atol=1e-9)
        assert r.theta[k + 1] == pytest.approx(r.theta[k] + r.v[k], abs=1e-9)
        # rectangle with alternating sides
        s = side * (1 if k % 2 == 0 else -1)
        assert prm.rectangle.contains(r.inputs[k], r.states[k, 4] + r.inputs[k, 2], s, tol=1e-6)
        # distance per step
        d = np.hypot(*(r.states[k + 1, [0, 2]] - r.states[k, [0, 2]]))
        assert prm.delta_min - 1e-6 <= d <= prm.delta_max + 1e-6
    assert np.all(r.v >= -1e-9) and np.all(r.v <= prm.v_max + 1e-9)
    assert np.all((r.theta >= -1e-9) & (r.theta <= path.length + 1e-9))
    assert r.footsteps.shape == (prm.N, 3)
    assert np.allclose(r.footsteps[:, :2], r.states[:-1][:, [0, 2]] + r.inputs[:, :2])


@pytest.mark.parametrize("preset, obstacle_speed", [("circle", None), ("overtake_mpcc", 0.6), ("overtake_cartesian", 0.1)])
def test_sqp_matches_ipopt(preset, obstacle_speed):
    """The fast SQP and the paper's Opti+IPOPT formulation solve the same problem: IPOPT's
    solution is a fixed point of the SQP, and both reach local minima of the same quality."""
    if preset == "circle":
        path = ArcPath.circle(2.0)
        obstacles = []
    else:
        path = LinePath((0, 0), (30, 0))
        obstacles = [Obstacle.circle(0.25, path=path, s0=1.5, speed=obstacle_speed)]
    prm = getattr(MpccParams, preset)()
    fast = MpccPlanner(path, prm)
    ref = MpccPlanner(path, prm.with_(solver="ipopt"))
    x, side = np.zeros(5), 1
    m = prm.model
    same = 0
    for k in range(12):
        rf = fast.solve(x, side, obstacles, t_now=k * m.T)
        ri = ref.solve(x, side, obstacles, t_now=k * m.T)
        assert rf.found and ri.found
        scale = max(1.0, abs(ri.cost))
        # non-convex problem (−ρv² is concave): local minima may differ slightly
        assert rf.cost <= ri.cost + 0.01 * scale
        same += abs(rf.cost - ri.cost) < 1e-5 * scale
        # IPOPT's solution is a KKT point of the SQP's problem: the SQP accepts it at once
        sqp = fast._get(len(obstacles))["sqp"]
        x0_full = np.r_[x, ri.theta_init]
        sol = sqp.solve(np.column_stack([ri.inputs, ri.v]), (x0_full, fast.parameters(side, obstacles, k * m.T)))
        assert sol.found and sol.iterations <= 3
        assert sol.cost == pytest.approx(ri.cost, abs=1e-5 * scale)
        assert np.allclose(sol.u.reshape(-1, 4)[:, :3], ri.inputs, atol=1e-3)
        x = m.step(x, ri.u0)
        side = -side
    assert same >= 4


def test_obstacle_cbf_and_foothold_clearance_hold_in_the_plan():
    path = LinePath((0, 0), (30, 0))
    ob = Obstacle.circle(0.25, path=path, s0=1.5, speed=0.6)
    prm = MpccParams.overtake_mpcc()
    pl = MpccPlanner(path, prm)
    x, side = np.zeros(5), 1
    m = prm.model
    for k in range(25):
        r = pl.solve(x, side, [ob], t_now=k * m.T)
        t = k * m.T + m.T * np.arange(prm.N + 1)
        b = ob.clearance(r.states[:, [0, 2]], t, prm.robot_radius + prm.obstacle_margin) + 1e-6
        # barrier b_k = ‖p − c‖²/r² − 1 is decreasing by at most (1 − γ) per step
        r_inf = ob.axes[0] + prm.obstacle_inflation
        bb = np.sum((r.states[:, [0, 2]] - ob.center(t)) ** 2, axis=1) / r_inf**2 - 1
        assert np.all(bb[1:] >= (1 - prm.gamma) * bb[:-1] - 1e-6)
        fc = ob.clearance(r.footsteps[:, :2], t[:-1], prm.foot_radius + prm.obstacle_margin)
        assert np.all(fc >= -1e-6)
        x = m.step(x, r.u0)
        side = -side
    del b


def test_cartesian_is_mpcc_with_equal_weights():
    p = MpccParams.overtake_cartesian()
    assert p.Q_bar[0] == p.Q_bar[1] and p.W_bar[0] == p.W_bar[1]
    assert MpccParams.overtake_mpcc().Q_bar == (1.0, 1000.0)
    assert MpccParams.circle().rho == 10.0 and MpccParams.circle().R == (100.0, 100.0, 5.0)


def test_fallback_replays_shifted_plan_and_counts(monkeypatch):
    path = ArcPath.circle(2.0)
    pl = MpccPlanner(path, MpccParams.circle())
    x, side, last = _walk(pl, np.zeros(5), 1, 3)

    def broken(*a, **k):
        return False, "forced failure", 3, math.nan, np.zeros((6, 6)), np.zeros((5, 4))

    monkeypatch.setattr(pl, "_solve_sqp", broken)
    r = pl.solve(x, side)
    assert r.used_fallback and not r.found
    assert pl.failures == 1
    assert np.allclose(r.inputs[:-1], last.inputs[1:])  # the shifted previous plan
    assert np.allclose(r.states[0], x)


def test_failure_without_previous_plan_raises(monkeypatch):
    pl = MpccPlanner(ArcPath.circle(2.0), MpccParams.circle())
    monkeypatch.setattr(pl, "_solve_sqp", lambda *a, **k: (False, "forced failure", 1, math.nan, None, None))
    with pytest.raises(NoFallbackPlanError, match="forced failure"):
        pl.solve(np.zeros(5), 1)


def test_infeasible_obstacle_is_reported_not_crashing():
    """An obstacle sitting on the robot makes the foothold constraints infeasible: the
    first solve raises a clear error (no previous plan)."""
    path = LinePath((0, 0), (10, 0))
    ob = Obstacle.circle(0.5, position=(0.0, 0.0))
    pl = MpccPlanner(path, MpccParams.overtake_mpcc())
    with pytest.raises(NoFallbackPlanError, match="failed"):
        pl.solve(np.zeros(5), 1, [ob])


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"N": 0}, "horizon"),
        ({"gamma": 1.0}, r"\(0, 1\)"),
        ({"v_max": 0.0}, "> 0"),
        ({"delta_min": 0.5, "delta_max": 0.4}, "delta_max"),
        ({"Q_bar": (1.0, -1.0)}, "non-negative"),
        ({"R": (1.0, 1.0)}, "three"),
        ({"solver": "snopt"}, "sqp"),
        ({"heading_weight": -1.0}, "heading_weight"),
        ({"heading_weight": float("nan")}, "heading_weight"),
        ({"past_end": "yes"}, "past_end"),
    ],
)
def test_bad_params(kw, match):
    with pytest.raises(ParameterError, match=match):
        MpccParams(**kw)


def test_bad_state_and_side():
    pl = MpccPlanner(ArcPath.circle(2.0), MpccParams.circle())
    with pytest.raises(StateError, match="5-vector"):
        pl.solve(np.zeros(4), 1)
    with pytest.raises(StateError, match="finite"):
        pl.solve(np.array([0, 0, np.nan, 0, 0]), 1)
    with pytest.raises(ParameterError, match="stance_side"):
        pl.solve(np.zeros(5), 0)
    with pytest.raises(ParameterError, match="Obstacle"):
        pl.solve(np.zeros(5), 1, ["not an obstacle"])
    with pytest.raises(ParameterError, match="Path"):
        MpccPlanner("circle", MpccParams())


def test_heading_weight_turns_the_plan_back_to_the_path_tangent():
    """With a 0.16 m lateral bound in the new heading frame, paper A's cost (heading change weighted
    only) lets a Cartesian MPC starting from rest keep turning; the heading weight brings the planned
    headings back towards the path's tangent (here 0), and both solvers agree on the weighted problem."""
    from lipmpcc.models.lip3d import ReachabilityRectangle

    rect = ReachabilityRectangle(forward=(-0.35, 0.35), lateral=(0.16, 0.40), heading=(-0.3, 0.3))
    path = LinePath((0.0, 0.0), (40.0, 0.0))
    headings = {}
    for w in (0.0, 50.0):
        prm = MpccParams.overtake_cartesian(rectangle=rect, heading_weight=w)
        res = MpccPlanner(path, prm).solve(np.zeros(5), stance_side=+1)
        assert res.found
        headings[w] = res.footsteps[:, 2]
    assert np.sum(np.abs(headings[50.0][1:])) < 0.5 * np.sum(np.abs(headings[0.0][1:]))
    prm = MpccParams.overtake_cartesian(rectangle=rect, heading_weight=50.0)
    a = MpccPlanner(path, prm).solve(np.zeros(5), stance_side=+1)
    b = MpccPlanner(path, prm.with_(solver="ipopt")).solve(np.zeros(5), stance_side=+1)
    assert a.cost == pytest.approx(b.cost, rel=1e-4, abs=1e-6)


def _lip_input(x, k, t, stance_side, obstacles=(), path=None):
    """The PlannerInput of the LIP loop at a support exchange (the swing foot lands now)."""
    from lipmpcc.planners.base import PlannerInput

    return PlannerInput(
        t=t, com_pos=np.array([x[0], x[2], 0.9]), com_vel=np.array([x[1], x[3], 0.0]), dcm=np.zeros(2), omega=3.3,
        stance_side=stance_side, stance_pos=np.zeros(3), stance_yaw=0.0, swing_pos=np.zeros(3), swing_yaw=0.0,
        time_since_touchdown=0.4, step_index=k, torso_yaw=x[4], course=path, obstacles=tuple(obstacles),
    )


def test_plan_is_the_contract_on_the_lip():
    """plan(PlannerInput) solves from the LIP state in the input, for the swing foot (the side opposite
    the stance), with the input's obstacles, and returns x + u_0, θ + u^θ_0, the model's T and the
    MpccResult; a second call in the same step returns the same plan."""
    from lipmpcc.planners.base import FootstepSource, StepPlan

    path = LinePath((0, 0), (30, 0))
    prm = MpccParams.overtake_mpcc()
    obstacles = [Obstacle.circle(0.25, path=path, s0=0.5, speed=0.1)]  # just ahead at t = 1.2 s
    x = np.array([0.1, 0.2, -0.05, 0.0, 0.02])
    pl, ref = MpccPlanner(path, prm), MpccPlanner(path, prm)
    assert isinstance(pl, FootstepSource) and pl.name == "mpcc"
    plan = pl.plan(_lip_input(x, 0, 1.2, "right", obstacles, path))  # right stance: the left foot is placed
    res = ref.solve(x, +1, obstacles, t_now=1.2)
    assert isinstance(plan, StepPlan) and isinstance(plan.record, type(res))
    u = res.u0
    np.testing.assert_array_equal(plan.foothold, [x[0] + u[0], x[2] + u[1]])
    assert plan.yaw == x[4] + u[2] and plan.duration == prm.model.T
    assert plan.ok and plan.record.stance_side == +1 and plan.cost == res.cost
    np.testing.assert_array_equal(plan.preview[:, :3], res.footsteps)
    assert pl.plan(_lip_input(x, 0, 1.25, "right", obstacles)) is plan  # once per step
    # without the obstacle, another plan
    free = MpccPlanner(path, prm).plan(_lip_input(x, 0, 1.2, "right"))
    assert not np.allclose(free.record.inputs, plan.record.inputs)
    pl.reset()
    assert pl.plan(_lip_input(x, 0, 1.2, "right", obstacles)) is not plan


def test_fallback_plan_is_not_ok(monkeypatch):
    pl = MpccPlanner(ArcPath.circle(2.0), MpccParams.circle())
    first = pl.plan(_lip_input(np.zeros(5), 0, 0.0, "left"))
    assert first.ok
    monkeypatch.setattr(pl, "_attempt", lambda *a, **k: None)  # every solve fails from now on
    second = pl.plan(_lip_input(first.record.states[1], 1, 0.4, "right"))
    assert not second.ok and second.status.startswith("fallback") and second.record.used_fallback
    assert pl.failures == 1


def test_old_condensed_scp_warns_and_solves_like_the_new_sqp():
    import lipmpcc.planners.mpcc as mpcc_module

    path, prm = ArcPath.circle(2.0), MpccParams.circle()
    with pytest.warns(DeprecationWarning, match="CondensedSqp"):
        old_cls = mpcc_module.CondensedScp
    old = old_cls(path, prm, 0)
    new = mpcc_module.build_sqp(path, prm, 0)
    pl = MpccPlanner(path, prm)
    x0_full = np.r_[np.zeros(5), 0.0]
    p = pl.parameters(1, [], 0.0)
    U0 = np.tile([0.0, 0.1, 0.0, 0.15], (prm.N, 1))
    ok, status, iters, cost, U = old.solve(x0_full, p, U0)
    sol = new.solve(U0, (x0_full, p))
    assert ok == sol.found and status == sol.status and cost == sol.cost
    np.testing.assert_array_equal(U, sol.u.reshape(-1, 4))
    np.testing.assert_array_equal(old.rollout(x0_full, U)[-1], mpcc_module.rollout(prm.model, x0_full, U)[-1])


# ---- far and many obstacles -------------------------------------------------------------------
def _footsteps(obstacles, n=12, path=None):
    from lipmpcc.planners.mpcc import MpccPlanner as P

    pl = P(path or LinePath((0.0, 0.0), (40.0, 0.0)), MpccParams.overtake_mpcc())
    _, _, _ = _walk(pl, np.zeros(5), 1, 1, obstacles)  # first solve (cold)
    out = [pl.last.footsteps[0].copy()]
    x = pl.params.model.step(np.zeros(5), pl.last.u0)
    side = -1
    for k in range(1, n):
        r = pl.solve(x, side, obstacles, t_now=k * pl.params.model.T)
        assert r.found, r.status
        out.append(r.footsteps[0].copy())
        x = pl.params.model.step(x, r.u0)
        side = -side
    return np.array(out)


@pytest.mark.parametrize("where", [(30.0, 5.0), (0.0, 60.0), (-150.0, 0.0), (5000.0, 0.0)])
def test_a_far_obstacle_changes_nothing(where):
    """An obstacle farther than the horizon can reach is left out of the solve: the footsteps are the
    very same as without it (it made every solve fail when its barrier exceeded 1e4, ~100 (r + 0.15) m)."""
    far = Obstacle.circle(0.1, position=where)
    np.testing.assert_array_equal(_footsteps([far]), _footsteps([]))


def test_a_far_moving_obstacle_counts_its_speed():
    """6.5 m ahead but coming at 2 m/s: it can be 4 m closer within the horizon (N T = 2 s), so it is planned for."""
    from lipmpcc.planners.mpcc import obstacle_reach, relevant_obstacles

    prm = MpccParams.overtake_mpcc()
    x0 = np.zeros(5)
    still = Obstacle.circle(0.25, position=(6.5, 0.0))
    coming = Obstacle.circle(0.25, position=(6.5, 0.0), velocity=(-2.0, 0.0))
    assert relevant_obstacles(prm, x0, [still, coming], 0.0) == [coming]
    near = Obstacle.circle(0.25, position=(obstacle_reach(prm) + 0.25 + 0.4, 0.0))
    assert relevant_obstacles(prm, x0, [near], 0.0) == [near]
    line = LinePath((0.0, 0.0), (40.0, 0.0))
    on_path = Obstacle.circle(0.25, path=line, s0=20.0, speed=-0.6)
    assert relevant_obstacles(prm, x0, [on_path], 0.0) == []
    assert relevant_obstacles(prm, x0, [on_path], 28.0) == [on_path]  # 3.2 m away: within reach


def test_obstacle_slots_come_in_few_sizes():
    from lipmpcc.planners.mpcc import inert_obstacle, obstacle_capacity

    assert [obstacle_capacity(n) for n in (0, 1, 2, 3, 4, 5, 9, 17)] == [0, 1, 2, 4, 4, 8, 16, 32]
    x0 = np.array([1.0, 0.0, 2.0, 0.0, 0.0])
    inert = inert_obstacle(x0)
    assert inert.clearance(np.array([[1.0, 2.0]]), 0.0, 10.0)[0] > 900.0


def test_many_obstacles_beside_the_path_plan_fast():
    """200 static obstacles 3 m beside a straight path (r = 0.3 m, every 0.2 m): only those the horizon can
    reach enter a solve (at most 8 slots, wherever the robot is), and the robot walks on without a failure.
    (How fast a solve is, is for a benchmark to measure, not for a test: it failed under load.)"""
    from lipmpcc.planners.mpcc import relevant_obstacles

    obs = [Obstacle.circle(0.3, position=(0.2 * i, 3.0)) for i in range(200)]
    prm = MpccParams.overtake_mpcc()
    assert 0 < len(relevant_obstacles(prm, np.zeros(5), obs, 0.0)) <= 8
    pl = MpccPlanner(LinePath((0.0, 0.0), (40.0, 0.0)), prm)
    _walk(pl, np.zeros(5), 1, 2, obs)  # builds the solvers
    x, _, res = _walk(pl, np.zeros(5), 1, 20, obs)
    assert pl.failures == 0 and res.found
    assert x[0] > 4.0 and abs(x[2]) < 0.3  # walks on along the path
    assert 0 < len(relevant_obstacles(prm, x, obs, 0.0)) <= 8


def test_a_far_obstacle_changes_nothing_on_the_circle():
    circle = ArcPath.circle(2.0)
    far = Obstacle.circle(0.25, position=(40.0, 0.0))
    np.testing.assert_array_equal(_footsteps([far], path=circle), _footsteps([], path=circle))
# ---- issue 14: one validation layer -------------------------------------------------------------
@pytest.mark.parametrize(
    "kw, match",
    [
        ({"R": None}, r"R = None: expected three non-negative weights"),
        ({"R": "abc"}, r"R = 'abc'"),
        ({"Q_bar": (1.0, float("nan"))}, r"Q_bar = .*NaN or inf"),
        ({"foot_radius": float("nan")}, r"foot_radius = nan: expected a finite number >= 0 \[m\]"),
        ({"foot_radius": -1}, r"foot_radius = -1: expected a finite number >= 0 \[m\]"),
        ({"robot_radius": "big"}, r"robot_radius = 'big'"),
        ({"N": 5.0}, r"N = 5.0: expected an integer horizon >= 1"),
        ({"N": True}, r"N = True"),
        ({"N": 10**6}, r"N = 1000000: expected an integer horizon >= 1 and <= 100"),
        ({"gamma": "x"}, r"gamma = 'x'"),
        ({"jit": "yes"}, r"jit = 'yes': expected True or False"),
        ({"max_iter": 0}, r"max_iter = 0"),
        ({"model": None}, r"model = None: expected a lipmpcc.models.lip3d.Lip3dModel"),
        ({"rectangle": (0, 1)}, r"rectangle = \(0, 1\)"),
        ({"v_max": float("inf")}, r"v_max = inf"),
    ],
)
def test_bad_params_are_named(kw, match):
    with pytest.raises(ParameterError, match=match):
        MpccParams(**kw)


def test_numpy_horizon_is_accepted_as_an_int():
    prm = MpccParams(N=np.int64(4), rho=np.float32(10.0))
    assert prm.N == 4 and type(prm.N) is int


def test_bad_solve_and_plan_arguments_are_named():
    pl = MpccPlanner(ArcPath.circle(2.0), MpccParams.circle())
    with pytest.raises(StateError, match=r"x0 = 'abc': expected a 5-vector"):
        pl.solve("abc")
    with pytest.raises(ParameterError, match=r"stance_side = None: expected \+1 \(left\) or -1 \(right\)"):
        pl.solve(np.zeros(5))
    with pytest.raises(StateError, match=r"x0 = .*5-vector.*got shape \(2, 5\)"):
        pl.solve(np.zeros((2, 5)), 1)
    with pytest.raises(StateError, match=r"NaN or inf"):
        pl.solve([0, 0, np.inf, 0, 0], 1)
    with pytest.raises(ParameterError, match=r"stance_side = True"):
        pl.solve(np.zeros(5), True)
    with pytest.raises(ParameterError, match=r"stance_side = 'left'"):
        pl.solve(np.zeros(5), "left")
    with pytest.raises(ParameterError, match=r"obstacles = "):
        pl.solve(np.zeros(5), 1, Obstacle.circle(0.3, position=(3, 0)))
    with pytest.raises(ParameterError, match=r"t_now = nan"):
        pl.solve(np.zeros(5), 1, t_now=float("nan"))
    with pytest.raises(ParameterError, match=r"theta_init = 'start'"):
        pl.solve(np.zeros(5), 1, theta_init="start")
    with pytest.raises(ParameterError, match=r"shift = 1"):
        pl.solve(np.zeros(5), 1, shift=1)
    with pytest.raises(ParameterError, match=r"inp = 'abc': expected a lipmpcc.planners.base.PlannerInput"):
        pl.plan("abc")
    with pytest.raises(ParameterError, match=r"params = "):
        MpccPlanner(ArcPath.circle(2.0), {"N": 5})
    assert pl.solves == 0  # nothing was solved


def test_a_fallback_that_would_walk_into_an_obstacle_holds_in_place(monkeypatch):
    """No way out (issue 31): the solver fails and the replayed previous plan walks into an obstacle; the
    planner steps in place instead and names the obstacle. One that does not bar the replay changes nothing."""
    from lipmpcc.planners.liveness import barred_by

    path = LinePath((0.0, 0.0), (10.0, 0.0))
    pl = MpccPlanner(path, MpccParams.circle())
    x, side, last = _walk(pl, np.zeros(5), 1, 4)
    monkeypatch.setattr(pl, "_solve_sqp", lambda *a, **k: (False, "forced failure", 3, math.nan, None, None))
    monkeypatch.setattr(pl, "_solve_ipopt", lambda *a, **k: (False, "forced failure", 3, math.nan, None, None))
    T = pl.params.model.T
    t = 4 * T
    far = Obstacle.circle(0.2, position=(x[0] + 0.4, 3.0))
    wall = Obstacle.circle(0.3, position=(x[0] + 0.75, x[2]))  # on the replay's way: it walks ~0.25 m a step
    replay = pl._fallback(pl.formulation.call(x, side, t, float(x[0]), True, pl.last), "x", 0, 0.0, [far])
    assert replay.held_by == [] and barred_by(replay.states[:, [0, 2]], t + T * np.arange(6), [wall],
                                              pl.params.obstacle_inflation) == [0]
    pl.last = last
    r = pl.solve(x, side, [far, wall], t_now=t)
    assert r.used_fallback and r.held_by == [1]
    assert np.all(r.v == 0.0)
    com = r.states[:, [0, 2]]
    assert np.max(np.linalg.norm(com - com[0], axis=1)) < 0.3  # comes to rest near where it is
    assert np.min(wall.clearance(com, t + T * np.arange(6), pl.params.robot_radius)) > 0.0
    assert np.sign(r.footsteps[0, 1] - x[2]) == side  # the foot placed now on its own side


def test_rollout_is_the_matrix_recursion():
    """rollout's plain-float recursion (issue 28) gives the numbers of x_{k+1} = A x_k + B u_k, ϑ capped."""
    import lipmpcc.planners.mpcc as mpcc_module
    from lipmpcc.models.lip3d import Lip3dModel

    rng = np.random.default_rng(7)
    for model in (Lip3dModel(), Lip3dModel(T=0.33, H=1.02)):
        A, B = model.A, model.B
        for scale in (1e-3, 1.0, 30.0):
            x0 = rng.normal(size=6) * scale
            U = rng.normal(size=(8, 4)) * [0.3, 0.3, 0.2, 0.1]
            X = mpcc_module.rollout(model, x0, U, theta_max=x0[5] + 0.25)
            ref = [x0]
            for u in U:
                ref.append(np.r_[A @ ref[-1][:5] + B @ u[:3], min(ref[-1][5] + u[3], x0[5] + 0.25)])
            # bit for bit where numpy's small matmul rounds each product (this machine's OpenBLAS: the lip- bit-checks
            # are unchanged); a BLAS that fuses multiply-adds may differ in the last bit
            np.testing.assert_allclose(X, np.array(ref), rtol=1e-15, atol=1e-15 * scale)


def test_compiled_rollout_is_the_python_reference_bit_for_bit():
    """lipmpcc._sqp.lip_rollout (the planner's roll-out when it imports) gives rollout_reference's numbers to the
    bit: the same operations on doubles, compiled without fused multiply-adds; ϑ capped, a wider U (its first
    four columns), ±inf and NaN as the reference treats them; bad shapes refused."""
    import lipmpcc.planners.mpcc as mpcc_module
    from lipmpcc.models.lip3d import Lip3dModel

    from lipmpcc.solvers.sqp_compiled import compiled_function

    compiled = compiled_function("lip_rollout")
    if compiled is None:
        pytest.skip("lipmpcc._sqp is not built")
    assert mpcc_module._LIP_ROLLOUT is compiled
    rng = np.random.default_rng(11)
    for model in (Lip3dModel(), Lip3dModel(T=0.33, H=1.02)):
        coef = mpcc_module._lip_coefficients(model)
        for scale in (1e-6, 1.0, 1e3):
            for n, cols in ((5, 4), (1, 4), (0, 4), (7, 6)):
                x0 = rng.normal(size=6) * scale
                U = rng.normal(size=(n, cols)) * scale
                for cap in (np.inf, x0[5] + 0.3 * scale):
                    ref = mpcc_module.rollout_reference(model, x0, U, cap)
                    got = mpcc_module.rollout(model, x0, U, cap)
                    assert got.shape == ref.shape == (n + 1, 6) and got.dtype == np.float64
                    assert np.array_equal(got, ref), (scale, n, cols, cap)
    x0, U = np.zeros(6), np.array([[np.inf, 1.0, np.nan, 0.5], [1.0, -np.inf, 0.0, np.nan]])
    ref = mpcc_module.rollout_reference(Lip3dModel(), x0, U, 0.7)
    coef = mpcc_module._lip_coefficients(Lip3dModel())
    assert np.array_equal(compiled(x0, U, *coef, 0.7), ref, equal_nan=True)
    with pytest.raises(ValueError, match="x0"):
        compiled(np.zeros(5), np.zeros((2, 4)), *coef, np.inf)
    with pytest.raises(ValueError, match="U"):
        compiled(np.zeros(6), np.zeros((2, 3)), *coef, np.inf)
