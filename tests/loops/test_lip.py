"""Paper A's results on the 3D-LIP (issue 'Done means'), through lipmpcc.loops.lip; the loop's
planner call and its pushes."""

import math

import numpy as np
import pytest

from lipmpcc.conventions import Side
from lipmpcc.exceptions import InvalidInputError, NoFallbackPlanError, ParameterError, StateError
from lipmpcc.loops import lip as lip_loop
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import ArcPath, LinePath
from lipmpcc.planners.base import PlannerInput, StepPlan
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.push import Push


def _circle_run(pushes=(), steps=110):
    path = ArcPath.circle(2.0, turns=1.25)
    pl = MpccPlanner(path, MpccParams.circle())
    return lip_loop.simulate(pl, np.zeros(5), steps, pushes=pushes)


def test_circle_contouring_error_below_5cm_after_2s():
    log = _circle_run()
    s = lip_loop.summarize(log, settle_time=2.0)
    assert s["solver_failures"] == 0
    assert s["contouring_error_max_m"] <= 0.05
    assert s["progress_m"] > 4 * np.pi  # a full lap in 44 s
    # the continuous COM stays close to the circle too (LIP sway between steps)
    r = np.hypot(log.com[:, 0] - 0.0, log.com[:, 2] - 2.0)
    assert np.max(np.abs(r[log.tc > 2.0] - 2.0)) < 0.12


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_circle_with_random_pushes_recovers_within_2s(seed):
    rng = np.random.default_rng(seed)
    pushes = lip_loop.random_pushes(44.0, rng)
    assert len(pushes) >= 10
    assert all(abs(np.hypot(*p.force)) <= 50.0 and p.duration == 0.1 for p in pushes)
    gaps = np.diff([p.t_start for p in pushes])
    assert np.all(gaps <= 2.0 + 1e-9)
    log = _circle_run(pushes)
    s = lip_loop.summarize(log, settle_time=2.0)
    assert s["solver_failures"] == 0
    rec = np.array(s["push_recovery_s"], dtype=float)
    assert np.all(np.isfinite(rec)) and np.max(rec) <= 2.0


def test_pushes_move_the_point_mass_by_impulse_over_mass():
    """A push of F for Δt changes the COM velocity by F Δt / m (exact integration)."""
    path = LinePath((0, 0), (10, 0))
    pl = MpccPlanner(path, MpccParams.circle())
    x0 = np.zeros(5)
    foot = np.array([0.0, 0.0])
    push = Push((48.0, 0.0), 0.1, 0.1)
    end_p, _, _ = lip_loop._integrate_step(x0, foot, 0.25, 1e-6, 0.0, [push], 48.0, 0.01)
    end_0, _, _ = lip_loop._integrate_step(x0, foot, 0.25, 1e-6, 0.0, [], 48.0, 0.01)
    assert end_p[1] - end_0[1] == pytest.approx(0.1, rel=1e-4)  # 48 N · 0.1 s / 48 kg
    del pl


def test_overtake_cartesian_trails():
    path = LinePath((0, 0), (40, 0))
    ob = Obstacle.circle(0.25, path=path, s0=1.5, speed=0.1)
    pl = MpccPlanner(path, MpccParams.overtake_cartesian())
    log = lip_loop.simulate(pl, np.zeros(5), 70, [ob])
    s = lip_loop.summarize(log, [ob], settle_time=2.0)
    assert not s["overtook"]
    assert s["cartesian_error_max_m"] <= 0.06
    assert s["min_clearance_m"] >= 0.0
    assert s["solver_failures"] == 0
    # trails: always behind the obstacle along the path, and keeps walking
    obs_s = 1.5 + 0.1 * log.t
    assert np.all(log.states[:, 0] < obs_s)
    assert s["progress_m"] > 3.0


def test_overtake_mpcc_overtakes():
    path = LinePath((0, 0), (40, 0))
    ob = Obstacle.circle(0.25, path=path, s0=1.5, speed=0.6)
    pl = MpccPlanner(path, MpccParams.overtake_mpcc())
    log = lip_loop.simulate(pl, np.zeros(5), 70, [ob])
    s = lip_loop.summarize(log, [ob], settle_time=2.0)
    assert s["overtook"]
    assert s["min_clearance_m"] >= 0.0
    assert s["v_avg_mean"] >= 0.9 * 0.3
    assert s["solver_failures"] == 0
    # the paper's signature: the lag stays near zero while the contouring error grows temporarily
    assert s["lag_error_rms_m"] < 0.02
    assert s["contouring_error_max_m"] > 0.3
    assert abs(log.e_contouring[-1]) < 0.05  # back on the path after overtaking


