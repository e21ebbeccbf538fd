"""lipmpcc.loops.lip with ``replan_hz``: paper B's within-step loop on the 3D-LIP (the timed MPCC re-planned
at 25 Hz within each step; the foot lands when and where the last plan said)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, ParameterError
from lipmpcc.loops.lip import run_lip_loop, summarize
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import LinePath
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner
from lipmpcc.push import Push

LINE = LinePath((0, 0), (40, 0))


def _timed(prm: MpccParams, lo: float = 0.3, hi: float = 0.5, **kw) -> TimedMpccPlanner:
    return TimedMpccPlanner(LINE, TimedMpccParams(mpcc=prm, T_min=lo, T_max=hi, **kw), within_step=True)


def _run(pl: TimedMpccPlanner, n: int, obstacles=(), pushes=()):
    prm = pl.params.mpcc
    return run_lip_loop(pl, np.zeros(5), n, LINE, list(obstacles), list(pushes), robot_radius=prm.robot_radius,
                        foot_radius=prm.foot_radius, replan_hz=25.0)


def test_within_step_loop_overtakes_the_08_m_per_s_obstacle():
    """Re-planned at 25 Hz, the timed MPCC passes the 0.8 m/s obstacle (fixed T = 0.4 s tops out at
    0.75 m/s: tests/planners/test_mpcc_timed.py) without contact; each step lasts what its last plan said,
    within [T_min, T_max]."""
    ob = Obstacle.circle(0.25, path=LINE, s0=1.0, speed=0.8)
    log = _run(_timed(MpccParams.overtake_mpcc()), 45, [ob])
    s = summarize(log, [ob])
    d = np.diff(log.t)
    assert s["overtook"] and not log.fell and s["min_clearance_m"] > 0.0
    assert s["solver_failures"] == 0 and s["replans"] == len(log.replan_solve_time) > 4 * log.steps
    assert np.all(d >= 0.3 - 1e-9) and np.all(d <= 0.5 + 1e-9)
    np.testing.assert_allclose(log.planned_durations, d, atol=1e-12)
    assert np.min(d) < 0.32  # it walks faster than T = 0.4 s allows
    # the first footstep is the starting stance under the COM; each later one is where the last plan put it
    np.testing.assert_allclose(log.footholds[0, :2], [0.0, 0.0])
    for k in range(1, log.steps):
        np.testing.assert_allclose(log.footholds[k, :2], log.plans[k - 1].footsteps[0, :2], atol=1e-12)


def test_a_push_within_the_step_changes_that_steps_duration_as_paper_b_fig7():
    """A 0.1 s push 0.1 s into step 8: forward, the step ends sooner than unpushed; backward, later."""
    prm = MpccParams.overtake_mpcc()
    ends = {}
    for name, fx in (("none", 0.0), ("forward", 150.0), ("backward", -150.0)):
        pushes = [] if fx == 0.0 else [Push((fx, 0.0), 0.1, 0.1, step=8)]
        log = _run(_timed(prm, reward_speed=False), 11, pushes=pushes)
        assert not log.fell and summarize(log)["solver_failures"] == 0
        ends[name] = float(np.diff(log.t)[8])
    assert ends["forward"] < ends["none"] - 0.02 and ends["backward"] > ends["none"] + 0.02, ends


@pytest.mark.parametrize("hz", [0.0, -25.0, math.nan, math.inf, "fast", 5000.0])
def test_a_bad_rate_is_named(hz):
    with pytest.raises(ParameterError, match="replan_hz"):
        run_lip_loop(_timed(MpccParams.overtake_mpcc()), np.zeros(5), 2, LINE, replan_hz=hz)


def test_a_planner_that_plans_only_at_exchanges_is_refused():
    prm = MpccParams.overtake_mpcc()
    for pl in (MpccPlanner(LINE, prm), TimedMpccPlanner(LINE, TimedMpccParams(mpcc=prm, T_min=0.3, T_max=0.5))):
        with pytest.raises(InvalidInputError, match="within_step=True"):
            run_lip_loop(pl, np.zeros(5), 2, LINE, replan_hz=25.0)
