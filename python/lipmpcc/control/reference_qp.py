"""The whole-body QP written out in numpy: a slow, readable reference of the C++ controller.

:class:`~lipmpcc.control.wbc.WholeBodyController` assembles and solves its QP in C++ (``lipmpcc._wbc``).
:class:`ReferenceWbcQp` rebuilds, from the same model specification, the QP that the C++ core (``cpp/wbc``) assembles,
by a different route:

- dynamics terms from separate Pinocchio calls (``crba``, ``nonLinearEffects``,
  ``computeJointJacobians`` + ``getFrameJacobian``, ``forwardKinematics(q, v, 0)`` +
  ``getFrameClassicalAcceleration``, ``centerOfMass(q, v, 0)``, ``jacobianCenterOfMass``,
  ``computeCentroidalMapTimeVariation``) instead of the single ``computeAllTerms`` pass;
- closed loops from ``buildModelAndConstraintsFromMJCF``'s point-anchor constraint models
  (their own Jacobian, ``calc`` + ``jacobian``, rotated to world axes) instead of frames at the
  anchors; the loop drift from the anchors' classical accelerations;
- the actuation pseudo-inverse from ``numpy.linalg.pinv`` and the unactuated rows from the zero
  rows of B;
- the *textbook* closed-loop QP: all nv accelerations, the loop rows (and the rigid-spring rows) as
  equalities and their forces λ as QP variables (the C++ ``multipliers`` formulation); the C++
  default eliminates the loop-dependent accelerations, a different QP with the same optimum. The
  eliminated QP is also rebuilt here (:meth:`ReferenceWbcQp.build_reduced`, from the C++ model's
  choice of dependent coordinates) so that its matrices can be compared too;
- the QP solved by qpsolvers ("proxqp", cold start, one-sided ``G x <= h`` form) instead of the
  warm-started C++ proxsuite object.

Variables, rows and their order follow the C++ QP (``cpp/wbc/include/lipmpcc/wbc/qp.hpp``), so that
the matrices can be compared entry by entry with :meth:`WholeBodyController.last_qp
<lipmpcc.control.wbc.WholeBodyController.last_qp>`, and the solutions too. The parity tests
(``tests/control/test_wbc_parity.py``) and notebook 08 do so. Each contact's eleven inequality rows (nineteen with ``WbcParams.torsion_cone``)
are :func:`contact_wrench_rows`.

Example::

    from lipmpcc.control.reference_qp import ReferenceWbcQp
    from lipmpcc.control.wbc import WholeBodyController

    wbc = WholeBodyController("digit_like")
    ref_qp = ReferenceWbcQp(wbc.model.spec, wbc.params)
    qp = ref_qp.build(q, v, ref)            # H, g, A, b, C, l, u as numpy arrays
    sol = ref_qp.solve(q, v, ref)           # q̈, wrenches, efforts of the cold reference solve

It needs ``pinocchio`` (a dependency); the solve uses ``qpsolvers`` when it is installed (the
``test`` extra) and proxsuite's dense solver otherwise. Units: SI throughout ([m], [s], [rad], [N],
[N m]).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from ..exceptions import RobotDescriptionError
from .wbc_types import WbcParams, WbcReference

__all__ = ["ReferenceWbcQp", "ReferenceSolution", "solve_dense_qp", "split_solution", "contact_wrench_rows", "INF",
           "CONTACT_ROWS", "TORSION_CONE_ROWS"]

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
#: the QP's "no bound" (proxsuite's convention): bounds beyond ±INF/2 are absent
INF = 1e20
#: inequality rows per stance foot (:func:`contact_wrench_rows`; C++ ``kRowsPerContactInequality``)
CONTACT_ROWS = 11
#: more rows per stance foot with ``WbcParams.torsion_cone`` (C++ ``kTorsionConeRows``)
TORSION_CONE_ROWS = 8
ELIMINATE = "eliminate"
MULTIPLIERS = "multipliers"


def solve_dense_qp(qp: dict[str, Any], eps: float = 1e-10) -> np.ndarray | None:
    """Cold solve of a QP in the proxsuite form of :meth:`ReferenceWbcQp.build`; None if not solved.

    ``qp`` holds ``H, g`` (cost ``½ xᵀHx + gᵀx``), ``A, b`` (``A x = b``) and ``C, l, u``
    (``l <= C x <= u``, bounds beyond ±:data:`INF`/2 absent); ``eps`` is the absolute tolerance.
    qpsolvers' proxqp first, when qpsolvers is installed (one-sided ``G x <= h`` form). Closed-loop
    QPs are badly scaled (rod inertias ~1e-6 next to a 48 kg base) and trip proxsuite's
    infeasibility certificate at its default threshold: those (and every QP without qpsolvers) go to
    a proxsuite dense QP whose certificates are off (1e-14), as the C++ solver does.
    """
    C, lo, up = qp["C"], qp["l"], qp["u"]
    upper = up < INF / 2
    lower = lo > -INF / 2
    G = np.vstack([C[upper], -C[lower]])
    h = np.concatenate([up[upper], -lo[lower]])
    try:
        import qpsolvers
    except ImportError:  # not a dependency of the package (the test extra installs it)
        qpsolvers = None
    if qpsolvers is not None:
        x = qpsolvers.solve_qp(qp["H"], qp["g"], G, h, qp["A"], qp["b"], solver="proxqp",
                               eps_abs=eps, eps_rel=0.0, max_iter=100000)
        if x is not None:
            return np.asarray(x)
    import proxsuite

    n, n_eq = qp["H"].shape[0], qp["A"].shape[0]
    solver = proxsuite.proxqp.dense.QP(n, n_eq, G.shape[0])
    s = solver.settings
    s.eps_abs, s.eps_rel, s.max_iter, s.max_iter_in = eps, 0.0, 20000, 200
    s.eps_primal_inf, s.eps_dual_inf = 1e-14, 1e-14
    solver.init(qp["H"], qp["g"], qp["A"], qp["b"], G, np.full(G.shape[0], -1e20), h)
    solver.solve()
    if solver.results.info.status != proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED:
        return None
    return np.array(solver.results.x)


def split_solution(qp: dict[str, Any], x: np.ndarray, nv: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A solution ``x`` of the QP ``qp`` (:meth:`ReferenceWbcQp.build`) split into the sole wrenches (2, 6)
    [N, N m] (zero for a foot out of contact), the generalised force the actuators, loops and springs must
    supply, M q̈ + h − Σ J_soleᵀ w − J_extraᵀ λ (nv,) [N, N m], and the extra multipliers λ (loop forces and
    rigid springs)."""
    t = qp["terms"]
    wrenches = np.zeros((2, 6))
    gen = t["M"] @ x[:nv] + t["h"]
    for i, o in enumerate(qp["offsets"]):
        if o >= 0:
            wrenches[i] = x[o:o + 6]
            gen -= t["J_sole"][i].T @ wrenches[i]
    lam = x[qp["extra_offset"]:qp["extra_offset"] + qp["n_extra"]]
    gen -= t["J_extra"].T @ lam
    return wrenches, gen, lam