def test_two_obstacles_and_an_ellipse_are_avoided():
    path = LinePath((0, 0), (40, 0))
    obs = [
        Obstacle.circle(0.25, path=path, s0=1.5, speed=0.6),
        Obstacle(axes=(0.5, 0.25), position=(9.0, 0.6), velocity=(0.0, 0.0)),
    ]
    pl = MpccPlanner(path, MpccParams.overtake_mpcc())
    log = lip_loop.simulate(pl, np.zeros(5), 60, obs)
    s = lip_loop.summarize(log, obs, settle_time=2.0)
    assert s["min_clearance_m"] >= 0.0
    assert s["progress_m"] > 12.0


def test_bad_simulation_input():
    pl = MpccPlanner(LinePath((0, 0), (5, 0)), MpccParams.circle())
    with pytest.raises(StateError, match="5-vector"):
        lip_loop.simulate(pl, np.zeros(3), 5)
    with pytest.raises(ParameterError, match="n_steps"):
        lip_loop.simulate(pl, np.zeros(5), 0)
    with pytest.raises(ParameterError, match="first_side"):
        lip_loop.simulate(pl, np.zeros(5), 3, first_side=2)
    with pytest.raises(InvalidInputError, match="MpccPlanner"):
        lip_loop.simulate(object(), np.zeros(5), 3)
    with pytest.raises(InvalidInputError, match="FootstepSource"):
        lip_loop.run_lip_loop(object(), np.zeros(5), 3)
    with pytest.raises(InvalidInputError, match="duration"):
        Push((1.0, 0.0), 0.0, -0.1)
    with pytest.raises(InvalidInputError, match="force"):
        Push((float("nan"), 0.0), 0.0, 0.1)


def test_old_push_of_the_lip_loop_warns_and_is_the_one_push():
    from lipmpcc.sim import lip_loop as old

    with pytest.warns(DeprecationWarning, match="lipmpcc.push.Push"):
        p = old.Push(0.5, 0.1, (10.0, -5.0))
    assert p == Push((10.0, -5.0), 0.5, 0.1) and p.t_end == 0.5 + 0.1


def test_end_of_path_stops_the_run():
    pl = MpccPlanner(LinePath((0, 0), (3, 0)), MpccParams.circle())
    log = lip_loop.simulate(pl, np.zeros(5), 100)
    assert log.stopped_reason == "end of path"
    assert log.steps < 100
    # the progress trace (issue 31): the closest path parameter of every exchange state, ending at theta_final
    assert log.theta_closest.shape == (log.steps + 1,) and log.theta_closest[-1] == log.theta_final
    assert log.theta_closest[0] == 0.0 and log.theta_final > 3.0 - 0.3  # within the outcome's end tolerance


def test_a_diverging_robot_is_reported_as_fallen(monkeypatch):
    """Inputs that push the mass away from its feet make the LIP fall; the run stops and says so."""
    path = LinePath((0, 0), (40, 0))
    pl = MpccPlanner(path, MpccParams.circle())
    real = pl.solve

    def bad(*a, **k):
        r = real(*a, **k)
        r.inputs[0, :2] = [-0.35, 0.0]  # foot far behind the COM, every step
        return r

    monkeypatch.setattr(pl, "solve", bad)
    log = lip_loop.simulate(pl, np.array([0.0, 1.0, 0.0, 0.0, 0.0]), 40)
    s = lip_loop.summarize(log)
    assert s["fell"] is True and s["fall_step"] is not None and log.steps < 40


def test_failed_warm_start_is_retried_from_cold_starts():
    """Cartesian weights against a fast obstacle: warm starts fail at times; the retry from
    cold starts keeps the run free of fallbacks and collisions."""
    path = LinePath((0, 0), (40, 0))
    ob = Obstacle.circle(0.25, path=path, s0=1.5, speed=0.6)
    log = lip_loop.simulate(MpccPlanner(path, MpccParams.overtake_cartesian()), np.zeros(5), 70, [ob])
    s = lip_loop.summarize(log, [ob])
    assert s["solver_failures"] == 0 and not s["fell"]
    assert s["min_clearance_m"] >= 0.0


