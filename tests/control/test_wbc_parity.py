"""Parity of the C++ whole-body QP with the slow numpy/qpsolvers formulation (lipmpcc.control.reference_qp).

On random states and references, in every support mode, for the small test biped, for digit_like
and — when ../shared is present — for the reference Digit v3 (closed loops, passive springs,
slide+ball base, gears) in three variants: loops eliminated (the default), loops as multipliers,
and compliant instead of rigid passive springs:

- the QP data (H, g, A, b, C, l, u) that C++ assembles equal the numpy ones (for eliminated loops:
  the numpy QP in the independent accelerations built from C++'s choice of dependent coordinates);
- the C++ solution (q̈, wrenches, motor efforts, loop forces, spring torques) equals the solution of
  the textbook QP (all accelerations, loop forces as variables) solved by qpsolvers (allclose);
- the solution is physically consistent: M q̈ + h₀ = B u + Σ J_cᵀ w + J_loopᵀ λ + S_springᵀ τ_s
  (h₀: bias forces without the springs), the loops' relative accelerations vanish, rigid passive
  springs follow q̈_s = -k_d q̇_s, friction pyramid, CoP in the sole, normal-force and motor bounds
  hold.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.control.wbc_types import TaskGains, WbcParams, WbcReference
from lipmpcc.robots import load_robot

from ..conftest import SHARED_DIGIT
from lipmpcc.control.reference_qp import ReferenceWbcQp

DATA = Path(__file__).resolve().parent / "data"
MODES = {"double": (True, True), "left": (True, False), "right": (False, True), "flight": (False, False)}
N_STATES = 6
N_STATES_V3 = 3  # the closed-loop reference QP is slower to build and solve

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


#: Digit v3 variants: (loop_formulation, spring_model)
V3 = {"digit_v3": ("eliminate", "rigid"), "digit_v3-multipliers": ("multipliers", "rigid"),
      "digit_v3-compliant": ("eliminate", "compliant")}


def make_controller(name: str, params: WbcParams) -> WholeBodyController:
    if name == "mini_biped":
        return WholeBodyController(mini_description(), params)
    if name == "digit_like":
        return WholeBodyController(load_robot("digit_like"), params)
    if not SHARED_DIGIT.exists():
        pytest.skip(f"reference model not found at {SHARED_DIGIT}")
    formulation, springs = V3[name]
    return WholeBodyController(load_robot(SHARED_DIGIT), params, loop_formulation=formulation, spring_model=springs)


@pytest.fixture(scope="module", params=["mini_biped", "digit_like", *V3])
def setup(request):
    wbc = make_controller(request.param, PARAMS)
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


def loop_state(wbc: WholeBodyController, ref_qp: ReferenceWbcQp, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A state of a closed-loop model on its loop manifold: the standing pose with the base moved
    (tilt up to 0.3 rad, any yaw), the motors moved by N(0, 0.1) rad and the springs by N(0, 0.01)
    rad, the loops closed again by Newton steps on the other unactuated joints, and a velocity
    N(0, 0.5) projected onto the loops' admissible motions."""
    from lipmpcc.robots.state_map import StateMap
    import mujoco

    m = ref_qp.model
    mj = mujoco.MjModel.from_xml_path(str(wbc.description.mjcf_path))
    q0, _ = StateMap(mj).to_pinocchio(np.asarray(wbc.description.standing_qpos), np.zeros(mj.nv))
    nl = ref_qp.n_loop
    springs = {s[1] for s in ref_qp.springs}
    cols = [i for i in range(6, m.nv) if not np.any(ref_qp.B[i]) and i not in springs]
    actuated = np.flatnonzero(np.any(ref_qp.B != 0.0, axis=1))
    for _attempt in range(10):  # a draw whose loops cannot close (a rod beyond reach) is redrawn
        dq = np.zeros(m.nv)
        dq[actuated] = rng.normal(0.0, 0.1, actuated.size)  # motors
        for _, iv, _, _, _ in ref_qp.springs:
            dq[iv] = rng.normal(0.0, 0.01)  # spring deflections
        q = pin.integrate(m, q0, dq)
        q[:3] = rng.uniform(-0.5, 0.5, 3) + [0.0, 0.0, 1.0]
        rpy = rng.uniform([-0.3, -0.3, -np.pi], [0.3, 0.3, np.pi])
        q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(rpy)).coeffs()
        for _ in range(20):
            t = ref_qp.terms(q, np.zeros(m.nv))
            r = t["loop_residual"]
            if np.max(np.abs(r)) < 1e-12:
                break
            step = np.zeros(m.nv)
            step[cols] = -np.linalg.lstsq(t["J_extra"][:nl][:, cols], r, rcond=None)[0]
            q = pin.integrate(m, q, step)
        if np.max(np.abs(ref_qp.terms(q, np.zeros(m.nv))["loop_residual"])) < 1e-10:
            break
    else:
        raise AssertionError("no closed-loop state found")
    J = ref_qp.terms(q, np.zeros(m.nv))["J_extra"][:nl]
    v = rng.normal(0.0, 0.5, m.nv)
    v -= np.linalg.pinv(J) @ (J @ v)
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