def contact_wrench_rows(R_sole: np.ndarray, center: np.ndarray, mu: float, half_length: float,
                        half_width: float, torsion_cone: bool = False) -> np.ndarray:
    """The inequality rows (11, 6), or (19, 6) with ``torsion_cone``, of one contact on its wrench ``w = [f; τ]``
    (world axes, at the sole frame): ``rows @ w <= 0`` for all but row 10, ``rows[10] @ w = f_z`` (bounded below
    by the minimum normal force and above by the load bound).

    In the sole frame (``f_s = R_soleᵀ f``, ``τ_s = R_soleᵀ τ``, moments taken about the centre ``c``
    of the sole rectangle, ``center`` = (c_x, c_y) [m] in the sole frame):

    - rows 0–3, friction pyramid: ``±f_x − μ f_z <= 0``, ``±f_y − μ f_z <= 0``;
    - rows 4–7, centre of pressure in the rectangle: ``±τ_x − W f_z <= 0``, ``±τ_y − L f_z <= 0``
      (``half_width`` W, ``half_length`` L [m], already shrunk by the safety factor);
    - rows 8–9, torsion: ``±τ_z − μ min(L, W) f_z <= 0``;
    - row 10: ``f_z``;
    - with ``torsion_cone`` (``WbcParams.torsion_cone``), rows 11–18, the yaw rows of the rectangle's contact
      wrench cone (Caron, Pham, Nakamura 2015, "Stability of surface contacts for humanoid robots", a friction
      pyramid at each corner): for s_z, s₁, s₂ = ±1, ``s_z τ_z + s₁ (W f_x + s_z μ τ_x) + s₂ (L f_y + s_z μ τ_y)
      − μ (L + W) f_z <= 0``: the yaw moment the sole can carry shrinks with the CoP's distance to the
      rectangle's edges and with the tangential force, to none at a corner. With rows 0–7 they are the cone
      exactly (``tests/control/test_reference_qp.py`` checks it against the corners' linear program).

    Args:
        R_sole: the sole frame's rotation (3, 3) (columns: its axes in the world).
        center: (c_x, c_y) [m], the sole rectangle's centre in the sole frame.
        mu: friction coefficient [-].
        half_length, half_width: half-extents of the allowed CoP rectangle [m].
        torsion_cone: append rows 11–18.
    """
    R = np.asarray(R_sole, dtype=float)
    L = np.zeros((6, 6))
    L[:3, :3] = R.T
    L[3:, 3:] = R.T
    fx, fy, fz, tx, ty, tz = L
    cx, cy = (float(c) for c in center)
    tx, ty, tz = tx - cy * fz, ty + cx * fz, tz - cx * fy + cy * fx
    mu_t = mu * min(half_length, half_width)
    rows = [fx - mu * fz, -fx - mu * fz, fy - mu * fz, -fy - mu * fz,
            tx - half_width * fz, -tx - half_width * fz, ty - half_length * fz, -ty - half_length * fz,
            tz - mu_t * fz, -tz - mu_t * fz, fz]
    if not torsion_cone:
        return np.array(rows)
    cone = mu * (half_length + half_width) * fz
    for sz in (1.0, -1.0):  # the torsion rows of the rectangle's contact wrench cone (Caron et al. 2015)
        for s1 in (1.0, -1.0):
            for s2 in (1.0, -1.0):
                rows.append(sz * tz + s1 * (half_width * fx + sz * mu * tx) + s2 * (half_length * fy + sz * mu * ty)
                            - cone)
    return np.array(rows)


