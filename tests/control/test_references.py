"""lipmpcc.control.references: LIP COM, swing polynomial with apex, phase re-timing, blending; the old
lipmpcc.trajectory path."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from lipmpcc.exceptions import ParameterError, StateError
from lipmpcc.control.references import (
    LipComReference,
    Quintic,
    _quintic_coefficients_array,
    StepTrajectory,
    SwingParams,
    apex_bump,
    smoothstep5,
)
from lipmpcc.models.lip import dcm, lip_solution
from lipmpcc.models.lip import omega as lip_omega
from lipmpcc.models.phase import PhaseClock


def _numdiff(f, t: float, h: float = 1e-6) -> np.ndarray:
    return (np.asarray(f(t + h)) - np.asarray(f(t - h))) / (2 * h)


# --------------------------------------------------------------------------------------------
# LIP
# --------------------------------------------------------------------------------------------
def test_lip_solution_matches_ode_integration() -> None:
    omega = lip_omega(0.9)
    c0, v0, p = np.array([0.05, -0.08]), np.array([0.4, 0.3]), np.array([0.1, -0.12])

    def f(_t, s):
        return np.r_[s[2:], omega**2 * (s[:2] - p)]

    ts = np.linspace(0.0, 0.6, 13)
    sol = solve_ivp(f, (0, 0.6), np.r_[c0, v0], t_eval=ts, rtol=1e-11, atol=1e-12)
    c, v, a = lip_solution(c0, v0, p, omega, ts)
    np.testing.assert_allclose(c, sol.y[:2].T, atol=1e-8)
    np.testing.assert_allclose(v, sol.y[2:].T, atol=1e-8)
    np.testing.assert_allclose(a, omega**2 * (c - p), atol=1e-12)


def test_lip_com_reference_constant_height_and_analytic() -> None:
    ref = LipComReference(com_height=0.92)
    assert ref.omega == pytest.approx(math.sqrt(9.81 / 0.92))
    ref.reset(1.0, [0.0, 0.02, 0.9], [0.5, -0.1, 0.0], [0.03, -0.1])
    for t in (1.0, 1.1, 1.37):
        pos, vel, acc = ref.evaluate(t)
        c, v, a = lip_solution([0.0, 0.02], [0.5, -0.1], [0.03, -0.1], ref.omega, t - 1.0)
        np.testing.assert_allclose(pos[:2], c, atol=1e-12)
        np.testing.assert_allclose(vel[:2], v, atol=1e-12)
        np.testing.assert_allclose(acc[:2], a, atol=1e-12)
        assert pos[2] == 0.92 and vel[2] == 0.0 and acc[2] == 0.0
    # the DCM grows as ξ − p = (ξ0 − p) e^{ωt}
    xi0 = dcm([0.0, 0.02], [0.5, -0.1], ref.omega)
    pos, vel, _ = ref.evaluate(1.3)
    np.testing.assert_allclose(
        dcm(pos, vel, ref.omega) - [0.03, -0.1], (xi0 - [0.03, -0.1]) * math.exp(0.3 * ref.omega), atol=1e-12
    )


def test_lip_com_reference_moves_its_pivot_continuously() -> None:
    """A planned centre of pressure: the reference keeps its position and velocity and turns about
    the new pivot from then on (acceleration omega² (c − p_new))."""
    ref = LipComReference(com_height=0.92)
    ref.reset(0.0, [0.0, 0.02], [0.5, -0.1], [0.03, -0.1])
    before = ref.evaluate(0.2)
    ref.move_pivot(0.2, np.array([0.08, -0.12]))
    after = ref.evaluate(0.2)
    np.testing.assert_allclose(after[0], before[0], atol=1e-15)
    np.testing.assert_allclose(after[1], before[1], atol=1e-15)
    np.testing.assert_allclose(after[2][:2], ref.omega**2 * (before[0][:2] - [0.08, -0.12]), atol=1e-12)
    np.testing.assert_allclose(ref.pivot, [0.08, -0.12])
    c, v, _ = lip_solution(before[0][:2], before[1][:2], [0.08, -0.12], ref.omega, 0.15)
    np.testing.assert_allclose(ref.evaluate(0.35)[0][:2], c, atol=1e-12)


def test_lip_omega_rejects_nonpositive_height() -> None:
    with pytest.raises(ParameterError, match="com_height"):
        lip_omega(0.0)


# --------------------------------------------------------------------------------------------
# Polynomials
# --------------------------------------------------------------------------------------------
def test_quintic_boundary_conditions() -> None:
    q = Quintic(0.5, 1.3, [1.0, -2.0], [0.3, 0.0], [-1.0, 2.0], x1=[0.0, 1.0], v1=[0.1, -0.2], a1=[0.0, 0.5])
    x, v, a = q.evaluate(0.5)
    np.testing.assert_allclose(x, [1.0, -2.0], atol=1e-12)
    np.testing.assert_allclose(v, [0.3, 0.0], atol=1e-12)
    np.testing.assert_allclose(a, [-1.0, 2.0], atol=1e-12)
    x, v, a = q.evaluate(1.3 - 1e-12)
    np.testing.assert_allclose(x, [0.0, 1.0], atol=1e-9)
    np.testing.assert_allclose(v, [0.1, -0.2], atol=1e-9)
    np.testing.assert_allclose(a, [0.0, 0.5], atol=1e-8)
    # derivatives are consistent
    t = 0.91
    np.testing.assert_allclose(_numdiff(lambda s: q.evaluate(s)[0], t), q.evaluate(t)[1], atol=1e-6)
    np.testing.assert_allclose(_numdiff(lambda s: q.evaluate(s)[1], t), q.evaluate(t)[2], atol=1e-5)
    with pytest.raises(ParameterError, match="t1"):
        Quintic(1.0, 1.0, [0.0])


def _quintic_coefficients_numpy(t0: float, t1: float, x0: np.ndarray, v0: np.ndarray, a0: np.ndarray,
                                x1: np.ndarray, v1: np.ndarray, a1: np.ndarray) -> np.ndarray:
    """The coefficients as Quintic computed them before its per-coordinate loop: numpy on whole vectors."""
    return _quintic_coefficients_array(t1 - t0, x0, v0, a0, x1, v1, a1)


def test_quintic_coefficients_equal_the_vector_arithmetic_to_the_bit() -> None:
    """The per-coordinate float arithmetic of Quintic gives the bits of the numpy expressions it replaced, on
    random ends over six decades (sizes 1 to 6, durations 1 ms to 3 s), and on 2-D ends (the numpy path)."""
    rng = np.random.default_rng(28)
    for _ in range(400):
        n = int(rng.integers(1, 7))
        t0 = float(rng.uniform(-5.0, 50.0))
        t1 = t0 + 10 ** float(rng.uniform(-3.0, 0.5))
        ends = [rng.normal(size=n) * 10 ** float(rng.uniform(-6.0, 3.0)) for _ in range(6)]
        q = Quintic(t0, t1, *ends)
        assert q._c.shape == (6, n)
        assert q._c.tobytes() == _quintic_coefficients_numpy(q.t0, q.t1, *ends).tobytes()
    ends2 = [rng.normal(size=(2, 3)) for _ in range(6)]
    q = Quintic(0.0, 0.4, *ends2)
    assert q._c.tobytes() == _quintic_coefficients_numpy(0.0, 0.4, *ends2).tobytes()


def test_blend_and_bump_shapes() -> None:
    assert smoothstep5(0.0) == (0.0, 0.0, 0.0)
    assert smoothstep5(1.0)[0] == pytest.approx(1.0)
    assert smoothstep5(1.0)[1:] == pytest.approx((0.0, 0.0))
    b, db, ddb = apex_bump(0.5)
    assert b == pytest.approx(1.0) and db == pytest.approx(0.0)
    assert ddb < 0.0
    for tau in (0.0, 1.0):
        assert apex_bump(tau) == pytest.approx((0.0, 0.0, 0.0))
    for tau in (0.2, 0.7):
        assert _numdiff(lambda s: apex_bump(s)[0], tau) == pytest.approx(apex_bump(tau)[1], abs=1e-6)
        assert _numdiff(lambda s: apex_bump(s)[1], tau) == pytest.approx(apex_bump(tau)[2], abs=1e-4)


# --------------------------------------------------------------------------------------------
# Phase
# --------------------------------------------------------------------------------------------
def test_phase_is_linear_then_retimed_continuously() -> None:
    ph = PhaseClock(2.0, 2.4)
    assert ph.tau(2.0) == 0.0
    assert ph.tau(2.2) == pytest.approx(0.5)
    assert ph.tau_dot(2.1) == pytest.approx(2.5)
    # the planner shortens the step at t = 2.2: T_des 2.4 -> 2.35
    before = ph.tau(2.2)
    ph.retime(2.2, 2.35)
    assert ph.tau(2.2) == pytest.approx(before)
    assert ph.tau_dot(2.25) == pytest.approx((1 - 0.5) / (2.35 - 2.2))  # SPEC §2, eq. 13
    t = 2.3
    assert ph.tau(t) == pytest.approx(0.5 + 0.5 * (t - 2.2) / (2.35 - 2.2))  # SPEC §2, eq. 12
    assert ph.tau(2.35) == pytest.approx(1.0)
    assert ph.tau(2.3499) < 1.0
    # lengthening again later keeps τ continuous and reaches 1 at the latest end time
    tau_i = ph.tau(2.3)
    ph.retime(2.3, 2.5)
    assert ph.tau(2.3) == pytest.approx(tau_i)
    assert ph.tau(2.5) == pytest.approx(1.0)
    assert ph.tau(2.49) < 1.0
    assert ph.tau_dot(2.6) == 0.0 and ph.tau(2.6) == 1.0


def test_phase_rejects_end_before_now() -> None:
    with pytest.raises(ParameterError, match="t_end"):
        PhaseClock(1.0, 0.9)
    ph = PhaseClock(0.0, 0.4)
    with pytest.raises(ParameterError, match="t_end"):
        ph.retime(0.3, 0.3)


# --------------------------------------------------------------------------------------------
# Swing foot
# --------------------------------------------------------------------------------------------
def _step(**kw) -> StepTrajectory:
    args = dict(
        t_start=1.0,
        t_end=1.4,
        start_pos=np.array([0.0, 0.13, 0.0]),
        start_yaw=0.0,
        target_pos=np.array([0.4, 0.15, 0.0]),
        target_yaw=0.2,
        torso_start_yaw=0.05,
        params=SwingParams(apex_height=0.1),
    )
    args.update(kw)
    return StepTrajectory(**args)


def test_swing_starts_at_liftoff_reaches_apex_mid_phase_and_lands_at_foothold() -> None:
    st = _step()
    r0 = st.evaluate(1.0)
    np.testing.assert_allclose(r0.swing_pos, [0.0, 0.13, 0.0], atol=1e-12)
    np.testing.assert_allclose(r0.swing_vel, 0.0, atol=1e-12)
    assert r0.swing_yaw == 0.0 and r0.torso_yaw == 0.05
    mid = st.evaluate(1.2)
    assert mid.tau == pytest.approx(0.5)
    assert mid.swing_pos[2] == pytest.approx(0.1)
    assert mid.swing_vel[2] == pytest.approx(0.0, abs=1e-12)
    zs = [st.evaluate(t).swing_pos[2] for t in np.linspace(1.0, 1.4, 81)]
    assert max(zs) == pytest.approx(0.1) and min(zs) >= -1e-12
    end = st.evaluate(1.4)
    assert end.tau == 1.0
    np.testing.assert_allclose(end.swing_pos, [0.4, 0.15, 0.0], atol=1e-12)
    np.testing.assert_allclose(end.swing_vel, 0.0, atol=1e-12)
    np.testing.assert_allclose(end.swing_acc, 0.0, atol=1e-12)
    assert end.swing_yaw == pytest.approx(0.2) and end.swing_yaw_rate == pytest.approx(0.0)
    assert end.torso_yaw == pytest.approx(0.2) and end.torso_yaw_rate == pytest.approx(0.0)
    # velocities are the time derivatives of the positions
    t = 1.13
    np.testing.assert_allclose(_numdiff(lambda s: st.evaluate(s).swing_pos, t), st.evaluate(t).swing_vel, atol=1e-6)
    np.testing.assert_allclose(_numdiff(lambda s: st.evaluate(s).swing_vel, t), st.evaluate(t).swing_acc, atol=1e-4)


def test_apex_is_above_mean_height_on_uneven_landing() -> None:
    st = _step(target_pos=np.array([0.4, 0.15, 0.06]))
    assert st.evaluate(1.2).swing_pos[2] == pytest.approx(0.03 + 0.1)
    np.testing.assert_allclose(st.evaluate(1.4).swing_pos, [0.4, 0.15, 0.06], atol=1e-12)


def _continuity(st: StepTrajectory, t: float, change) -> tuple[StepTrajectory, float, float]:
    eps = 1e-7
    before = st.evaluate(t)
    change(st)
    after = st.evaluate(t)
    np.testing.assert_allclose(after.swing_pos, before.swing_pos, atol=1e-12)
    np.testing.assert_allclose(after.swing_vel, before.swing_vel, atol=1e-9)
    np.testing.assert_allclose(after.swing_acc, before.swing_acc, atol=1e-7)
    assert after.torso_yaw == pytest.approx(before.torso_yaw, abs=1e-12)
    assert after.torso_yaw_rate == pytest.approx(before.torso_yaw_rate, abs=1e-9)
    assert after.tau == pytest.approx(before.tau, abs=1e-12)
    # and just after the change the trajectory moves on smoothly
    nxt = st.evaluate(t + eps)
    np.testing.assert_allclose(nxt.swing_pos, after.swing_pos, atol=1e-6)
    return st, before.tau, after.tau


def test_foothold_change_mid_swing_is_continuous_and_lands_at_new_foothold() -> None:
    st = _step()
    new = np.array([0.5, 0.22, 0.0])
    _continuity(st, 1.15, lambda s: s.update(1.15, target_pos=new, target_yaw=0.3, torso_target_yaw=0.25))
    assert st.n_updates == 1
    end = st.evaluate(1.4)
    np.testing.assert_allclose(end.swing_pos, new, atol=1e-12)
    np.testing.assert_allclose(end.swing_vel, 0.0, atol=1e-12)
    assert end.swing_yaw == pytest.approx(0.3)
    assert end.torso_yaw == pytest.approx(0.25)
    # velocity stays bounded (no spike) over the rest of the swing
    speeds = [np.linalg.norm(st.evaluate(t).swing_vel) for t in np.linspace(1.15, 1.4, 51)]
    assert max(speeds) < 4.0


def test_retiming_mid_swing_is_continuous_and_lands_at_new_time() -> None:
    st = _step()
    _continuity(st, 1.25, lambda s: s.update(1.25, t_end=1.33))
    assert st.t_end == pytest.approx(1.33)
    end = st.evaluate(1.33)
    assert end.tau == pytest.approx(1.0)
    np.testing.assert_allclose(end.swing_pos, [0.4, 0.15, 0.0], atol=1e-12)
    np.testing.assert_allclose(end.swing_vel, 0.0, atol=1e-12)
    assert st.evaluate(1.32).tau < 1.0
    # a longer step: lands later, still exactly at the foothold
    st = _step()
    _continuity(st, 1.1, lambda s: s.update(1.1, t_end=1.55, target_pos=np.array([0.3, 0.1, 0.0])))
    assert st.evaluate(1.54).swing_pos[2] > 0.0
    np.testing.assert_allclose(st.evaluate(1.55).swing_pos, [0.3, 0.1, 0.0], atol=1e-12)


def test_many_small_updates_stay_smooth() -> None:
    """A planner at 100 Hz moving the foothold a little each time gives a smooth, landing foot."""
    st = _step()
    ts = np.arange(1.0, 1.4, 0.0005)
    pos, vel = [], []
    for t in ts:
        k = round((t - 1.0) / 0.01)
        if abs((t - 1.0) - 0.01 * k) < 1e-9:
            st.update(t, target_pos=np.array([0.4 + 0.2 * (t - 1.0), 0.15 - 0.1 * (t - 1.0), 0.0]), t_end=1.4 - 0.1 * (t - 1.0))
        r = st.evaluate(t)
        pos.append(r.swing_pos)
        vel.append(r.swing_vel)
    pos, vel = np.array(pos), np.array(vel)
    assert np.max(np.linalg.norm(np.diff(pos, axis=0), axis=1)) < 2e-3  # no jumps (≤ 4 m/s × 0.5 ms)
    assert np.max(np.linalg.norm(np.diff(vel, axis=0), axis=1)) < 0.05  # no velocity steps
    final = st.evaluate(st.t_end)
    np.testing.assert_allclose(final.swing_pos, st.target_pos, atol=1e-12)
    np.testing.assert_allclose(final.swing_vel, 0.0, atol=1e-12)


def test_target_is_locked_after_freeze_phase() -> None:
    st = _step(params=SwingParams(apex_height=0.1, freeze_phase=0.8))
    assert not st.update(1.35, target_pos=np.array([1.0, 1.0, 0.0]))
    np.testing.assert_allclose(st.target_pos, [0.4, 0.15, 0.0])
    # re-timing is still allowed, but never closer than min_remaining to now
    assert st.update(1.3, t_end=1.32)
    assert st.t_end == pytest.approx(1.3 + SwingParams().min_remaining)


def test_repeating_the_end_time_never_postpones_landing() -> None:
    """A planner that keeps asking for the same end time near the end of the step does not push
    the landing out (min_remaining only limits *changes*)."""
    st = _step()
    for t in np.arange(1.0, 1.4, 0.0025):
        st.update(float(t), t_end=1.4)
    assert st.t_end == pytest.approx(1.4)
    assert st.evaluate(1.4).tau == 1.0
    # asking for an earlier end when the current one is already closer than min_remaining: kept
    st = _step()
    st.update(1.37, t_end=1.371)
    assert st.t_end == pytest.approx(1.4)


def test_heading_wraps_the_short_way() -> None:
    st = _step(start_yaw=3.1, torso_start_yaw=3.1, target_yaw=-3.1)
    end = st.evaluate(1.4)
    assert end.swing_yaw == pytest.approx(3.1 + (2 * math.pi - 6.2))
    assert end.torso_yaw == pytest.approx(end.swing_yaw)


def test_bad_inputs_are_named() -> None:
    with pytest.raises(StateError, match="target_pos"):
        _step(target_pos=np.array([0.0, np.nan, 0.0]))
    with pytest.raises(StateError, match="start_pos"):
        _step(start_pos=np.zeros(2))
    with pytest.raises(ParameterError, match="apex_height"):
        SwingParams(apex_height=-0.1)
    with pytest.raises(ParameterError, match="freeze_phase"):
        SwingParams(freeze_phase=0.0)


def test_the_old_trajectory_path_forwards_every_name_with_a_warning() -> None:
    import lipmpcc.trajectory as old
    from lipmpcc import conventions, rotations
    from lipmpcc.control import references
    from lipmpcc.models import lip, phase

    moved = {
        "StepTrajectory": references.StepTrajectory, "PhaseClock": phase.PhaseClock,
        "LipComReference": references.LipComReference, "wrap_angle": rotations.wrap_angle,
        "yaw_rotation": rotations.yaw_rotation, "unwrap_near": rotations.unwrap_near, "lip_omega": lip.omega,
        "lip_solution": lip.lip_solution, "dcm": lip.dcm, "GRAVITY": conventions.GRAVITY,
    }
    for name, obj in moved.items():
        with pytest.warns(DeprecationWarning, match=rf"lipmpcc\.trajectory\.{name} moved"):
            assert getattr(old, name) is obj
    with pytest.raises(AttributeError):
        old.no_such_name
    assert lip_omega(0.9, 9.81) == math.sqrt(9.81 / 0.9) and LipComReference(0.9).omega == lip_omega(0.9)


# ---- issue 14: parameters of the wrong type are named ------------------------------------------
def test_bad_swing_params_are_named():
    import pytest

    from lipmpcc.control.references import SwingParams
    from lipmpcc.exceptions import ParameterError

    for kw, match in (({"apex_height": None}, r"apex_height = None"), ({"freeze_phase": "x"}, r"freeze_phase = 'x'")):
        with pytest.raises(ParameterError, match=match):
            SwingParams(**kw)
