"""lipmpcc.loops.alip, the reduced-order closed loop: exact steps, variable touch-down, 25 Hz
re-planning, pushes, the failure criterion and the planner contract (paper B's cases and push test
run through the study: tests/studies/test_stepping_stones.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.conventions import Side
from lipmpcc.exceptions import InvalidInputError, NoFallbackPlanError, ParameterError
from lipmpcc.loops.alip import AlipInitialState, AlipLoopConfig, loop_metrics, run_alip_loop
from lipmpcc.models.alip import AlipParams
from lipmpcc.planners.alip_mpc import AlipMpc
from lipmpcc.planners.base import FootstepSource, PlannerInput, StepPlan
from lipmpcc.push import Push
from lipmpcc.terrain import StoneSequence, approach_footholds, make_profile

P = AlipParams()
LAM = P.lam


class FixedPlanner:
    """Puts each foot at its target (the first stone of the course) + ``offset`` after ``T`` seconds;
    records what the loop gives it (dcm, stance, stance side sign, t since touch-down, the input);
    every ``guess_every``-th plan is a guess (status not "ok")."""

    name = "fixed"
    rate_hz = 25.0

    def __init__(self, T=0.5, offset=(0.0, 0.0), fail_at=None, guess_every=None):
        self.T, self.offset, self.fail_at, self.guess_every = T, np.asarray(offset, float), fail_at, guess_every
        self.calls = []

    def reset(self):
        self.calls = []

    def plan(self, inp: PlannerInput) -> StepPlan:
        self.calls.append((np.array(inp.dcm), np.asarray(inp.stance_pos)[:2], Side(inp.stance_side).sign, inp.time_since_touchdown, inp))
        if self.fail_at is not None and len(self.calls) > self.fail_at:
            raise NoFallbackPlanError("fixed", "failed", 0)
        guess = self.guess_every is not None and len(self.calls) % self.guess_every == 0
        return StepPlan(inp.course.centers[0] + self.offset, 0.0, self.T, status="guess" if guess else "ok")


def short_course(n=8, L=0.4, W=0.0):
    return approach_footholds() + make_profile("I", L=L, W=W).head(n)


@pytest.fixture(scope="module")
def mpc_log():
    return run_alip_loop(AlipMpc(), short_course(8, W=0.15))


def test_steps_follow_the_step_to_step_map(mpc_log):
    """Without pushes each touch-down obeys z^k = sigma^k z^{k-1} - u^k exactly."""
    log = mpc_log
    assert log.completed and not log.fell
    stances = np.vstack([log.start_stance, log.footholds[:-1]])
    for k in range(log.n_steps):
        sig = math.exp(LAM * log.durations[k])
        u = log.footholds[k] - stances[k]
        np.testing.assert_allclose(log.z_initial[k + 1], sig * log.z_initial[k] - u, atol=1e-9)


def test_touchdown_at_latest_plan_and_25hz_replanning(mpc_log):
    log = mpc_log
    for k in range(log.n_steps):
        ticks = np.flatnonzero(log.plan_step == k)
        t_step = log.plan_t_step[ticks]
        np.testing.assert_allclose(np.diff(t_step), 0.04, atol=1e-9)
        assert t_step[0] == 0.0
        # the step ends at the duration planned at its last tick, before the next tick
        assert log.durations[k] == pytest.approx(log.plan_T[ticks[-1]], abs=1e-12)
        assert t_step[-1] <= log.durations[k] <= t_step[-1] + 0.04 + 1e-9
    assert np.all((log.durations >= 0.35 - 1e-9) & (log.durations <= 0.65 + 1e-9))
    np.testing.assert_allclose(log.td_times, np.cumsum(log.durations), atol=1e-9)


def test_logged_trajectory_is_continuous_and_sampled(mpc_log):
    log = mpc_log
    assert np.all(np.diff(log.t) > 0) and np.max(np.diff(log.t)) <= 0.01 + 1e-9
    assert np.max(np.linalg.norm(np.diff(log.com, axis=0), axis=1)) < 0.03  # no jumps in the COM


def test_foothold_off_the_stone_is_a_failure():
    pl = FixedPlanner(offset=(0.15, 0.0))  # 0.15 m past the centre of a 0.2 m stone
    seq2 = make_profile("I", L=0.3, W=0.0).head(3)
    app = approach_footholds()
    bad = run_alip_loop(pl, app + seq2, approach_planner=AlipMpc(), approach_steps=6)
    assert bad.fell and "outside its stone" in bad.fall_reason
    assert bad.fall_index == 6 and loop_metrics(bad)["fall_step"] == 1
    assert loop_metrics(bad)["stones_violated"] == 1 and loop_metrics(bad)["steps_completed"] == 0


def test_kinematic_limit_is_a_failure():
    seq = approach_footholds()
    log = run_alip_loop(FixedPlanner(offset=(0.0, 0.2)), seq)  # right foot 0.06 m right of the left
    assert log.fell and "kinematic" in log.fall_reason and log.fall_index == 0


def test_non_viable_dcm_is_a_failure():
    init = AlipInitialState((0.0, 0.14), +1, (0.0, 0.14), (1.5, 0.0))  # running start, 1.5 m/s
    log = run_alip_loop(AlipMpc(), short_course(4), initial=init)
    assert log.fell and "viable set" in log.fall_reason and log.fall_index == 0
    assert log.plan_t.size == 0 and log.fall_time == 0.0  # detected before the first plan


def test_planner_without_fallback_ends_the_run():
    log = run_alip_loop(FixedPlanner(fail_at=3), short_course(4))
    assert log.fell and "no fallback" in log.fall_reason


def test_push_shifts_the_initial_dcm_by_the_impulse():
    """A push F over [a, b] moves z^0 by F/(m lam^2) (e^{-lam a} - e^{-lam b})."""
    F, a, b = np.array([100.0, -40.0]), 0.1, 0.2
    pl = FixedPlanner(T=0.5)
    run_alip_loop(pl, short_course(2), config=AlipLoopConfig(pushes=(Push.between(tuple(F), a, b, step=0),)))
    z = [(d - s) * math.exp(-LAM * t) for d, s, side, t, _ in pl.calls]
    t_calls = np.array([c[3] for c in pl.calls])
    i_before, i_after = int(np.argmin(abs(t_calls - 0.08))), int(np.argmin(abs(t_calls - 0.24)))
    before, after = z[i_before], z[i_after]
    expected = F / (P.mass * LAM**2) * (math.exp(-LAM * a) - math.exp(-LAM * b))
    np.testing.assert_allclose(after - before, expected, atol=1e-10)
    # an absolute-time push acts the same way
    pl2 = FixedPlanner(T=0.5)
    run_alip_loop(pl2, short_course(2), config=AlipLoopConfig(pushes=(Push.between(tuple(F), a, b),)))
    z2 = [(d - s) * math.exp(-LAM * t) for d, s, side, t, _ in pl2.calls]
    np.testing.assert_allclose(z2[i_after] - z2[0], expected, atol=1e-10)


@pytest.mark.parametrize(
    "call, err, word",
    [
        (lambda: run_alip_loop(AlipMpc(), approach_footholds().head(1), initial=AlipInitialState((0, -0.14), -1, (0, 0))), InvalidInputError, "sides[0]"),
        (lambda: run_alip_loop(AlipMpc(), "stones"), InvalidInputError, "sequence"),
        (lambda: run_alip_loop(object(), short_course(2)), InvalidInputError, "planner"),
        (lambda: run_alip_loop(AlipMpc(), short_course(2), approach_planner=AlipMpc(), approach_steps=99), InvalidInputError, "approach_steps"),
        (lambda: run_alip_loop(AlipMpc(), short_course(2), config="fast"), ParameterError, "config"),
        (lambda: run_alip_loop(AlipMpc(), short_course(2), config=AlipLoopConfig(alip=AlipParams(z_c=1.0))), ParameterError, "alip"),
        (lambda: run_alip_loop(AlipMpc(), short_course(2), initial=AlipInitialState((0, 0.14), 1, (np.nan, 0))), InvalidInputError, "initial.com"),
        (lambda: AlipLoopConfig(replan_period=0.0), ParameterError, "replan_period"),
        (lambda: AlipLoopConfig(pushes=("push",)), ParameterError, "pushes"),
        (lambda: Push.between((1.0, 2.0), 0.2, 0.1), InvalidInputError, "t_start"),
        (lambda: Push.between((1.0,), 0.1, 0.2), InvalidInputError, "force"),
        (lambda: Push.between((1.0, 2.0), 0.1, 0.2, step=-1), InvalidInputError, "step"),
    ],
)
def test_bad_inputs_are_named(call, err, word):
    with pytest.raises(err) as e:
        call()
    assert word in str(e.value)


def test_the_loop_gives_the_planner_the_contract_input():
    """At every tick the planner gets the DCM, the stance foot and side, the time since touch-down
    and the footholds still ahead, the first being the swing foot's target."""
    seq = short_course(3)
    pl = FixedPlanner(T=0.5, guess_every=7)
    log = run_alip_loop(pl, seq)
    # stepping on the targets without regard to the DCM: the ALIP falls after two steps
    assert log.fell and log.n_steps == 2 and "viable set" in log.fall_reason
    assert len(pl.calls) == log.plan_t.size > 20
    for (dcm, stance, side, t, inp), k, t_glob in zip(pl.calls, log.plan_step, log.plan_t):
        assert isinstance(inp.course, StoneSequence) and len(inp.course) == len(seq) - k
        np.testing.assert_array_equal(inp.course.centers[0], seq.centers[k])
        assert inp.step_index == k and inp.t == t_glob and inp.omega == LAM and inp.mass == P.mass
        assert inp.swing_side.sign == int(seq.sides[k]) and side == -int(seq.sides[k])
        assert inp.com_pos[2] == P.z_c and inp.stance_pos[2] == 0.0
        np.testing.assert_allclose(inp.dcm, inp.com_pos[:2] + inp.com_vel[:2] / LAM, atol=1e-12)
    # the stance foot is the last foothold; the swing foot the one before
    first = [c[4] for c in pl.calls if c[4].step_index == 0][0]
    second = [c[4] for c in pl.calls if c[4].step_index == 1][0]
    np.testing.assert_array_equal(first.stance_pos[:2], log.start_stance)
    np.testing.assert_array_equal(first.swing_pos[:2], log.start_swing)
    np.testing.assert_array_equal(second.stance_pos[:2], log.footholds[0])
    np.testing.assert_array_equal(second.swing_pos[:2], log.start_stance)
    assert second.time_since_touchdown == 0.0 and log.plan_t_step[1] == pytest.approx(0.04)
    # plans that are not "ok" are solver failures of the planner under test, but the run goes on
    guesses = sum(1 for i in range(1, len(pl.calls) + 1) if i % 7 == 0)
    assert guesses == 3 and log.solver_failures == guesses == int(np.sum(log.plan_fallback))
    assert log.plan_status.count("guess") == guesses