def models(*v3_variants: str) -> pytest.MarkDecorator:
    """Run a test on the tree models and on these Digit v3 ``v3_variants`` only (indirect ``setup``)."""
    return pytest.mark.parametrize("setup", ["mini_biped", "digit_like", *v3_variants], indirect=True)


def cases(setup, mode: str, seed: int):
    name, wbc, ref_qp = setup
    offset = {"mini_biped": 0, "digit_like": 7}.get(name, 11)
    rng = np.random.default_rng(seed + 1000 * list(MODES).index(mode) + offset)
    for _ in range(N_STATES if name not in V3 else N_STATES_V3):
        q, v = loop_state(wbc, ref_qp, rng) if ref_qp.n_loop else random_state(ref_qp.model, rng)
        yield q, v, random_reference(wbc, q, MODES[mode], rng)


def reference_qp_data(wbc: WholeBodyController, ref_qp: ReferenceWbcQp, q, v, ref) -> dict:
    """The numpy QP in the C++ controller's coordinates (reduced when it eliminates loops)."""
    if wbc.model.eliminates_loops:
        return ref_qp.build_reduced(q, v, ref, list(wbc.model.dependent_idx_v))
    return ref_qp.build(q, v, ref)


def assert_same_qp_data(cpp: dict, py: dict, keys: tuple[str, ...], rel: float) -> None:
    """The C++ QP's ``keys`` equal the numpy reference's (same shapes; within ``rel`` of the largest finite
    magnitude of each, and at least ``rel`` absolute)."""
    for key in keys:
        a, b = np.asarray(cpp[key]), py[key]
        assert a.shape == b.shape, key
        if a.size:
            scale = max(1.0, float(np.max(np.abs(b[np.abs(b) < 1e19]), initial=0.0)))
            np.testing.assert_allclose(a, b, rtol=0, atol=rel * scale, err_msg=key)


@pytest.mark.parametrize("mode", list(MODES))
def test_qp_data_match(setup, mode):
    """C++ and numpy assemble the same matrices and vectors (relative to their scale)."""
    name, wbc, ref_qp = setup
    # closed-loop QPs go through a solve with J_d (eliminated) or span 1e-6..1e3 (rod inertias)
    rel = 1e-11 if name in ("mini_biped", "digit_like") else 1e-9
    for q, v, ref in cases(setup, mode, seed=1):
        wbc.solve(q, v, ref)
        cpp = wbc.last_qp()
        py = reference_qp_data(wbc, ref_qp, q, v, ref)
        assert_same_qp_data(cpp, py, ("H", "g", "A", "b", "C", "l", "u"), rel)


