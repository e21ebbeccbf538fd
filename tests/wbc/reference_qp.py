"""Slow reference formulation of the whole-body QP: numpy + pinocchio-python + qpsolvers.

It rebuilds, from the same model specification, the QP that the C++ core (``cpp/wbc``) assembles,
by a different route:

- dynamics terms from separate Pinocchio calls (``crba``, ``nonLinearEffects``,
  ``computeJointJacobians`` + ``getFrameJacobian``, ``forwardKinematics(q, v, 0)`` +
  ``getFrameClassicalAcceleration``, ``centerOfMass(q, v, 0)``, ``jacobianCenterOfMass``,
  ``computeCentroidalMapTimeVariation``) instead of the single ``computeAllTerms`` pass;
- the actuation pseudo-inverse from ``numpy.linalg.pinv`` and the unactuated rows from the zero
  rows of B;
- the QP solved by qpsolvers ("proxqp", cold start, one-sided ``G x <= h`` form) instead of the
  warm-started C++ proxsuite object.

Variables, rows and their order follow ``cpp/wbc/include/lipmpcc/wbc/qp.hpp``, so that the
matrices can be compared entry by entry as well as the solutions.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin
import qpsolvers

from lipmpcc.wbc import WbcParams, WbcReference

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
INF = 1e20


@dataclass
class ReferenceSolution:
    """Solution of the reference QP."""

    found: bool
    x: np.ndarray
    qdd: np.ndarray
    wrenches: np.ndarray  # (2, 6), zeros for a swing foot
    tau: np.ndarray  # (nu,) actuator efforts
    qp: dict[str, Any]


class ReferenceWbcQp:
    """The whole-body QP built with numpy.

    Args:
        spec: the C++ ``WbcModelSpec`` (``controller.model.spec``): file, frames, actuators, arms,
            springs, sole size, friction.
        params: the :class:`~lipmpcc.wbc.WbcParams` of the controller under test.
    """

    def __init__(self, spec: Any, params: WbcParams) -> None:
        self.params = params
        self.model = pin.buildModelFromMJCF(spec.mjcf_path)
        m = self.model
        assert m.joints[1].shortname() == "JointModelFreeFlyer"
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
        self.springs = [
            (m.joints[m.getJointId(j)].idx_q, m.joints[m.getJointId(j)].idx_v, k, r)
            for j, k, r in zip(spec.spring_joints, spec.spring_stiffness, spec.spring_reference)
        ]
        self.damping = np.array(m.damping)
        self.mu = float(spec.friction)
        self.half_length = float(spec.foot_half_length)
        self.half_width = float(spec.foot_half_width)

    # ---- dynamics terms ------------------------------------------------------------------
    def terms(self, q: np.ndarray, v: np.ndarray) -> dict[str, Any]:
        m = self.model
        q = q.copy()
        q[3:7] /= np.linalg.norm(q[3:7])
        zero = np.zeros(m.nv)
        t: dict[str, Any] = {}

        d = m.createData()
        M = pin.crba(m, d, q)
        t["M"] = np.triu(M) + np.triu(M, 1).T
        h = pin.nonLinearEffects(m, d, q, v).copy() + self.damping * v
        for iq, iv, k, r in self.springs:
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
        p = self.params
        t = self.terms(q, v)
        q = t["q"]
        nv = self.nv
        contact = [bool(c) for c in ref.contact]
        offsets, o = [], nv
        for c in contact:
            offsets.append(o if c else -1)
            o += 6 if c else 0
        n = o
        nc = sum(contact)
        H = np.zeros((n, n))
        g = np.zeros(n)

        def task(J, drift, target, w):
            W = np.diag(np.broadcast_to(np.asarray(w, dtype=float), (J.shape[0],)))
            H[:nv, :nv] += J.T @ W @ J
            g[:nv] += J.T @ W @ (drift - target)

        def pd(gains, acc, e, ev):
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
        for k, (iq, iv) in enumerate(zip(self.arm_q, self.arm_v)):
            target = a.kp * (ref.arm_posture[k] - q[iq]) - a.kd * v[iv]
            H[iv, iv] += a.weight
            g[iv] -= a.weight * target
        if p.angular_momentum_weight > 0:
            task(t["A_ang"], t["drift_k"], -p.angular_momentum_kd * t["k_com"], p.angular_momentum_weight)
        H[np.arange(nv), np.arange(nv)] += p.qdd_regularization
        H[np.arange(nv, n), np.arange(nv, n)] += p.force_regularization

        # equalities
        nun = self.NT.shape[0]
        A = np.zeros((nun + 6 * nc, n))
        b = np.zeros(nun + 6 * nc)
        A[:nun, :nv] = self.NT @ t["M"]
        b[:nun] = -self.NT @ t["h"]
        row = nun
        for i in range(2):
            if not contact[i]:
                continue
            A[:nun, offsets[i]:offsets[i] + 6] = -self.NT @ t["J_sole"][i].T
            A[row:row + 6, :nv] = t["J_sole"][i]
            b[row:row + 6] = -t["drift_sole"][i] - p.contact_velocity_gain * t["vel_sole"][i]
            row += 6

        # inequalities
        nu = self.B.shape[1]
        C = np.zeros((11 * nc + nu, n))
        lo = np.zeros(11 * nc + nu)
        up = np.zeros(11 * nc + nu)
        sL = p.cop_safety_factor * self.half_length
        sW = p.cop_safety_factor * self.half_width
        mu, mu_t = self.mu, self.mu * min(sL, sW)
        row = 0
        for i in range(2):
            if not contact[i]:
                continue
            R = t["R_sole"][i]
            # local wrench = blockdiag(R^T, R^T) w; rows on the local components
            L = np.zeros((6, 6))
            L[:3, :3] = R.T
            L[3:, 3:] = R.T
            fx, fy, fz, tx, ty, tz = L
            rows = [fx - mu * fz, -fx - mu * fz, fy - mu * fz, -fy - mu * fz,
                    tx - sW * fz, -tx - sW * fz, ty - sL * fz, -ty - sL * fz,
                    tz - mu_t * fz, -tz - mu_t * fz, fz]
            C[row:row + 11, offsets[i]:offsets[i] + 6] = np.array(rows)
            lo[row:row + 10] = -INF
            up[row:row + 10] = 0.0
            lo[row + 10] = p.min_normal_force
            fmax = float(np.asarray(ref.max_normal_force, dtype=float)[i])
            up[row + 10] = fmax if np.isfinite(fmax) else INF
            row += 11
        C[row:, :nv] = self.B_pinv @ t["M"]
        for i in range(2):
            if contact[i]:
                C[row:, offsets[i]:offsets[i] + 6] = -self.B_pinv @ t["J_sole"][i].T
        Bh = self.B_pinv @ t["h"]
        lo[row:] = np.maximum(self.u_min - Bh, -INF)
        up[row:] = np.minimum(self.u_max - Bh, INF)
        return dict(H=H, g=g, A=A, b=b, C=C, l=lo, u=up, offsets=offsets, terms=t)

    def solve(self, q: np.ndarray, v: np.ndarray, ref: WbcReference, eps: float = 1e-10) -> ReferenceSolution:
        qp = self.build(q, v, ref)
        C, lo, up = qp["C"], qp["l"], qp["u"]
        upper = up < INF / 2
        lower = lo > -INF / 2
        G = np.vstack([C[upper], -C[lower]])
        h = np.concatenate([up[upper], -lo[lower]])
        x = qpsolvers.solve_qp(qp["H"], qp["g"], G, h, qp["A"], qp["b"], solver="proxqp",
                               eps_abs=eps, eps_rel=0.0, max_iter=100000)
        nv = self.nv
        if x is None:
            return ReferenceSolution(False, np.full(qp["H"].shape[0], np.nan), np.full(nv, np.nan),
                                     np.full((2, 6), np.nan), np.full(self.B.shape[1], np.nan), qp)
        t = qp["terms"]
        wrenches = np.zeros((2, 6))
        gen = t["M"] @ x[:nv] + t["h"]
        for i, o in enumerate(qp["offsets"]):
            if o >= 0:
                wrenches[i] = x[o:o + 6]
                gen -= t["J_sole"][i].T @ wrenches[i]
        return ReferenceSolution(True, x, x[:nv].copy(), wrenches, self.B_pinv @ gen, qp)