def test_footplanner_and_old_push_are_deprecated():
    import lipmpcc.loops.alip as loop
    from lipmpcc.sim import alip_loop as old

    with pytest.warns(DeprecationWarning, match="FootstepSource"):
        assert loop.FootPlanner is FootstepSource
    with pytest.warns(DeprecationWarning, match="Push.between"):
        p = old.Push((1.0, 2.0), 0.1, 0.3, 4)
    assert p == Push.between((1.0, 2.0), 0.1, 0.3, step=4) and p.t_end == 0.3


# ---- issue 14: bad arguments of a run are named -------------------------------------------------
def test_bad_initial_state_is_named():
    import math

    import pytest

    from lipmpcc.exceptions import StateError
    from lipmpcc.loops.alip import AlipInitialState

    for kw, match in (({"com": (math.nan, 0.0)}, r"initial.com = .*NaN"), ({"stance": "here"}, r"initial.stance = 'here'"),
                      ({"stance_side": 2}, r"initial.stance_side = 2"), ({"swing_foot": (1.0,)}, r"initial.swing_foot")):
        args = {"stance": (0.0, 0.14), "stance_side": 1, "com": (0.0, 0.1), **kw}
        with pytest.raises(StateError, match=match):
            AlipInitialState(**args)
    assert AlipInitialState((0.0, 0.14), np.int64(1), np.array([0.0, 0.1])).stance_side == 1