class Recorder:
    """A capture-point planner that records what the loop gives it: each foot where the DCM of the
    periodic gait of 0.2 m steps, 0.25 m apart, says; steps of ``T``; every third plan a guess."""

    name = "recorder"
    rate_hz = 10.0

    def __init__(self, T=0.4, fail_at=None):
        self.T, self.fail_at = T, fail_at
        self.inputs: list[PlannerInput] = []

    def reset(self):
        self.inputs = []

    def plan(self, inp):
        self.inputs.append(inp)
        if self.fail_at is not None and len(self.inputs) > self.fail_at:
            raise NoFallbackPlanError("recorder", "failed", 0)
        sig = math.exp(inp.omega * self.T)
        offset = np.array([-0.2 / (sig - 1.0), inp.swing_side.sign * 0.25 / (sig + 1.0)])
        return StepPlan(inp.dcm + offset, 0.0, self.T, status="ok" if inp.step_index % 3 else "guess")


def test_any_planner_drives_the_lip_loop():
    """The loop's input at each exchange: the stance is the last foot placed (at first under the COM),
    the swing foot lands now on the plan's foothold, the plan's duration is the next step's; the MPCC's
    own fields are NaN for another planner, and non-"ok" plans are counted as failures."""
    rec = Recorder(T=0.35)
    x0 = np.array([0.0, 0.5, 0.0, 0.0, 0.0])
    log = lip_loop.run_lip_loop(rec, x0, 6, path=LinePath((0, 0), (10, 0)), first_side="right")
    inp = rec.inputs
    assert [i.step_index for i in inp] == list(range(6)) == list(range(log.steps))
    np.testing.assert_allclose([i.t for i in inp], 0.35 * np.arange(6), atol=1e-12)
    assert inp[0].time_since_touchdown == 0.0 and all(i.time_since_touchdown == pytest.approx(0.35) for i in inp[1:])
    assert [i.stance_side for i in inp] == [Side.LEFT, Side.RIGHT] * 3  # the first foot placed is the right
    np.testing.assert_array_equal(inp[0].stance_pos, [0.0, 0.0, 0.0])  # under the initial COM
    for k in range(1, 6):
        np.testing.assert_array_equal(inp[k].stance_pos[:2], log.footholds[k - 1, :2])
        np.testing.assert_array_equal(inp[k].com_pos[[0, 1]], log.states[k, [0, 2]])
        assert inp[k].com_pos[2] == 0.9 and inp[k].course is not None and inp[k].omega == pytest.approx(math.sqrt(9.81 / 0.9))
        np.testing.assert_allclose(inp[k].dcm, log.states[k, [0, 2]] + log.states[k, [1, 3]] / inp[k].omega)
    for k in range(6):  # the foot lands where the plan says, from the DCM at the exchange
        sig = math.exp(inp[k].omega * 0.35)
        np.testing.assert_allclose(log.footholds[k, :2], inp[k].dcm + [-0.2 / (sig - 1), inp[k].swing_side.sign * 0.25 / (sig + 1)])
    assert not log.fell and log.footholds[-1, 0] > 0.8
    assert np.all(np.isnan(log.theta_init)) and np.all(np.isnan(log.e_lag)) and math.isnan(log.v_max)
    assert np.all(np.isfinite(log.e_contouring)) and log.plans == []
    assert list(log.fallback) == [True, False, False, True, False, False]
    assert lip_loop.summarize(log)["solver_failures"] == 2


def test_step_pushes_and_planner_failures():
    """A push with a step index acts from the exchange that starts that step; a planner with nothing to
    offer ends the run (or raises at the first step)."""
    x0 = np.zeros(5)
    a = lip_loop.run_lip_loop(Recorder(), x0, 4)
    b = lip_loop.run_lip_loop(Recorder(), x0, 4, pushes=[Push((48.0, 0.0), 0.1, 0.1, step=2)])
    np.testing.assert_array_equal(a.states[:3], b.states[:3])  # nothing before step 2
    assert b.pushes[0].t_start == pytest.approx(0.8 + 0.1) and b.pushes[0].step is None
    t_end = b.pushes[0].t_end
    ib, ia = int(np.flatnonzero(b.tc == t_end)[0]), int(np.argmin(np.abs(a.tc - t_end)))
    w = math.sqrt(9.81 / 0.9)  # the LIP under a constant force F for Δt: Δẋ = F sinh(ω Δt) / (m ω)
    assert b.com[ib, 1] - a.com[ia, 1] == pytest.approx(48.0 * math.sinh(w * 0.1) / (lip_loop.DIGIT_MASS * w), rel=1e-6)
    stopped = lip_loop.run_lip_loop(Recorder(fail_at=2), x0, 5)
    assert stopped.steps == 2 and "no fallback" in stopped.stopped_reason
    with pytest.raises(NoFallbackPlanError):
        lip_loop.run_lip_loop(Recorder(fail_at=0), x0, 5)


