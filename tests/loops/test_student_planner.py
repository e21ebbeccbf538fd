"""A footstep planner written in a few lines against the one contract (lipmpcc.planners.base) runs,
unchanged, in the three loops: the 3D-LIP, the ALIP over stepping stones, and digit_like in MuJoCo
under the whole-body QP (issue 13, 'Done means')."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.planners.base import FootstepSource, PlannerInput, StepPlan


class StudentPlanner:
    """Capture point: the swing foot lands where the DCM, at the end of a step of ``T``, is that of the
    periodic gait with steps of ``step`` along the stance foot's heading, ``width`` apart."""

    name, rate_hz = "student", 20.0

    def __init__(self, step: float = 0.15, width: float = 0.25, T: float = 0.4) -> None:
        self.step, self.width, self.T = step, width, T

    def reset(self) -> None:
        pass

    def plan(self, inp: PlannerInput) -> StepPlan:
        sigma = math.exp(inp.omega * self.T)
        p = np.asarray(inp.stance_pos, dtype=float)[:2]
        left = max(self.T - inp.time_since_touchdown, 0.0)
        xi_end = p + (np.asarray(inp.dcm, dtype=float) - p) * math.exp(inp.omega * left)
        c, s = math.cos(inp.stance_yaw), math.sin(inp.stance_yaw)
        b = np.array([self.step / (sigma - 1.0), -inp.swing_side.sign * self.width / (sigma + 1.0)])
        return StepPlan(xi_end - np.array([c * b[0] - s * b[1], s * b[0] + c * b[1]]), inp.stance_yaw, self.T)


def test_it_is_a_footstep_source():
    assert isinstance(StudentPlanner(), FootstepSource)


def test_student_planner_on_the_lip():
    """On the LIP the capture point is exact: from rest, every step is ``step`` long, the feet
    alternate ``width`` apart, and after n steps the COM has moved about n·step."""
    from lipmpcc.loops.lip import run_lip_loop, summarize
    from lipmpcc.paths import LinePath

    n, step, width = 20, 0.15, 0.25
    log = run_lip_loop(StudentPlanner(step, width), np.zeros(5), n, path=LinePath((0.0, 0.0), (10.0, 0.0)))
    assert log.steps == n and not log.fell and log.stopped_reason == "steps"
    np.testing.assert_allclose(np.diff(log.footholds[:, 0]), step, atol=1e-9)
    np.testing.assert_allclose(np.abs(np.diff(log.footholds[:, 1])), width, atol=1e-9)
    assert log.footholds[0, 1] > log.footholds[1, 1]  # the left foot first, on the left
    np.testing.assert_allclose(np.diff(log.t), 0.4, atol=1e-12)
    # the DCM is on the periodic gait at once; the COM converges to it: each step ends with the COM
    # half a step past the stance foot
    np.testing.assert_allclose(log.states[-10:, 0] - log.footholds[-10:, 0], step / 2, atol=1e-4)
    assert log.states[-1, 0] == pytest.approx(n * step, abs=step)
    s = summarize(log)
    assert s["solver_failures"] == 0 and s["progress_m"] == pytest.approx(log.states[-1, 0], abs=1e-3)
    assert s["contouring_error_max_m"] < 0.2  # the lateral sway about the line


def test_student_planner_on_the_alip_over_profile_I():
    """On the ALIP over paper B's course it walks the free approach footholds with steps of ``step``
    (it does not read the stones), then misses the first stone: the loop reports that fall."""
    from lipmpcc.loops.alip import loop_metrics, run_alip_loop
    from lipmpcc.terrain import N_APPROACH, approach_footholds, make_profile

    step, width, T = 0.15, 0.28, 0.5
    seq = approach_footholds() + make_profile("I", L=0.4, W=0.0).head(8)
    log = run_alip_loop(StudentPlanner(step, width, T), seq)
    assert log.n_steps == N_APPROACH + 1 and log.fell and log.fall_index == N_APPROACH
    assert "outside its stone" in log.fall_reason  # not the kinematic limits, not the DCM
    assert np.all(log.kin_ok) and np.all(log.in_stone[:N_APPROACH]) and not log.in_stone[N_APPROACH]
    np.testing.assert_allclose(log.durations, T, atol=1e-12)  # lands when it says, every time
    np.testing.assert_allclose(np.diff(log.footholds[:, 0]), step, atol=1e-6)
    np.testing.assert_allclose(np.abs(log.footholds[:, 1]), width / 2, atol=1e-6)  # ±w/2, as it stood
    assert log.footholds[N_APPROACH, 0] < seq[N_APPROACH].lower[0]  # short of the stone
    assert all(log.dcm_bounds.contains(z, s, 1e-9) for z, s in zip(log.z_initial[1:], -log.step_sides))
    m = loop_metrics(log)
    assert m["fell"] and m["fall_step"] == 1 and m["steps_completed"] == 0 and m["solver_failures"] == 0


@pytest.mark.slow
def test_student_planner_walks_digit_like_in_mujoco():
    """On digit_like under the whole-body QP it walks forward without a fall; the feet land where it
    plans, alternating ``width`` apart, each step forward by about ``step`` (the swing touches down a
    little before the planned T, so a little less)."""
    from lipmpcc.loops.fullbody import FullBodyLoop
    from lipmpcc.robots import load_robot

    n, step, width = 8, 0.15, 0.25
    res = FullBodyLoop(load_robot("digit_like"), planner=StudentPlanner(step, width)).run(n_steps=n)
    assert not res.fell and res.n_steps == n
    tds = res.touchdowns
    assert [td.side for td in tds] == ["left", "right"] * (n // 2)  # the right foot stands first
    for td in tds:
        assert np.linalg.norm(td.pos[:2] - td.planned) < 0.01
    pos = np.array([td.pos[:2] for td in tds])
    advance = np.diff(pos[:, 0])
    assert np.all((advance > 0.6 * step) & (advance < 1.2 * step))
    assert np.all(np.abs(np.abs(np.diff(pos[:, 1])) - width) < 0.08)
    com = res.log.com
    assert com[-1, 0] - com[0, 0] > 0.6 * n * step and abs(com[-1, 1] - com[0, 1]) < 0.15
