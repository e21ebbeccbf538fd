"""Parity of the C++ whole-body QP with the slow numpy/qpsolvers formulation (reference_qp.py).

On random states and references, in every support mode, for the small test biped and for
digit_like:

- the QP data (H, g, A, b, C, l, u) that C++ assembles equal the numpy ones;
- the C++ solution (q̈, wrenches, motor efforts) equals the qpsolvers one (allclose);
- the solution is physically consistent: M q̈ + h = B u + Σ J_cᵀ w, friction pyramid, CoP in the
  sole, normal-force bounds and motor bounds hold.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from lipmpcc.robot import load_robot
from lipmpcc.wbc import TaskGains, WbcParams, WbcReference, WholeBodyController

from .reference_qp import ReferenceWbcQp

DATA = Path(__file__).resolve().parent / "data"
MODES = {"double": (True, True), "left": (True, False), "right": (False, True), "flight": (False, False)}
N_STATES = 6

# Tight solver tolerance so that both solvers land on the same optimum; every task active.
PARAMS = WbcParams(
    com=TaskGains(weight=(80.0, 100.0, 120.0), kp=(90.0, 100.0, 110.0), kd=(18.0, 20.0, 22.0)),
    angular_momentum_weight=0.05,
    angular_momentum_kd=4.0,
    contact_velocity_gain=2.0,
    min_normal_force=1.0,
    qp_eps_abs=1e-10,
)


def mini_description():
    return load_robot(
        DATA / "mini_biped.xml",
        arm_joints=("left_shoulder_pitch", "right_shoulder_pitch"),
        foot_length=0.2,
        foot_width=0.1,
    )


@pytest.fixture(scope="module", params=["mini_biped", "digit_like"])
def setup(request):
    desc = mini_description() if request.param == "mini_biped" else load_robot("digit_like")
    wbc = WholeBodyController(desc, PARAMS)
    ref_qp = ReferenceWbcQp(wbc.model.spec, PARAMS)
    return request.param, wbc, ref_qp


def random_state(model: pin.Model, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """q inside the joint ranges (base tilted up to 0.3 rad, any yaw), v ~ N(0, 0.5)."""
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    q = np.zeros(model.nq)
    q[:3] = rng.uniform(-0.5, 0.5, 3) + [0.0, 0.0, 1.0]
    rpy = rng.uniform([-0.3, -0.3, -np.pi], [0.3, 0.3, np.pi])
    q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(rpy)).coeffs()
    q[7:] = rng.uniform(0.8 * lo[7:] + 0.2 * hi[7:], 0.2 * lo[7:] + 0.8 * hi[7:])
    v = rng.normal(0.0, 0.5, model.nv)
    return q, v


def random_reference(wbc: WholeBodyController, q: np.ndarray, contact, rng) -> WbcReference:
    """A reference near the current configuration, with random velocities and accelerations."""
    ref = wbc.hold_reference(q, contact)
    ref.com_pos = ref.com_pos + rng.normal(0.0, 0.05, 3)
    ref.com_vel = rng.normal(0.0, 0.1, 3)
    ref.com_acc = rng.normal(0.0, 0.5, 3)
    ref.torso_rot = pin.exp3(rng.normal(0.0, 0.1, 3)) @ ref.torso_rot
    ref.torso_angvel = rng.normal(0.0, 0.2, 3)
    ref.torso_angacc = rng.normal(0.0, 0.5, 3)
    ref.foot_pos = ref.foot_pos + rng.normal(0.0, 0.03, (2, 3))
    ref.foot_vel = rng.normal(0.0, 0.2, (2, 3))
    ref.foot_acc = rng.normal(0.0, 1.0, (2, 3))
    ref.foot_rot = np.stack([pin.exp3(rng.normal(0.0, 0.1, 3)) @ R for R in ref.foot_rot])
    ref.foot_angvel = rng.normal(0.0, 0.2, (2, 3))
    ref.foot_angacc = rng.normal(0.0, 1.0, (2, 3))
    ref.arm_posture = ref.arm_posture + rng.normal(0.0, 0.1, ref.arm_posture.shape)
    ref.max_normal_force = np.array([2000.0, np.inf])
    return ref


def cases(setup, mode: str, seed: int):
    name, wbc, ref_qp = setup
    rng = np.random.default_rng(seed + 1000 * list(MODES).index(mode) + (0 if name == "mini_biped" else 7))
    for _ in range(N_STATES):
        q, v = random_state(ref_qp.model, rng)
        yield q, v, random_reference(wbc, q, MODES[mode], rng)


@pytest.mark.parametrize("mode", list(MODES))
def test_qp_data_match(setup, mode):
    """C++ and numpy assemble the same matrices and vectors (relative to their scale)."""
    _, wbc, ref_qp = setup
    for q, v, ref in cases(setup, mode, seed=1):
        wbc.solve(q, v, ref)
        cpp = wbc.last_qp()
        py = ref_qp.build(q, v, ref)
        for key in ("H", "g", "A", "b", "C", "l", "u"):
            a, b = np.asarray(cpp[key]), py[key]
            assert a.shape == b.shape, key
            if a.size:
                scale = max(1.0, float(np.max(np.abs(b[np.abs(b) < 1e19]), initial=0.0)))
                np.testing.assert_allclose(a, b, rtol=0, atol=1e-11 * scale, err_msg=key)


@pytest.mark.parametrize("mode", list(MODES))
def test_solution_matches_reference(setup, mode):
    """The warm-started C++ solution equals the cold qpsolvers solution of the numpy QP."""
    _, wbc, ref_qp = setup
    solved = 0
    for q, v, ref in cases(setup, mode, seed=2):
        out = wbc.solve(q, v, ref)
        sol = ref_qp.solve(q, v, ref)
        assert out.status == "solved", out.status
        assert sol.found
        solved += 1
        for got, want in ((out.qdd, sol.qdd), (out.wrenches, sol.wrenches), (out.tau, sol.tau)):
            scale = max(1.0, float(np.max(np.abs(want))))
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * scale)
    assert solved == N_STATES


@pytest.mark.parametrize("mode", ["double", "left", "right"])
def test_default_tolerance_solution_close(setup, mode):
    """With the default tolerance (1e-6) the solution is still close to the exact one."""
    name, _, ref_qp = setup
    desc = mini_description() if name == "mini_biped" else load_robot("digit_like")
    params = WbcParams()
    wbc = WholeBodyController(desc, params)
    exact = ReferenceWbcQp(wbc.model.spec, params)
    for q, v, ref in cases((name, wbc, ref_qp), mode, seed=3):
        out = wbc.solve(q, v, ref)
        sol = exact.solve(q, v, ref)
        assert out.status == "solved" and sol.found
        for got, want in ((out.qdd, sol.qdd), (out.wrenches, sol.wrenches), (out.tau, sol.tau)):
            scale = max(1.0, float(np.max(np.abs(want))))
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-3 * scale)


@pytest.mark.parametrize("mode", ["double", "left", "right"])
def test_physical_consistency(setup, mode):
    """Dynamics, friction pyramid, CoP, normal-force bounds and motor bounds hold at the solution."""
    _, wbc, ref_qp = setup
    B = wbc.actuation
    u_min, u_max = wbc.u_limits
    spec = wbc.model.spec
    mu = spec.friction
    half_l = PARAMS.cop_safety_factor * spec.foot_half_length
    half_w = PARAMS.cop_safety_factor * spec.foot_half_width
    tol = 1e-7
    for q, v, ref in cases(setup, mode, seed=4):
        out = wbc.solve(q, v, ref)
        assert out.status == "solved"
        t = ref_qp.terms(q, v)
        rhs = B @ out.tau + sum(t["J_sole"][i].T @ out.wrenches[i] for i in range(2))
        lhs = t["M"] @ out.qdd + t["h"]
        np.testing.assert_allclose(lhs, rhs, rtol=0, atol=1e-8 * max(1.0, np.max(np.abs(lhs))))
        np.testing.assert_allclose(out.tau_joint, B @ out.tau, atol=1e-12)
        assert np.all(out.tau >= u_min - tol) and np.all(out.tau <= u_max + tol)
        for i, in_contact in enumerate(MODES[mode]):
            w = out.wrenches[i]
            if not in_contact:
                assert np.all(w == 0.0)
                continue
            R = t["R_sole"][i]
            f, tau = R.T @ w[:3], R.T @ w[3:]  # in the sole frame
            fz = f[2]
            assert PARAMS.min_normal_force - tol <= fz <= ref.max_normal_force[i] + tol
            assert abs(f[0]) <= mu * fz + tol and abs(f[1]) <= mu * fz + tol
            cop_x, cop_y = -tau[1] / fz, tau[0] / fz
            assert abs(cop_x) <= half_l + 1e-6 and abs(cop_y) <= half_w + 1e-6
            assert abs(tau[2]) <= mu * min(half_l, half_w) * fz + tol
            # no slip: the sole does not accelerate
            acc = t["J_sole"][i] @ out.qdd + t["drift_sole"][i]
            np.testing.assert_allclose(acc, -PARAMS.contact_velocity_gain * t["vel_sole"][i],
                                       atol=1e-6 * max(1.0, np.max(np.abs(acc))))
