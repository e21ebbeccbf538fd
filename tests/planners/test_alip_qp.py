"""ALIP-QP (Khadiv et al.'s DCM step-timing QP): the published DcmVrpPlanner reference
cases, the stepping-stone front end, fallback and bad inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, NoFallbackPlanError, ParameterError, StateError
from lipmpcc.planners.alip_qp import (
    AlipQp,
    AlipQpParams,
    DcmVrpParams,
    StepTimingQp,
    StepTimingSolution,
    dcm_vrp_step,
)
from lipmpcc.terrain import Stone

# reactive_planners DcmVrpPlanner unit tests: COM (x, y) -> next step, duration
REFERENCE = [
    ((0.0, 0.0), (0.0, 0.0), 0.2, math.exp(math.sqrt(9.81 / 0.2) * 0.2)),
    ((0.02, 0.0), (0.0800414, 0.0), 0.199436, 4.0420886),
    ((-0.02, 0.0), (-0.0800414, 0.0), 0.199436, 4.0420886),
    ((0.0, 0.02), (0.0, 0.0800414), 0.199436, 4.0420886),
    ((0.0, -0.02), (0.0, -0.0800414), 0.199436, 4.0420886),
]


@pytest.mark.parametrize("com, step, duration, tau", REFERENCE)
def test_published_reference_cases(com, step, duration, tau):
    p = DcmVrpParams.reference()
    sol = dcm_vrp_step(
        p,
        stance_foot=(0.0, 0.0, 0.0),
        t_since_touchdown=0.0,
        left_in_contact=False,  # right foot in stance
        v_des=(0.0, 0.0, 0.0),
        com=(com[0], com[1], 0.20),
        com_vel=(0.0, 0.0, 0.0),
    )
    np.testing.assert_allclose(sol.next_step, step, atol=1e-5)
    assert sol.duration == pytest.approx(duration, abs=1e-5)
    assert sol.tau == pytest.approx(tau, abs=1e-5)
    assert sol.t_nom == pytest.approx(0.2)
    # the end-of-step condition u + b = (xi - u0) e^{-omega t} tau holds
    np.testing.assert_allclose(sol.qp.u + sol.b, np.array(com) * sol.tau, atol=1e-8)


def test_nominal_time_is_mid_range():
    p = DcmVrpParams(0.0, 0.0, 0.0, 0.0, 1.0, 3.0, 0.0, 9.81, (10, 10, 1, 1000, 1000, 1e6, 1e6, 1e6, 1e6))
    assert p.omega == pytest.approx(1.0)
    assert p.nominal_time == 2.0
    assert p.tau_nom == pytest.approx(math.exp(2.0), rel=1e-15)


def test_yaw_and_stance_offset_rotate_the_answer():
    p = DcmVrpParams.reference()
    yaw = 0.6
    c, s = math.cos(yaw), math.sin(yaw)
    foot = np.array([1.0, -2.0])
    com = foot + np.array([0.02 * c, 0.02 * s])
    sol = dcm_vrp_step(p, foot, 0.0, False, (0, 0), com, (0, 0), yaw=yaw)
    np.testing.assert_allclose(sol.next_step, foot + 0.0800414 * np.array([c, s]), atol=1e-5)


def test_soft_dcm_bounds_use_slacks():
    """A DCM offset beyond its bound is allowed, at the price of a slack."""
    qp = StepTimingQp((10, 10, 1, 1000, 1000, 1e6, 1e6, 1e6, 1e6))
    # a large initial DCM with a tight foothold box forces b above its upper bound
    sol = qp.solve([0.2, 0.0], [0.0, 0.0], 4.0, [0.0, 0.0], [-0.05, -0.05], [0.05, 0.05], 3.0, 5.0, [-0.1, -0.1], [0.1, 0.1])
    assert sol.success
    assert sol.b[0] > 0.1 and sol.slacks[0] > 0
    assert sol.b[0] - sol.slacks[0] == pytest.approx(0.1, abs=1e-7)
    np.testing.assert_allclose(sol.u + sol.b, np.array([0.2, 0.0]) * sol.tau, atol=1e-8)
    assert sol.u[0] == pytest.approx(0.05, abs=1e-8)  # the hard foothold bound holds


def _stones(n=3, L=0.4):
    return [Stone((L * (j + 1), 0.14 if j % 2 else -0.14)) for j in range(n)]


def test_stone_front_end_keeps_the_foothold_on_the_stone():
    q = AlipQp()
    lam = q.params.lam
    stones = _stones()
    stance = np.array([0.0, 0.14])
    # a DCM pushing far forward: the foothold is clamped to the stone's front edge
    res = q.solve(stance + np.array([0.35, -0.05]), stance, "left", 0.1, stones)
    assert res.success and not res.fallback
    assert stones[0].contains(res.next_foothold, tol=1e-7)
    assert res.next_foothold[0] == pytest.approx(0.5, abs=1e-6)
    assert q.params.T_min - 1e-9 <= res.step_duration <= q.params.T_max + 1e-9
    z0 = np.array([0.35, -0.05]) * math.exp(-lam * 0.1)
    np.testing.assert_allclose(res.z0, z0)
    np.testing.assert_allclose(res.u[0] + res.z[0], z0 * res.sigma[0], atol=1e-8)


def test_stone_front_end_nominal_state_gives_the_nominal_step():
    q = AlipQp()
    lam, w = q.params.lam, q.params.w
    sig = math.exp(lam * 0.5)
    stance = np.array([0.0, 0.14])
    # periodic gait of (L, W) = (0.4, 0): initial DCM of a right swing
    z0 = np.array([0.4 / (sig - 1), -w / (sig + 1)])
    stones = [Stone((0.4, -0.14)), Stone((0.8, 0.14)), Stone((1.2, -0.14))]
    res = q.solve(stance + z0, stance, "left", 0.0, stones)
    np.testing.assert_allclose(res.next_foothold, [0.4, -0.14], atol=1e-6)
    assert res.step_duration == pytest.approx(0.5, abs=1e-6)


def test_duration_not_before_the_current_time():
    q = AlipQp()
    stance = np.array([0.0, 0.14])
    res = q.solve(stance + np.array([0.3, -0.05]), stance, "left", 0.55, _stones())
    assert res.step_duration >= 0.55 - 1e-9


def test_failure_falls_back_within_the_step_then_raises_after_touchdown(monkeypatch):
    q = AlipQp()
    stance = np.array([0.0, 0.14])
    xi = stance + np.array([0.1, -0.05])
    first = q.solve(xi, stance, "left", 0.0, _stones())
    real = StepTimingQp.solve

    def failing(self, *a, **k):
        s = real(self, *a, **k)
        return StepTimingSolution(s.u, s.tau, s.duration, s.b, s.slacks, False, "PROXQP_MAX_ITER_REACHED", 0, 0.0, s.cost)

    monkeypatch.setattr(StepTimingQp, "solve", failing)
    held = q.solve(xi, stance, "left", 0.04, _stones())
    assert held.fallback and not held.success and q.failures == 1
    np.testing.assert_allclose(held.next_foothold, first.next_foothold)
    with pytest.raises(NoFallbackPlanError):
        q.solve(xi, first.next_foothold, "right", 0.0, _stones()[1:])
    q2 = AlipQp()
    with pytest.raises(NoFallbackPlanError):
        q2.solve(xi, stance, "left", 0.0, _stones())


@pytest.mark.parametrize(
    "call, err, word",
    [
        (lambda: DcmVrpParams(0.2, 0.1, 0, 0, 0.1, 0.3, 0, 0.2, (1,) * 9), ParameterError, "l_min"),
        (lambda: DcmVrpParams(0, 0, 0, 0, 0.3, 0.1, 0, 0.2, (1,) * 9), ParameterError, "t_min"),
        (lambda: DcmVrpParams(0, 0, 0, 0, 0.1, 0.3, 0, -0.2, (1,) * 9), ParameterError, "ht"),
        (lambda: DcmVrpParams(0, 0, 0, 0, 0.1, 0.3, 0, 0.2, (1,) * 8), ParameterError, "weights"),
        (lambda: DcmVrpParams(0, 0, 0, 0, 0.1, 0.3, 0, 0.2, (1,) * 9, t_nom=0.5), ParameterError, "t_nom"),
        (lambda: AlipQpParams(T_min=0.6, T_max=0.4), ParameterError, "T_min"),
        (lambda: AlipQpParams(weights=(1, 1, 0, 1, 1, 1, 1, 1, 1)), ParameterError, "weights"),
        (lambda: AlipQpParams(dcm_target="later"), ParameterError, "dcm_target"),
        (lambda: StepTimingQp((1,) * 9, eps_abs=-1.0), ParameterError, "eps_abs"),
        (
            lambda: dcm_vrp_step(DcmVrpParams.reference(), (0, 0), 0.0, False, (0, 0), (float("nan"), 0), (0, 0)),
            StateError,
            "com",
        ),
        (lambda: dcm_vrp_step(DcmVrpParams.reference(), (0, 0), -1.0, False, (0, 0), (0, 0), (0, 0)), StateError, "t_since"),
        (lambda: dcm_vrp_step(DcmVrpParams.reference(), (0, 0), 0.0, "no", (0, 0), (0, 0), (0, 0)), InvalidInputError, "left_in_contact"),
        (lambda: dcm_vrp_step("params", (0, 0), 0.0, False, (0, 0), (0, 0), (0, 0)), ParameterError, "params"),
        (lambda: AlipQp().solve((0, 0), (0, 0.14), "middle", 0.0, _stones()), InvalidInputError, "side"),
        (lambda: AlipQp().solve((0, 0), (0, 0.14), "left", 0.0, []), InvalidInputError, "stones"),
        (lambda: AlipQp().solve((0, "x"), (0, 0.14), "left", 0.0, _stones()), StateError, "dcm_world"),
        (lambda: AlipQp("fast"), ParameterError, "params"),
    ],
)
def test_bad_inputs_are_named(call, err, word):
    with pytest.raises(err) as e:
        call()
    assert word in str(e.value)


# ---- issue 14: parameters of the wrong type are named ------------------------------------------
@pytest.mark.parametrize(
    "kw, match",
    [
        ({"stone_size": None}, r"stone_size = None"),
        ({"stone_size": (0.2, -0.1)}, r"stone_size = \(0.2, -0.1\): expected two finite numbers > 0"),
        ({"T_nom": "half"}, r"T_nom = 'half'"),
        ({"eps_abs": math.nan}, r"eps_abs = nan"),
    ],
)
def test_bad_qp_params_are_named(kw, match):
    from lipmpcc.planners.alip_qp import AlipQpParams

    with pytest.raises(ParameterError, match=match):
        AlipQpParams(**kw)