@models("digit_v3", "digit_v3-multipliers")
@pytest.mark.parametrize("mode", list(MODES))
def test_solution_matches_reference(setup, mode):
    """The warm-started C++ solution equals the cold qpsolvers solution of the numpy QP (for Digit v3,
    both C++ formulations against the textbook QP; its compliant-spring QPs are often infeasible
    under random references — the motors cannot accelerate unloaded springs — so they are compared
    matrix by matrix only)."""
    _, wbc, ref_qp = setup
    solved = 0
    for q, v, ref in cases(setup, mode, seed=2):
        out = wbc.solve(q, v, ref)
        sol = ref_qp.solve(q, v, ref)
        assert out.status == "solved", out.status
        assert sol.found
        solved += 1
        pairs = [(out.qdd, sol.qdd), (out.wrenches, sol.wrenches), (out.tau, sol.tau),
                 (out.loop_forces, sol.loop_forces), (out.spring_torques, sol.spring_torques)]
        for got, want in pairs:
            assert got.shape == want.shape
            if want.size:
                scale = max(1.0, float(np.max(np.abs(want))))
                np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * scale)
    assert solved == (N_STATES_V3 if setup[0] in V3 else N_STATES)


@models("digit_v3")
@pytest.mark.parametrize("mode", ["double", "left", "right"])
def test_default_tolerance_solution_close(setup, mode):
    """With the default tolerance (1e-6) the solution is still close to the exact one."""
    name, _, ref_qp = setup
    params = WbcParams()
    wbc = make_controller(name, params)
    exact = ReferenceWbcQp(wbc.model.spec, params)
    for q, v, ref in cases((name, wbc, ref_qp), mode, seed=3):
        out = wbc.solve(q, v, ref)
        sol = exact.solve(q, v, ref)
        assert out.status == "solved" and sol.found
        for got, want in ((out.qdd, sol.qdd), (out.wrenches, sol.wrenches), (out.tau, sol.tau)):
            scale = max(1.0, float(np.max(np.abs(want))))
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-3 * scale)


@models("digit_v3", "digit_v3-multipliers")
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
    nl = ref_qp.n_loop
    for q, v, ref in cases(setup, mode, seed=4):
        out = wbc.solve(q, v, ref)
        assert out.status == "solved"
        t = ref_qp.terms(q, v)
        h0 = t["h"].copy()  # bias and damping forces without the springs
        S = np.zeros((len(ref_qp.springs), ref_qp.nv))
        for k, (iq, iv, stiffness, rest, _) in enumerate(ref_qp.springs):
            h0[iv] -= stiffness * (t["q"][iq] - rest)
            S[k, iv] = 1.0
        rhs = B @ out.tau + sum(t["J_sole"][i].T @ out.wrenches[i] for i in range(2))
        rhs += t["J_extra"][:nl].T @ out.loop_forces + S.T @ out.spring_torques
        lhs = t["M"] @ out.qdd + h0
        np.testing.assert_allclose(lhs, rhs, rtol=0, atol=1e-8 * max(1.0, np.max(np.abs(lhs))))
        if nl:  # the loops stay closed: the anchors' relative acceleration is zero
            acc = t["J_extra"][:nl] @ out.qdd + t["gamma_extra"][:nl]
            np.testing.assert_allclose(acc, 0.0, atol=1e-6 * max(1.0, np.max(np.abs(t["gamma_extra"]))))
        for iq, iv, stiffness, rest, rigid in ref_qp.springs:
            if rigid:  # the controller holds a rigid passive spring at qdd = -k_d qdot
                assert out.qdd[iv] == pytest.approx(-PARAMS.spring_damping_gain * v[iv], abs=1e-6)
            else:  # a compliant spring carries its spring torque only
                i = [s[1] for s in ref_qp.springs].index(iv)
                assert out.spring_torques[i] == pytest.approx(-stiffness * (t["q"][iq] - rest), abs=1e-12)
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
            cx, cy = spec.sole_cop_centers[i]  # the sole rectangle's centre in the sole frame
            cop_x, cop_y = -tau[1] / fz, tau[0] / fz
            assert abs(cop_x - cx) <= half_l + 1e-6 and abs(cop_y - cy) <= half_w + 1e-6
            torsion = tau[2] - cx * f[1] + cy * f[0]  # about the centre
            assert abs(torsion) <= mu * min(half_l, half_w) * fz + tol
            # no slip: the sole does not accelerate
            acc = t["J_sole"][i] @ out.qdd + t["drift_sole"][i]
            np.testing.assert_allclose(acc, -PARAMS.contact_velocity_gain * t["vel_sole"][i],
                                       atol=1e-6 * max(1.0, np.max(np.abs(acc))))