@dataclass
class ReferenceSolution:
    """Solution of the reference QP (:meth:`ReferenceWbcQp.solve`; NaN everywhere when not found).

    Attributes:
        found: the solver solved the QP.
        x: the QP's variables [q̈; wrenches of the feet in contact; multipliers].
        qdd: (nv,) accelerations.
        wrenches: (2, 6) ``[f (N); τ (N m)]`` at each sole, world axes; zeros for a swing foot.
        tau: (nu,) actuator efforts.
        loop_forces: (3 per loop,) [N].
        spring_torques: (n_springs,) [N m].
        qp: the QP (:meth:`ReferenceWbcQp.build`), with its ``terms``.
    """

    found: bool
    x: np.ndarray
    qdd: np.ndarray
    wrenches: np.ndarray
    tau: np.ndarray
    loop_forces: np.ndarray
    spring_torques: np.ndarray
    qp: dict[str, Any]


class ReferenceWbcQp:
    """The whole-body QP built with numpy.

    Args:
        spec: the C++ ``WbcModelSpec`` (``controller.model.spec``): file, frames, actuators, arms,
            springs, damping, friction, gravity, sole size and centres, loop and spring models.
        params: the :class:`~lipmpcc.control.wbc_types.WbcParams` of the controller under test.
    """

    def __init__(self, spec: Any, params: WbcParams) -> None:
        self.params = params
        self.model, cmodels, _ = pin.buildModelAndConstraintsFromMJCF(spec.mjcf_path)
        m = self.model
        root = m.frames[m.getFrameId(spec.torso_body, pin.FrameType.BODY)].parentJoint
        if root == 0:  # no joint on the root body: Pinocchio adds the free-flyer
            self.model, cmodels, _ = pin.buildModelAndConstraintsFromMJCF(spec.mjcf_path, pin.JointModelFreeFlyer())
            m = self.model
            root = 1
        if m.joints[root].shortname() not in ("JointModelFreeFlyer", "JointModelComposite"):
            raise RobotDescriptionError(spec.mjcf_path, [f"a free joint or 3 slides + a ball joint as the base (found "
                                                         f"{m.joints[root].shortname()})"])
        self.base_quat = m.joints[root].idx_q + 3
        self.base_v = m.joints[root].idx_v
        if len(spec.gravity):
            m.gravity = pin.Motion(np.asarray(spec.gravity, dtype=float), np.zeros(3))
        self.sole_frames = []
        for side, (site, body, offset) in enumerate(zip(spec.sole_sites, spec.foot_bodies, spec.sole_offsets)):
            if site:
                self.sole_frames.append(m.getFrameId(site))
            else:
                bid = m.getFrameId(body, pin.FrameType.BODY)
                bf = m.frames[bid]
                placement = bf.placement * pin.SE3(np.eye(3), np.asarray(offset))
                name = f"ref_sole_{side}"
                frame = pin.Frame(name, bf.parentJoint, bid, placement, pin.FrameType.OP_FRAME)
                self.sole_frames.append(m.addFrame(frame, False))
        self.sole_centers = [np.asarray(c, dtype=float) for c in spec.sole_cop_centers]
        self.torso_frame = m.getFrameId(spec.torso_body, pin.FrameType.BODY)
        self.nv = m.nv
        nu = len(spec.actuated_joints)
        self.B = np.zeros((m.nv, nu))
        for k, jn in enumerate(spec.actuated_joints):
            self.B[m.joints[m.getJointId(jn)].idx_v, k] += spec.actuation_gains[k]
        self.B_pinv = np.linalg.pinv(self.B)
        zero_rows = [i for i in range(m.nv) if not np.any(self.B[i])]
        self.NT = np.eye(m.nv)[zero_rows]
        self.u_min = np.asarray(spec.u_min, dtype=float)
        self.u_max = np.asarray(spec.u_max, dtype=float)
        self.arm_q = [m.joints[m.getJointId(j)].idx_q for j in spec.arm_joints]
        self.arm_v = [m.joints[m.getJointId(j)].idx_v for j in spec.arm_joints]
        self.limits = []  # (idx_q, idx_v, lower, upper) of the range-limited actuated joints, as the C++ model
        for jn in spec.actuated_joints:
            joint = m.joints[m.getJointId(jn)]
            lo, hi = float(m.lowerPositionLimit[joint.idx_q]), float(m.upperPositionLimit[joint.idx_q])
            if np.isfinite(lo) and np.isfinite(hi) and abs(lo) < 1e10 and abs(hi) < 1e10 and lo < hi and \
                    all(lim[0] != joint.idx_q for lim in self.limits):
                self.limits.append((joint.idx_q, joint.idx_v, lo, hi))
        rigid_model = str(spec.spring_model).endswith("rigid")
        self.springs = []  # (idx_q, idx_v, stiffness, reference, rigid)
        for j, k, r in zip(spec.spring_joints, spec.spring_stiffness, spec.spring_reference):
            joint = m.joints[m.getJointId(j)]
            rigid = rigid_model and not np.any(self.B[joint.idx_v])
            self.springs.append((joint.idx_q, joint.idx_v, float(k), float(r), rigid))
        self.damping = np.asarray(spec.damping, dtype=float) if len(spec.damping) else np.array(m.damping)
        self.frictionloss = np.asarray(spec.frictionloss, dtype=float) if len(spec.frictionloss) else np.zeros(m.nv)
        self.mu = float(spec.friction)
        self.half_length = float(spec.foot_half_length)
        self.half_width = float(spec.foot_half_width)
        # loops: Pinocchio's constraint models for J, frames at the anchors for the drift
        self.cmodels = list(cmodels)
        self.cdatas = [c.createData() for c in self.cmodels]
        self.anchor_frames = []
        for k, c in enumerate(self.cmodels):
            f1 = m.addFrame(pin.Frame(f"ref_anchor1_{k}", c.joint1_id, 0, c.joint1_placement, pin.FrameType.OP_FRAME), False)
            f2 = m.addFrame(pin.Frame(f"ref_anchor2_{k}", c.joint2_id, 0, c.joint2_placement, pin.FrameType.OP_FRAME), False)
            self.anchor_frames.append((f1, f2))
        self.n_loop = 3 * len(self.cmodels)
        self.n_rigid = sum(s[4] for s in self.springs)
        self.n_extra = self.n_loop + self.n_rigid
        self.formulation = MULTIPLIERS if str(spec.loop_formulation).endswith("multipliers") else ELIMINATE

    # ---- dynamics terms ------------------------------------------------------------------
    def terms(self, q: np.ndarray, v: np.ndarray) -> dict[str, Any]:
        """The dynamics terms at Pinocchio's (q, v), each from its own Pinocchio call: ``M``, ``h`` (bias,
        damping, friction compensation and spring forces), per sole ``J_sole``, ``drift_sole`` (J̇v),
        ``vel_sole``, ``p_sole``, ``R_sole``; the torso's ``J_torso``, ``drift_torso``, ``w_torso``,
        ``R_torso``; ``com``, ``vcom``, ``drift_com``, ``J_com``; the centroidal ``A_ang``, ``drift_k``,
        ``k_com``; the holonomic rows ``J_extra``, ``gamma_extra``, ``loop_residual``; and ``q``
        (its quaternion normalised)."""
        m = self.model
        p = self.params
        q = q.copy()
        i = self.base_quat
        q[i:i + 4] /= np.linalg.norm(q[i:i + 4])
        zero = np.zeros(m.nv)
        t: dict[str, Any] = {}

        d = m.createData()
        M = pin.crba(m, d, q)
        t["M"] = np.triu(M) + np.triu(M, 1).T
        h = pin.nonLinearEffects(m, d, q, v).copy() + self.damping * v
        h += self.frictionloss * np.tanh(v / p.friction_compensation_velocity)
        for iq, iv, k, r, _ in self.springs:
            h[iv] += k * (q[iq] - r)
        t["h"] = h

        d = m.createData()
        pin.computeJointJacobians(m, d, q)
        pin.forwardKinematics(m, d, q, v, zero)
        pin.updateFramePlacements(m, d)
        t["J_sole"] = [pin.getFrameJacobian(m, d, f, LWA) for f in self.sole_frames]
        t["drift_sole"] = [pin.getFrameClassicalAcceleration(m, d, f, LWA).vector for f in self.sole_frames]
        t["vel_sole"] = [pin.getFrameVelocity(m, d, f, LWA).vector for f in self.sole_frames]
        t["p_sole"] = [d.oMf[f].translation.copy() for f in self.sole_frames]
        t["R_sole"] = [d.oMf[f].rotation.copy() for f in self.sole_frames]
        tf = self.torso_frame
        t["J_torso"] = pin.getFrameJacobian(m, d, tf, LWA)[3:]
        t["drift_torso"] = pin.getFrameClassicalAcceleration(m, d, tf, LWA).angular
        t["w_torso"] = pin.getFrameVelocity(m, d, tf, LWA).angular
        t["R_torso"] = d.oMf[tf].rotation.copy()

        # holonomic rows: loops (Pinocchio's constraint Jacobian is R_c1^T (J_2 - J_1): rotate it
        # to world axes, anchor 1 minus anchor 2), then the rigid springs
        J_e = np.zeros((self.n_extra, m.nv))
        gamma = np.zeros(self.n_extra)
        residual = np.zeros(self.n_loop)
        for k, (c, cd, (f1, f2)) in enumerate(zip(self.cmodels, self.cdatas, self.anchor_frames)):
            c.calc(m, d, cd)
            J_e[3 * k:3 * k + 3] = -cd.oMc1.rotation @ c.jacobian(m, d, cd)
            gamma[3 * k:3 * k + 3] = (pin.getFrameClassicalAcceleration(m, d, f1, LWA).linear
                                      - pin.getFrameClassicalAcceleration(m, d, f2, LWA).linear)
            residual[3 * k:3 * k + 3] = d.oMf[f1].translation - d.oMf[f2].translation
        row = self.n_loop
        for _, iv, _, _, rigid in self.springs:
            if rigid:
                J_e[row, iv] = 1.0
                gamma[row] = p.spring_damping_gain * v[iv]
                row += 1
        t["J_extra"], t["gamma_extra"], t["loop_residual"] = J_e, gamma, residual

        d = m.createData()
        pin.centerOfMass(m, d, q, v, zero)
        t["com"], t["vcom"], t["drift_com"] = d.com[0].copy(), d.vcom[0].copy(), d.acom[0].copy()
        t["J_com"] = pin.jacobianCenterOfMass(m, m.createData(), q)

        d = m.createData()
        pin.computeCentroidalMapTimeVariation(m, d, q, v)
        t["A_ang"] = d.Ag[3:].copy()
        t["drift_k"] = d.dAg[3:] @ v
        t["k_com"] = t["A_ang"] @ v
        t["q"] = q
        return t

    # ---- QP ---------------------------------------------------------------------------------
    def build(self, q: np.ndarray, v: np.ndarray, ref: WbcReference) -> dict[str, Any]:
        """The textbook QP: all accelerations, holonomic rows as equalities with multipliers."""
        t = self.terms(q, v)
        coords = dict(nv=self.nv, NT=self.NT, Bp=self.B_pinv, arm=self.arm_v, limit=[lim[1] for lim in self.limits])
        qp = self._assemble(t, t["q"], v, ref, coords, t["J_extra"], t["gamma_extra"], metric=None)
        qp["terms"] = t
        return qp

    def build_reduced(self, q: np.ndarray, v: np.ndarray, ref: WbcReference, dependent: list[int]) -> dict[str, Any]:
        """The QP in the independent accelerations (C++ default for closed loops): qdd = Z a + z0 with
        qdd[dependent] solved from the holonomic rows."""
        t = self.terms(q, v)
        dep = list(dependent)
        ind = [i for i in range(self.nv) if i not in set(dep)]
        Je, gamma = t["J_extra"], t["gamma_extra"]
        G = -np.linalg.solve(Je[:, dep], Je[:, ind])
        g0 = -np.linalg.solve(Je[:, dep], gamma)
        Z = np.zeros((self.nv, len(ind)))
        Z[ind] = np.eye(len(ind))
        Z[dep] = G
        z0 = np.zeros(self.nv)
        z0[dep] = g0
        r = dict(t)
        r["M"] = Z.T @ t["M"] @ Z
        r["h"] = Z.T @ (t["h"] + t["M"] @ z0)
        r["J_sole"] = [J @ Z for J in t["J_sole"]]
        r["drift_sole"] = [dr + J @ z0 for J, dr in zip(t["J_sole"], t["drift_sole"])]
        for key in ("com", "torso", "k"):
            jkey = {"com": "J_com", "torso": "J_torso", "k": "A_ang"}[key]
            r[jkey] = t[jkey] @ Z
            r[f"drift_{key}"] = t[f"drift_{key}"] + t[jkey] @ z0
        B_r = self.B[ind]
        zero_rows = [i for i in range(len(ind)) if not np.any(B_r[i])]
        coords = dict(nv=len(ind), NT=np.eye(len(ind))[zero_rows], Bp=np.linalg.pinv(B_r),
                      arm=[ind.index(i) for i in self.arm_v], limit=[ind.index(lim[1]) for lim in self.limits])
        qp = self._assemble(r, t["q"], v, ref, coords, np.zeros((0, len(ind))), np.zeros(0),
                            metric=(Z.T @ Z, Z.T @ z0))
        qp.update(terms=t, reduced_terms=r, Z=Z, z0=z0)
        return qp

    def _assemble(self, t: dict[str, Any], q: np.ndarray, v: np.ndarray, ref: WbcReference, coords: dict[str, Any],
                  J_e: np.ndarray, gamma_e: np.ndarray, metric: tuple[np.ndarray, np.ndarray] | None) -> dict[str, Any]:
        """The QP's matrices from the terms ``t``: the variables are the accelerations (``coords["nv"]``),
        a wrench per foot in contact, then one multiplier per holonomic row ``J_e``."""
        nv = coords["nv"]
        ne = J_e.shape[0]
        contact = [bool(c) for c in ref.contact]
        offsets, o = [], nv
        for c in contact:
            offsets.append(o if c else -1)
            o += 6 if c else 0
        extra_offset = o
        n = o + ne
        layout = dict(nv=nv, n=n, contact=contact, offsets=offsets, extra_offset=extra_offset)
        H, g = self._cost(t, q, v, ref, coords, layout, metric)
        A, b = self._equalities(t, coords, layout, J_e, gamma_e)
        C, lo, up = self._inequalities(t, ref, coords, layout, J_e)
        if self.params.joint_limit_horizon > 0.0 and self.limits:
            C, lo, up = self._limit_rows(q, v, coords, C, lo, up)
        return dict(H=H, g=g, A=A, b=b, C=C, l=lo, u=up, offsets=offsets, extra_offset=extra_offset, n_extra=ne)

    def _cost(self, t: dict[str, Any], q: np.ndarray, v: np.ndarray, ref: WbcReference, coords: dict[str, Any],
              layout: dict[str, Any], metric: tuple[np.ndarray, np.ndarray] | None) -> tuple[np.ndarray, np.ndarray]:
        """(H, g): the weighted task errors ``Σ ‖J q̈ + J̇v − a*‖²_W`` (COM, torso, swing foot, arm posture,
        angular momentum) and the regularisation."""
        p = self.params
        nv, n, contact, extra_offset = layout["nv"], layout["n"], layout["contact"], layout["extra_offset"]
        H = np.zeros((n, n))
        g = np.zeros(n)

        def task(J: np.ndarray, drift: np.ndarray, target: np.ndarray, w: Any) -> None:
            W = np.diag(np.broadcast_to(np.asarray(w, dtype=float), (J.shape[0],)))
            H[:nv, :nv] += J.T @ W @ J
            g[:nv] += J.T @ W @ (drift - target)

        def pd(gains: Any, acc: Any, e: np.ndarray, ev: np.ndarray) -> np.ndarray:
            return np.asarray(acc) + np.asarray(gains.kp) * e + np.asarray(gains.kd) * ev

        task(t["J_com"], t["drift_com"],
             pd(p.com, ref.com_acc, ref.com_pos - t["com"], ref.com_vel - t["vcom"]), p.com.weight)
        e_rot = pin.log3(np.asarray(ref.torso_rot) @ t["R_torso"].T)
        task(t["J_torso"], t["drift_torso"],
             pd(p.torso, ref.torso_angacc, e_rot, np.asarray(ref.torso_angvel) - t["w_torso"]), p.torso.weight)
        for i in range(2):
            if contact[i]:
                continue
            J, dr, vel = t["J_sole"][i], t["drift_sole"][i], t["vel_sole"][i]
            fp, fv, fa = (np.asarray(x)[i] for x in (ref.foot_pos, ref.foot_vel, ref.foot_acc))
            task(J[:3], dr[:3], pd(p.swing_position, fa, fp - t["p_sole"][i], fv - vel[:3]), p.swing_position.weight)
            fr, fw, fdw = (np.asarray(x)[i] for x in (ref.foot_rot, ref.foot_angvel, ref.foot_angacc))
            e = pin.log3(fr @ t["R_sole"][i].T)
            task(J[3:], dr[3:], pd(p.swing_orientation, fdw, e, fw - vel[3:]), p.swing_orientation.weight)
        a = p.arm_posture
        for k, (iq, iv, ix) in enumerate(zip(self.arm_q, self.arm_v, coords["arm"])):
            target = a.kp * (ref.arm_posture[k] - q[iq]) - a.kd * v[iv]
            H[ix, ix] += a.weight
            g[ix] -= a.weight * target
        if p.angular_momentum_weight > 0:
            task(t["A_ang"], t["drift_k"], -p.angular_momentum_kd * t["k_com"], p.angular_momentum_weight)
        if metric is None:
            H[np.arange(nv), np.arange(nv)] += p.qdd_regularization
        else:
            H[:nv, :nv] += p.qdd_regularization * metric[0]
            g[:nv] += p.qdd_regularization * metric[1]
        H[np.arange(nv, extra_offset), np.arange(nv, extra_offset)] += p.force_regularization  # not on λ
        return H, g

    def _equalities(self, t: dict[str, Any], coords: dict[str, Any], layout: dict[str, Any], J_e: np.ndarray,
                    gamma_e: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(A, b): the unactuated rows of the dynamics, no slip of each stance sole, the holonomic rows."""
        p = self.params
        nv, n, contact, offsets, extra_offset = (layout[k] for k in ("nv", "n", "contact", "offsets", "extra_offset"))
        ne = J_e.shape[0]
        nc = sum(contact)
        NT = coords["NT"]
        nun = NT.shape[0]
        A = np.zeros((nun + 6 * nc + ne, n))
        b = np.zeros(nun + 6 * nc + ne)
        A[:nun, :nv] = NT @ t["M"]
        b[:nun] = -NT @ t["h"]
        row = nun
        for i in range(2):
            if not contact[i]:
                continue
            A[:nun, offsets[i]:offsets[i] + 6] = -NT @ t["J_sole"][i].T
            A[row:row + 6, :nv] = t["J_sole"][i]
            b[row:row + 6] = -t["drift_sole"][i] - p.contact_velocity_gain * t["vel_sole"][i]
            row += 6
        if ne:
            A[:nun, extra_offset:] = -NT @ J_e.T
            A[row:, :nv] = J_e
            b[row:] = -gamma_e
        return A, b

    def _inequalities(self, t: dict[str, Any], ref: WbcReference, coords: dict[str, Any], layout: dict[str, Any],
                      J_e: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(C, l, u): each contact's :func:`contact_wrench_rows` with the normal-force bounds, then the
        motor bounds ``u_min <= B⁺(M q̈ + h − J_cᵀ w − J_eᵀ λ) <= u_max``."""
        p = self.params
        nv, n, contact, offsets, extra_offset = (layout[k] for k in ("nv", "n", "contact", "offsets", "extra_offset"))
        nc = sum(contact)
        Bp = coords["Bp"]
        nu = Bp.shape[0]
        n_rows = CONTACT_ROWS + (TORSION_CONE_ROWS if p.torsion_cone else 0)
        C = np.zeros((n_rows * nc + nu, n))
        lo = np.zeros(n_rows * nc + nu)
        up = np.zeros(n_rows * nc + nu)
        sL = p.cop_safety_factor * self.half_length
        sW = p.cop_safety_factor * self.half_width
        row = 0
        for i in range(2):
            if not contact[i]:
                continue
            C[row:row + n_rows, offsets[i]:offsets[i] + 6] = contact_wrench_rows(
                t["R_sole"][i], self.sole_centers[i], self.mu, sL, sW, p.torsion_cone)
            lo[row:row + n_rows] = -INF
            up[row:row + n_rows] = 0.0
            lo[row + 10] = p.min_normal_force
            fmax = float(np.asarray(ref.max_normal_force, dtype=float)[i])
            up[row + 10] = fmax if np.isfinite(fmax) else INF
            row += n_rows
        C[row:, :nv] = Bp @ t["M"]
        for i in range(2):
            if contact[i]:
                C[row:, offsets[i]:offsets[i] + 6] = -Bp @ t["J_sole"][i].T
        if J_e.shape[0]:
            C[row:, extra_offset:] = -Bp @ J_e.T
        Bh = Bp @ t["h"]
        lo[row:] = np.maximum(self.u_min - Bh, -INF)
        up[row:] = np.minimum(self.u_max - Bh, INF)
        return C, lo, up

    def _limit_rows(self, q: np.ndarray, v: np.ndarray, coords: dict[str, Any], C: np.ndarray, lo: np.ndarray,
                    up: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(C, l, u) with the joint position limit rows appended: ``lower <= q + v h + q̈ h²/2 <= upper``
        over the horizon ``h = joint_limit_horizon`` [s], one row per range-limited actuated joint."""
        h = float(self.params.joint_limit_horizon)
        s = 2.0 / (h * h)
        rows = np.zeros((len(self.limits), C.shape[1]))
        lo_l, up_l = np.zeros(len(self.limits)), np.zeros(len(self.limits))
        for k, ((iq, iv, lower, upper), ix) in enumerate(zip(self.limits, coords["limit"])):
            predicted = q[iq] + v[iv] * h
            rows[k, ix] = 1.0
            lo_l[k], up_l[k] = s * (lower - predicted), s * (upper - predicted)
        return np.vstack([C, rows]), np.concatenate([lo, lo_l]), np.concatenate([up, up_l])

    def solve(self, q: np.ndarray, v: np.ndarray, ref: WbcReference, eps: float = 1e-10) -> ReferenceSolution:
        """Solve the textbook QP (:meth:`build`) and recover efforts, loop forces and spring torques."""
        qp = self.build(q, v, ref)
        x = solve_dense_qp(qp, eps)
        nv = self.nv
        nan = np.nan
        if x is None:
            return ReferenceSolution(False, np.full(qp["H"].shape[0], nan), np.full(nv, nan), np.full((2, 6), nan),
                                     np.full(self.B.shape[1], nan), np.full(self.n_loop, nan),
                                     np.full(len(self.springs), nan), qp)
        t = qp["terms"]
        wrenches, gen, lam = split_solution(qp, x, nv)
        springs = np.array([-k * (t["q"][iq] - r) for iq, _, k, r, _ in self.springs])
        rigid = [j for j, s in enumerate(self.springs) if s[4]]
        springs[rigid] += lam[self.n_loop:]
        return ReferenceSolution(True, x, x[:nv].copy(), wrenches, self.B_pinv @ gen, lam[:self.n_loop].copy(),
                                 springs, qp)
