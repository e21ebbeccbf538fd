"""lipmpcc.control.reference_qp: the numpy whole-body QP (its parity with C++ is tests/control/test_wbc_parity.py).

Here: the contact rows (friction pyramid, CoP, torsion) on wrenches whose answer is known by hand and against
the four-corner linear program of the rectangle's contact wrench cone,
the dense solver on a QP solved by hand (with and without qpsolvers), and one QP of the small test
biped built and solved: its variables laid out as documented, its solution feasible and equal to
the C++ controller's.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from lipmpcc.control.reference_qp import INF, ReferenceWbcQp, contact_wrench_rows, solve_dense_qp
from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.control.wbc_types import WbcParams
from lipmpcc.robots import load_robot

DATA = Path(__file__).resolve().parent / "data"
MU, L, W = 0.8, 0.1, 0.04


def yaw(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_contact_rows_accept_a_wrench_inside_and_name_the_violated_bound() -> None:
    rows = contact_wrench_rows(np.eye(3), (0.0, 0.0), MU, L, W)
    assert rows.shape == (11, 6)
    fz = 400.0
    inside = np.array([0.5 * MU * fz, -0.5 * MU * fz, fz, 0.5 * W * fz, -0.5 * L * fz, 0.0])
    assert np.all(rows[:10] @ inside <= 0.0) and rows[10] @ inside == fz
    slip = inside.copy()
    slip[0] = 1.1 * MU * fz  # f_x beyond μ f_z: row 0 only
    assert np.flatnonzero(rows[:10] @ slip > 0).tolist() == [0]
    tip = inside.copy()
    tip[4] = -1.2 * L * fz  # CoP x = -τ_y / f_z = 1.2 L ahead of the centre: row 7 (−τ_y <= L f_z)
    assert np.flatnonzero(rows[:10] @ tip > 0).tolist() == [7]
    twist = inside.copy()
    twist[5] = -1.1 * MU * min(L, W) * fz
    assert np.flatnonzero(rows[:10] @ twist > 0).tolist() == [9]


def test_contact_rows_follow_the_sole_frame_and_its_centre() -> None:
    R = yaw(0.7)
    w_local = np.array([10.0, -20.0, 300.0, 1.0, 2.0, 0.5])
    w_world = np.concatenate([R @ w_local[:3], R @ w_local[3:]])
    np.testing.assert_allclose(contact_wrench_rows(R, (0.0, 0.0), MU, L, W) @ w_world,
                               contact_wrench_rows(np.eye(3), (0.0, 0.0), MU, L, W) @ w_local, atol=1e-12)
    # a CoP on the shifted centre of the rectangle is as good as a centred one is about the origin
    c = (0.03, -0.01)
    fz = 300.0
    at_centre = np.array([0.0, 0.0, fz, c[1] * fz, -c[0] * fz, 0.0])  # CoP = c: τ_x = c_y f_z, τ_y = -c_x f_z
    np.testing.assert_allclose(contact_wrench_rows(np.eye(3), c, MU, L, W)[4:8] @ at_centre,
                               [-W * fz, -W * fz, -L * fz, -L * fz], atol=1e-12)


def _corner_pyramids_carry(f: np.ndarray, tau_c: np.ndarray) -> bool:
    """Whether four corner forces of the 2L x 2W rectangle, each in its friction pyramid (μ = MU), sum to the
    sole-frame force ``f`` and the moments ``tau_c`` about the rectangle's centre (a linear program)."""
    from scipy.optimize import linprog

    corners = [(sx * L, sy * W) for sx in (1.0, -1.0) for sy in (1.0, -1.0)]
    A_eq = np.zeros((6, 12))
    for i, (x, y) in enumerate(corners):
        A_eq[0:3, 3 * i:3 * i + 3] = np.eye(3)
        A_eq[3:6, 3 * i:3 * i + 3] = [[0.0, 0.0, y], [0.0, 0.0, -x], [-y, x, 0.0]]  # (x, y, 0) x f_i
    A_ub = np.zeros((16, 12))
    for i in range(4):
        for k, (axis, sign) in enumerate(((0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0))):
            A_ub[4 * i + k, 3 * i + axis] = sign
            A_ub[4 * i + k, 3 * i + 2] = -MU
    res = linprog(np.zeros(12), A_ub=A_ub, b_ub=np.zeros(16), A_eq=A_eq, b_eq=np.concatenate([f, tau_c]),
                  bounds=[(None, None)] * 12, method="highs")
    return res.status == 0