@pytest.mark.parametrize("name", ["mini_biped", "digit_like", "digit_v3"])
def test_joint_limit_rows_match_the_reference_and_hold(name):
    """With ``joint_limit_horizon`` the C++ QP has one row per range-limited actuated joint, the same as
    the numpy reference QP's, and both solutions keep ``q + v h + q̈ h²/2`` in range for joints driven
    at their stops (states with some joints at a limit, moving out of it)."""
    h = 0.05
    params = dataclasses.replace(PARAMS, joint_limit_horizon=h)
    wbc = make_controller(name, params)
    ref_qp = ReferenceWbcQp(wbc.model.spec, params)
    assert len(ref_qp.limits) == len(wbc.model.limit_idx_q) > 0
    rng = np.random.default_rng(5)
    active = 0
    for mode in ("double", "left"):
        for q, v, ref in cases((name, wbc, ref_qp), mode, seed=4):
            for iq, iv, lo, hi in ref_qp.limits[::3]:  # some joints at a stop, moving out of range
                at_hi = rng.random() < 0.5
                q[iq] = hi if at_hi else lo
                if not ref_qp.n_loop:
                    v[iv] = 0.5 if at_hi else -0.5
            if ref_qp.n_loop:  # keep the closed-loop state consistent: only velocities are free
                q, v = loop_state(wbc, ref_qp, rng)
            out = wbc.solve(q, v, ref)
            cpp = wbc.last_qp()
            py = reference_qp_data(wbc, ref_qp, q, v, ref)
            assert cpp["n_limits"] == len(ref_qp.limits)
            assert_same_qp_data(cpp, py, ("C", "l", "u"), 1e-9)
            if out.status != "solved":
                continue
            for iq, iv, lo, hi in ref_qp.limits:
                pred = q[iq] + v[iv] * h + 0.5 * out.qdd[iv] * h * h
                assert lo - 1e-6 <= pred <= hi + 1e-6
                active += bool(abs(pred - lo) < 1e-6 or abs(pred - hi) < 1e-6)
    assert active > 0 or ref_qp.n_loop  # closed loops: states on the loop manifold, the rows compared only


@pytest.mark.parametrize("name", ["mini_biped", "digit_like"])
def test_torsion_cone_rows_match_the_reference_and_hold(name):
    """With ``torsion_cone`` the C++ QP has the eight yaw rows of each stance sole's contact wrench cone after its
    eleven rows, the same as the numpy reference QP's (``contact_wrench_rows(..., torsion_cone=True)``); the
    solutions are equal and hold the cone (references that ask for a turn: some rows bind)."""
    params = dataclasses.replace(PARAMS, torsion_cone=True)
    wbc = make_controller(name, params)
    ref_qp = ReferenceWbcQp(wbc.model.spec, params)
    binding = 0
    for mode in ("double", "left"):
        n_c = sum(MODES[mode])
        for q, v, ref in cases((name, wbc, ref_qp), mode, seed=6):
            ref.torso_angacc = np.array([0.0, 0.0, 40.0])  # a yaw the stance feet must push for
            out = wbc.solve(q, v, ref)
            cpp = wbc.last_qp()
            py = reference_qp_data(wbc, ref_qp, q, v, ref)
            assert np.asarray(cpp["C"]).shape[0] == 19 * n_c + wbc.nu
            assert_same_qp_data(cpp, py, ("C", "l", "u"), 1e-11)
            if out.status != "solved":
                continue
            sol = ref_qp.solve(q, v, ref)
            if sol.found:
                np.testing.assert_allclose(out.wrenches, sol.wrenches, rtol=0,
                                           atol=1e-5 * max(1.0, float(np.max(np.abs(sol.wrenches)))))
            x = np.concatenate([out.qdd, *[out.wrenches[i] for i in range(2) if MODES[mode][i]]])  # tree models
            cone = np.asarray(cpp["C"])[[r for k in range(n_c) for r in range(19 * k + 11, 19 * k + 19)]]
            slack = cone @ x
            scale = max(1.0, float(np.max(np.abs(out.wrenches))))
            assert np.all(slack <= 1e-6 * scale), slack.max()
            binding += int(np.any(slack > -1e-6 * scale))
    assert binding > 0
