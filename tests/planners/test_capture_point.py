"""Capture-point footstep source, closed on the analytic LIP (no robot)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import ParameterError
from lipmpcc.planners.capture_point import CapturePointParams, CapturePointPlanner, nominal_dcm_offset
from lipmpcc.conventions import LEFT, RIGHT
from lipmpcc.planners.base import FootstepSource, PlannerInput, StepPlan
from lipmpcc.models.lip import dcm, lip_solution
from lipmpcc.models.lip import omega as lip_omega

OMEGA = lip_omega(0.9)


def _walk_lip(
    planner: CapturePointPlanner,
    n_steps: int,
    push: tuple[int, np.ndarray] | None = None,
    early: float = 0.0,
    omega: float = OMEGA,
):
    """Closed loop on the LIP: planner at its rate, support exchange at the planned duration
    (``early`` [s] before it, as when a swing foot touches the ground before the clock). The LIP
    runs with ``omega`` while the planner is told ω = OMEGA (model mismatch).

    Returns the footholds (n+1, 2), their yaws, the COM path (m, 2) and the touch-down times.
    """
    dt = 1.0 / planner.rate_hz
    c, v = np.array([0.0, 0.0]), np.zeros(2)
    stance_side, stance, yaw = RIGHT, np.array([0.0, -0.13]), 0.0
    c = np.array([0.0, -0.13 + 0.055])  # COM shifted towards the first stance foot, at rest
    t, t_td = 0.0, 0.0
    feet, yaws, path, tds = [stance.copy()], [yaw], [c.copy()], [0.0]
    plan: StepPlan | None = None
    for k in range(n_steps):
        if push is not None and push[0] == k:
            v = v + push[1]
        while True:
            inp = PlannerInput(
                t=t,
                com_pos=np.r_[c, 0.9],
                com_vel=np.r_[v, 0.0],
                dcm=dcm(c, v, OMEGA),
                omega=OMEGA,
                stance_side=stance_side,
                stance_pos=np.r_[stance, 0.0],
                stance_yaw=yaw,
                swing_pos=np.r_[feet[-2] if len(feet) > 1 else stance + [0, 0.26], 0.0],
                swing_yaw=yaw,
                time_since_touchdown=t - t_td,
                step_index=k,
                torso_yaw=yaw,
            )
            plan = planner.plan(inp)
            t_end = t_td + plan.duration - early
            h = min(dt, t_end - t)
            c, v, _ = lip_solution(c, v, stance, omega, h)
            t += h
            path.append(c.copy())
            if t >= t_end - 1e-12:
                break
        stance, yaw, t_td = plan.foothold.copy(), plan.yaw, t
        stance_side = LEFT if stance_side == RIGHT else RIGHT
        feet.append(stance.copy())
        yaws.append(yaw)
        tds.append(t)
    return np.array(feet), np.array(yaws), np.array(path), np.array(tds)


def test_nominal_offset_gives_a_periodic_gait() -> None:
    T, L, w = 0.4, 0.2, 0.26
    sigma = math.exp(OMEGA * T)
    # two steps of the step-to-step map z+ = σ z − u return to the start (SPEC §2)
    z = nominal_dcm_offset(L, w, OMEGA, T, swing_left=True)  # relative to the new left stance foot
    u1 = np.array([L, -w])  # the right foot steps next
    z1 = sigma * z - u1
    np.testing.assert_allclose(z1, nominal_dcm_offset(L, w, OMEGA, T, swing_left=False), atol=1e-12)
    z2 = sigma * z1 - np.array([L, w])
    np.testing.assert_allclose(z2, z, atol=1e-12)


def test_planner_satisfies_protocol() -> None:
    assert isinstance(CapturePointPlanner(), FootstepSource)
    assert CapturePointPlanner().name == "capture-point"


@pytest.mark.parametrize("speed", [0.0, 0.5, 0.8])
def test_tracks_commanded_speed_on_the_lip(speed: float) -> None:
    p = CapturePointParams(step_duration=0.4, step_width=0.26, max_accel=2.0, speed_gain=0.0)
    feet, _, path, tds = _walk_lip(CapturePointPlanner(p, speed=speed), 30)
    steps = np.diff(feet, axis=0)
    # after the ramp the steps have the nominal length and width
    np.testing.assert_allclose(steps[-10:, 0], speed * 0.4, atol=2e-3)
    np.testing.assert_allclose(np.abs(steps[-10:, 1]), 0.26, atol=2e-3)
    assert np.all(np.sign(steps[:, 1]) == np.where(np.arange(len(steps)) % 2 == 0, 1, -1))  # alternate
    # the COM moves at the commanded speed and stays between the feet laterally
    v_avg = (feet[-1, 0] - feet[-11, 0]) / (tds[-1] - tds[-11])
    assert v_avg == pytest.approx(speed, abs=5e-3)
    assert np.all(np.abs(path[len(path) // 2 :, 1] - np.mean(feet[-10:, 1])) < 0.13)


def test_turns_on_a_circle_of_radius_v_over_yaw_rate() -> None:
    v, R = 0.5, 2.0
    params = CapturePointParams(max_accel=2.0, max_yaw_accel=2.0, speed_gain=0.0)
    planner = CapturePointPlanner(params, speed=v, yaw_rate=v / R)
    n = int(2 * math.pi * R / (v * 0.4)) + 12
    feet, yaws, path, _ = _walk_lip(planner, n)
    yaws = np.unwrap(yaws)
    assert yaws[-1] - yaws[0] > 2 * math.pi  # a full turn
    mid = 0.5 * (feet[1:] + feet[:-1])[10:]  # midpoints of consecutive feet, after the ramp
    # fit a circle (algebraic least squares)
    A = np.c_[2 * mid, np.ones(len(mid))]
    sol, *_ = np.linalg.lstsq(A, (mid**2).sum(axis=1), rcond=None)
    centre, radius = sol[:2], math.sqrt(sol[2] + sol[:2] @ sol[:2])
    assert radius == pytest.approx(R, rel=0.05)
    assert np.max(np.abs(np.linalg.norm(mid - centre, axis=1) - radius)) < 0.1


@pytest.mark.parametrize("push", [(8, (0.25, 0.15)), (8, (0.0, -0.2)), (9, (0.5, 0.0))])
def test_recovers_from_a_push_with_bounded_steps(push) -> None:
    p = CapturePointParams(max_accel=2.0, speed_gain=0.0)
    feet, _, path, tds = _walk_lip(CapturePointPlanner(p, speed=0.3), 20, push=(push[0], np.array(push[1])))
    steps = np.diff(feet, axis=0)
    # reachability: forward/backward bounds and never crossing the legs
    assert np.all(steps[:, 0] <= p.max_step_forward + 1e-9)
    assert np.all(steps[:, 0] >= -p.max_step_backward - 1e-9)
    lateral = np.abs(steps[:, 1])
    assert np.all(lateral >= p.min_step_width - 1e-9) and np.all(lateral <= p.max_step_width + 1e-9)
    assert np.all(np.sign(steps[:, 1]) == np.where(np.arange(len(steps)) % 2 == 0, 1, -1))
    durations = np.diff(tds)
    assert np.all(durations >= p.min_duration - 1e-9) and np.all(durations <= p.max_duration + 1e-9)
    # the push is absorbed: back to the nominal gait
    np.testing.assert_allclose(steps[-4:, 0], 0.3 * 0.4, atol=5e-3)
    np.testing.assert_allclose(np.abs(steps[-4:, 1]), p.step_width, atol=5e-3)
    np.testing.assert_allclose(durations[-4:], p.step_duration, atol=1e-9)


def test_step_timing_adaptation_escapes_the_lateral_trap() -> None:
    """A lateral push towards the stance foot needs a narrower step than allowed: with a fixed
    duration the clipped steps settle into a sideways drift; shortening the steps recovers."""
    push = (8, np.array([0.0, -0.2]))
    fixed = CapturePointParams(max_accel=2.0, min_duration=0.4, max_duration=0.4, speed_gain=0.0)
    feet, *_ = _walk_lip(CapturePointPlanner(fixed, speed=0.3), 20, push=push)
    assert abs(feet[-1, 1] - feet[-3, 1]) > 0.2  # drifting sideways by > 0.1 m per step
    adaptive = CapturePointParams(max_accel=2.0, speed_gain=0.0)
    feet, _, _, tds = _walk_lip(CapturePointPlanner(adaptive, speed=0.3), 20, push=push)
    assert abs(feet[-1, 1] - feet[-3, 1]) < 1e-3
    assert np.min(np.diff(tds)) < adaptive.step_duration - 0.05


def test_feedback_corrects_early_touchdown_and_model_mismatch() -> None:
    """Touch-down 20 ms before the clock and a LIP 10 % faster than the planner's model: pure LIP
    placement walks too slowly (and, with the early touch-down, too wide); the timing offset and the
    speed integrator restore the commanded speed and the nominal width."""
    v = 0.6
    pure = CapturePointParams(max_accel=2.0, speed_gain=0.0, timing_gain=0.0)
    feet, _, _, tds = _walk_lip(CapturePointPlanner(pure, speed=v), 40, early=0.02, omega=1.1 * OMEGA)
    v_pure = (feet[-1, 0] - feet[-11, 0]) / (tds[-1] - tds[-11])
    assert v_pure < 0.9 * v
    planner = CapturePointPlanner(CapturePointParams(max_accel=2.0), speed=v)
    feet, _, _, tds = _walk_lip(planner, 40, early=0.02, omega=1.1 * OMEGA)
    v_fb = (feet[-1, 0] - feet[-11, 0]) / (tds[-1] - tds[-11])
    assert v_fb == pytest.approx(v, abs=0.01)
    assert planner.timing_offset == pytest.approx(-0.02, abs=1e-3)
    # with the early touch-down alone, the width comes back to nominal too
    feet, *_ = _walk_lip(CapturePointPlanner(pure, speed=v), 30, early=0.02)
    assert np.all(np.abs(np.diff(feet[-6:, 1])) > 0.28)
    feet, *_ = _walk_lip(CapturePointPlanner(CapturePointParams(max_accel=2.0), speed=v), 30, early=0.02)
    np.testing.assert_allclose(np.abs(np.diff(feet[-6:, 1])), 0.26, atol=2e-3)


def test_command_is_ramped() -> None:
    planner = CapturePointPlanner(CapturePointParams(max_accel=0.5), speed=0.8)
    feet, *_ = _walk_lip(planner, 3)
    assert planner.command[0] < 0.8  # 1.2 s at 0.5 m/s² reaches 0.6 m/s at most
    assert planner.command[0] == pytest.approx(0.5 * 1.2, abs=0.02)


def test_bad_parameters_and_commands() -> None:
    with pytest.raises(ParameterError, match="step_duration"):
        CapturePointParams(step_duration=0.0)
    with pytest.raises(ParameterError, match="step_duration"):
        CapturePointParams(step_duration=0.6)
    with pytest.raises(ParameterError, match="step_width"):
        CapturePointParams(step_width=0.6)
    with pytest.raises(ParameterError, match="min_step_width"):
        CapturePointParams(min_step_width=0.6, max_step_width=0.5)
    with pytest.raises(ParameterError, match="speed"):
        CapturePointPlanner(speed=float("nan"))
    with pytest.raises(ParameterError, match="yaw_rate"):
        CapturePointPlanner(yaw_rate=5.0)


# ---- issue 14: parameters of the wrong type are named ------------------------------------------
@pytest.mark.parametrize("field, value", [("step_duration", None), ("max_speed", "fast"), ("timing_gain", math.nan), ("rate_hz", True)])
def test_bad_params_are_named(field, value):
    with pytest.raises(ParameterError, match=rf"{field} = "):
        CapturePointParams(**{field: value})


def test_plan_names_an_input_that_is_not_a_planner_input():
    from lipmpcc.exceptions import InvalidInputError

    with pytest.raises(InvalidInputError, match=r"inp = 'abc': expected a lipmpcc.planners.base.PlannerInput"):
        CapturePointPlanner().plan("abc")