# ---- issue 14: bad arguments of a run are named -------------------------------------------------
def test_bad_run_arguments_are_named():
    import math

    import numpy as np
    import pytest

    from lipmpcc.exceptions import ParameterError, StateError
    from lipmpcc.loops.lip import random_pushes, run_lip_loop
    from lipmpcc.paths import ArcPath
    from lipmpcc.planners.mpcc import MpccParams, MpccPlanner

    path = ArcPath.circle(2.0)
    pl = MpccPlanner(path, MpccParams.circle())
    x0 = np.zeros(5)
    cases = (
        (dict(x0="abc"), StateError, r"x0 = 'abc'"),
        (dict(n_steps=10**11), ParameterError, r"n_steps = 100000000000: expected an integer >= 1 and <= 100000"),
        (dict(n_steps=2.0), ParameterError, r"n_steps = 2.0"),
        (dict(path="circle"), ParameterError, r"path = 'circle'"),
        (dict(obstacles=["x"]), ParameterError, r"obstacles\[0\] = 'x'"),
        (dict(pushes="push"), ParameterError, r"pushes = 'push'"),
        (dict(com_height=None), ParameterError, r"com_height = None"),
        (dict(gravity=-9.81), ParameterError, r"gravity = -9.81"),
        (dict(dt_log=0.0), ParameterError, r"dt_log = 0.0"),
        (dict(stop_at_end="yes"), ParameterError, r"stop_at_end = 'yes'"),
        (dict(robot_radius=math.nan), ParameterError, r"robot_radius = nan"),
        (dict(foot_radius=-1), ParameterError, r"foot_radius = -1"),
        (dict(mass="heavy"), ParameterError, r"mass = 'heavy'"),
    )
    for kw, err, match in cases:
        args = {"planner": pl, "x0": x0, "n_steps": 3, "path": path}
        args.update(kw)
        with pytest.raises(err, match=match):
            run_lip_loop(**args)
    assert pl.solves == 0  # refused before planning
    rng = np.random.default_rng(0)
    with pytest.raises(ParameterError, match=r"t_end = inf"):
        random_pushes(math.inf, rng)
    with pytest.raises(ParameterError, match=r"max_gap = 0.05"):
        random_pushes(5.0, rng, max_gap=0.05)
    with pytest.raises(ParameterError, match=r"rng = 0"):
        random_pushes(5.0, 0)


def test_duration_stats_and_the_logged_durations():
    """Each plan's duration is logged (planned_durations) and executed (diff(t)); the summary gives both
    (issue 18), for any planner; a timed MPCC's v_max is its MPCC's."""
    from lipmpcc.planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner

    assert lip_loop.duration_stats([]) == {"n": 0, "min": None, "median": None, "max": None}
    assert lip_loop.duration_stats([0.3, 0.5, 0.4], values=True) == {"n": 3, "min": 0.3, "median": 0.4, "max": 0.5,
                                                                     "values": [0.3, 0.5, 0.4]}
    path = LinePath((0, 0), (20, 0))
    prm = TimedMpccParams(mpcc=MpccParams.overtake_mpcc(), T_min=0.3, T_max=0.5)
    pl = TimedMpccPlanner(path, prm)
    log = lip_loop.run_lip_loop(pl, np.zeros(5), 6, path)
    np.testing.assert_allclose(log.planned_durations, [p.durations[0] for p in log.plans], atol=0)
    np.testing.assert_allclose(np.diff(log.t), log.planned_durations, atol=1e-12)
    s = lip_loop.summarize(log)
    assert s["planned_durations_s"]["n"] == 6 and len(s["executed_durations_s"]["values"]) == 6
    assert s["v_max"] == prm.mpcc.v_max