def test_contact_rows_are_the_rectangles_contact_wrench_cone() -> None:
    """Rows 0–7 and 11–18 hold exactly when four corner friction pyramids can carry the wrench (Caron et al.
    2015): the yaw moment shrinks with the CoP's distance to the edges and with the tangential force; the sole
    frame rotated and the rectangle's centre off the sole origin, as in C++."""
    pytest.importorskip("scipy")
    rng = np.random.default_rng(3)
    R, c = yaw(-0.4), np.array([0.02, -0.005, 0.0])
    cone_rows = np.r_[0:8, 11:19]
    rows = contact_wrench_rows(R, c[:2], MU, L, W, torsion_cone=True)[cone_rows]
    seen = {True: 0, False: 0}
    for _ in range(300):
        fz = 300.0
        f = np.array([rng.uniform(-0.6, 0.6) * MU * fz, rng.uniform(-0.6, 0.6) * MU * fz, fz])
        tau_c = np.array([rng.uniform(-1, 1) * W * fz, rng.uniform(-1, 1) * L * fz,
                          rng.uniform(-1, 1) * MU * (L + W) * fz])
        tau_o = tau_c + np.cross(c, f)  # about the sole origin
        margin = float(np.max(rows @ np.concatenate([R @ f, R @ tau_o])))
        if abs(margin) < 1e-6 * fz:
            continue
        assert _corner_pyramids_carry(f, tau_c) == (margin < 0.0), (f, tau_c, margin)
        seen[margin < 0.0] += 1
    assert min(seen.values()) > 30, seen  # both sides sampled
    # the CoP at a corner of the rectangle: no yaw moment, however small; at the centre: μ (L + W) f_z
    at_corner = np.array([0.0, 0.0, 300.0, W * 300.0, -L * 300.0, 0.0])
    local = contact_wrench_rows(np.eye(3), (0.0, 0.0), MU, L, W, torsion_cone=True)
    assert local.shape == (19, 6) and np.array_equal(local[:11], contact_wrench_rows(np.eye(3), (0.0, 0.0), MU, L, W))
    assert np.all(local[11:] @ at_corner <= 1e-9)
    assert np.any(local[11:] @ (at_corner + [0, 0, 0, 0, 0, 1e-3]) > 0.0)
    centred = np.array([0.0, 0.0, 300.0, 0.0, 0.0, 0.99 * MU * (L + W) * 300.0])
    assert np.all(local[11:] @ centred < 0.0) and np.any(local[11:] @ (centred * [1, 1, 1, 1, 1, 1.02]) > 0.0)


def _tiny_qp() -> dict:
    """min ½‖x‖² − x₀ − x₁ with x₀ + x₁ <= 1, x₀ − x₁ = 0.2: x = (0.6, 0.4)."""
    return dict(H=np.eye(2), g=np.array([-1.0, -1.0]), A=np.array([[1.0, -1.0]]), b=np.array([0.2]),
                C=np.array([[1.0, 1.0]]), l=np.array([-INF]), u=np.array([1.0]))


def test_dense_solve_of_a_qp_solved_by_hand(monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("qpsolvers")
    np.testing.assert_allclose(solve_dense_qp(_tiny_qp()), [0.6, 0.4], atol=1e-8)
    monkeypatch.setitem(sys.modules, "qpsolvers", None)  # not installed: proxsuite's dense solver
    np.testing.assert_allclose(solve_dense_qp(_tiny_qp()), [0.6, 0.4], atol=1e-8)


@pytest.fixture(scope="module")
def mini():
    robot = load_robot(DATA / "mini_biped.xml", arm_joints=("left_shoulder_pitch", "right_shoulder_pitch"),
                       foot_length=0.2, foot_width=0.1)
    params = WbcParams(qp_eps_abs=1e-10)
    wbc = WholeBodyController(robot, params)
    return wbc, ReferenceWbcQp(wbc.model.spec, params)


@pytest.mark.parametrize("contact", [(True, True), (True, False)])
def test_one_qp_of_the_mini_biped(mini, contact) -> None:
    wbc, ref_qp = mini
    q = pin.neutral(ref_qp.model)  # joints at 0, base 1 m up
    q[2] += 1.0
    v = np.zeros(ref_qp.nv)
    ref = wbc.hold_reference(q, contact)
    ref.com_pos = ref.com_pos + np.array([0.02, -0.01, 0.0])
    if not contact[1]:
        ref.foot_pos[1] = ref.foot_pos[1] + np.array([0.0, 0.0, 0.05])
    qp = ref_qp.build(q, v, ref)
    n_c = sum(contact)
    assert qp["H"].shape == (ref_qp.nv + 6 * n_c,) * 2
    assert qp["C"].shape[0] == 11 * n_c + wbc.nu
    assert qp["offsets"] == [ref_qp.nv if contact[0] else -1, ref_qp.nv + 6 if contact[0] and contact[1] else -1]
    sol = ref_qp.solve(q, v, ref)
    assert sol.found
    x = sol.x
    np.testing.assert_allclose(qp["A"] @ x, qp["b"], atol=1e-7)
    Cx = qp["C"] @ x
    assert np.all(Cx >= qp["l"] - 1e-7) and np.all(Cx <= qp["u"] + 1e-7)
    assert np.all(sol.wrenches[~np.array(contact)] == 0.0)
    out = wbc.solve(q, v, ref)
    assert out.status == "solved"
    for got, want in ((out.qdd, sol.qdd), (out.wrenches, sol.wrenches), (out.tau, sol.tau)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * max(1.0, float(np.max(np.abs(want)))))
