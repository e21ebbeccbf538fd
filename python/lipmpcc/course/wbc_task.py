"""A whole-body controller whose COM task row is a student's, so that the robot stands on the student's code.

The whole-body QP (:mod:`lipmpcc.control.reference_qp`, the numpy rebuild of the C++ QP) minimises weighted task
errors ``Σ_k ‖J_k q̈ − b_k‖²_{W_k}``; each task is one *row block* ``(J_k, b_k)``: the task Jacobian and the
acceleration the task asks of ``J_k q̈``. Here the COM task's block is the student's function::

    J_task, b_task = com_task_row(terms, ref, kp, kd)

with ``terms`` the dynamics terms of the tick (a dict: ``J_com`` (3, nv), ``drift_com`` (3,) = J̇v [m/s²],
``com`` (3,) [m], ``vcom`` (3,) [m/s], and the others of :meth:`ReferenceWbcQp.terms
<lipmpcc.control.reference_qp.ReferenceWbcQp.terms>`), ``ref`` the tick's
:class:`~lipmpcc.control.wbc_types.WbcReference` (``com_pos`` [m], ``com_vel`` [m/s], ``com_acc`` [m/s²]) and
``kp`` [1/s²], ``kd`` [1/s] the COM gains (3,) each. The library puts ``Jᵀ W J`` in the Hessian and ``−Jᵀ W b``
in the gradient with the COM weights ``W`` of :class:`~lipmpcc.control.wbc_types.WbcParams`; everything else
(torso, swing feet, arms, angular momentum, the dynamics, contact and torque rows) is the library's.

- :class:`StudentWbcQp`: the numpy QP with the student's COM block in place of its own (with the right block,
  the same matrices as :class:`~lipmpcc.control.reference_qp.ReferenceWbcQp` to rounding);
- :class:`StudentComWbc`: a :class:`~lipmpcc.control.wbc.WholeBodyController` that solves that QP every tick
  (cold, in numpy, at most :data:`MAX_ITER` iterations: 1–7 ms a tick on ``digit_like``), for
  :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop`'s ``wbc=``. A tick whose QP is not solved returns the C++
  controller's fallback (the last efforts, damped).
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any, Callable

import numpy as np
import pinocchio as pin

from .. import _wbc
from ..control.reference_qp import INF, ReferenceWbcQp, split_solution
from ..control.wbc import WholeBodyController
from ..control.wbc_types import WbcOutput, WbcParams, WbcReference, WbcTaskErrors
from ..exceptions import InvalidInputError, LipmpccError
from ..robots import RobotDescription

__all__ = ["ComTaskRow", "StudentWbcQp", "StudentComWbc", "StudentRunStopped", "MAX_ITER"]

#: the most iterations of a tick's cold numpy solve (a tick beyond it takes the fallback, as in C++)
MAX_ITER = 300

#: the student's function: ``com_task_row(terms, ref, kp, kd) -> (J (3, nv), b (3,))`` (see the module doc)
ComTaskRow = Callable[[dict, WbcReference, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


class StudentRunStopped(LipmpccError):
    """:class:`StudentComWbc` stopped the run: the COM left its reference by more than ``stop_com_error``."""


def _solve(qp: dict[str, Any], eps: float, max_iter: int) -> np.ndarray | None:
    """Cold proxsuite dense solve of the QP of :meth:`ReferenceWbcQp.build` (one-sided ``G x <= h`` form, the
    certificates off as in C++), at most ``max_iter`` iterations; None if not solved."""
    import proxsuite

    C, lo, up = qp["C"], qp["l"], qp["u"]
    upper, lower = up < INF / 2, lo > -INF / 2
    G = np.vstack([C[upper], -C[lower]])
    h = np.concatenate([up[upper], -lo[lower]])
    solver = proxsuite.proxqp.dense.QP(qp["H"].shape[0], qp["A"].shape[0], G.shape[0])
    s = solver.settings
    s.eps_abs, s.eps_rel, s.max_iter, s.max_iter_in = eps, 0.0, max_iter, 200
    s.eps_primal_inf, s.eps_dual_inf = 1e-14, 1e-14
    solver.init(qp["H"], qp["g"], qp["A"], qp["b"], G, np.full(G.shape[0], -INF), h)
    solver.solve()
    if solver.results.info.status != proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED:
        return None
    return np.array(solver.results.x)


class StudentWbcQp(ReferenceWbcQp):
    """The numpy whole-body QP (:class:`~lipmpcc.control.reference_qp.ReferenceWbcQp`) whose COM task block is
    ``com_task_row``'s (see the module doc); ``spec`` and ``params`` as for the reference QP.

    Raises:
        InvalidInputError: ``com_task_row`` is not callable; at a tick, its block is not a finite (J (3, nv), b (3,)).
    """

    def __init__(self, spec: Any, params: WbcParams, com_task_row: ComTaskRow) -> None:
        if not callable(com_task_row):
            raise InvalidInputError("com_task_row", com_task_row, "a function (terms, ref, kp, kd) -> (J, b)")
        super().__init__(spec, dataclasses.replace(params, com=dataclasses.replace(params.com, weight=0.0)))
        self.com_gains = params.com
        self.com_task_row = com_task_row

    def student_block(self, t: dict[str, Any], ref: WbcReference) -> tuple[np.ndarray, np.ndarray]:
        """The student's (J (3, n), b (3,)) at the terms ``t`` (n: the QP's accelerations), checked."""
        gains = self.com_gains
        J, b = self.com_task_row(t, ref, np.asarray(gains.kp, dtype=float), np.asarray(gains.kd, dtype=float))
        J, b = np.asarray(J, dtype=float), np.asarray(b, dtype=float).reshape(-1)
        n = np.asarray(t["J_com"]).shape[1]
        if J.shape != (3, n) or b.shape != (3,) or not (np.all(np.isfinite(J)) and np.all(np.isfinite(b))):
            raise InvalidInputError("com_task_row's (J, b)", (J.shape, b.shape), f"finite arrays (3, {n}) and (3,)")
        return J, b

    def _cost(self, t: dict[str, Any], q: np.ndarray, v: np.ndarray, ref: WbcReference, coords: dict[str, Any],
              layout: dict[str, Any], metric: tuple[np.ndarray, np.ndarray] | None) -> tuple[np.ndarray, np.ndarray]:
        """The library's cost without its COM task (weight 0), plus the student's block ``‖J q̈ − b‖²_W``."""
        H, g = super()._cost(t, q, v, ref, coords, layout, metric)
        J, b = self.student_block(t, ref)
        nv = layout["nv"]
        W = np.diag(np.asarray(self.com_gains.weight, dtype=float))
        H[:nv, :nv] += J.T @ W @ J
        g[:nv] -= J.T @ W @ b
        return H, g


class StudentComWbc(WholeBodyController):
    """A whole-body controller that solves :class:`StudentWbcQp` (the student's COM block) every tick.

    Args:
        robot: as for :class:`~lipmpcc.control.wbc.WholeBodyController`.
        com_task_row: the student's function (see the module doc).
        params: the QP's :class:`~lipmpcc.control.wbc_types.WbcParams` (None: the robot's defaults); its
            ``qp_eps_abs`` is the numpy solve's tolerance.
        stop_com_error: a tick whose COM is further than this from its reference [m] raises
            :class:`StudentRunStopped` (a wrong row would otherwise spend minutes in hard QPs while it falls).

    :meth:`prepare` does nothing (each tick builds its own terms); :meth:`last_qp` and :meth:`last_terms` are the
    C++ controller's and stay empty: the numpy QP of the last tick is :attr:`last_student_qp`.
    """

    def __init__(self, robot: RobotDescription | str, com_task_row: ComTaskRow, params: WbcParams | None = None,
                 stop_com_error: float = 0.1) -> None:
        super().__init__(robot, params, threaded=False)
        self.stop_com_error = float(stop_com_error)
        self.qp = StudentWbcQp(self.model.spec, self.params, com_task_row)
        self.last_student_qp: dict[str, Any] | None = None

    def prepare(self, q: np.ndarray, v: np.ndarray) -> None:
        """Nothing: the numpy QP computes its terms in :meth:`solve`."""

    def solve(self, q: np.ndarray, v: np.ndarray, ref: WbcReference) -> WbcOutput:
        """One tick on the student's COM block: the efforts of the numpy QP's solution, or the fallback (the
        last efforts, damped) when it is not solved. Errors of the student's function propagate."""
        w0 = time.perf_counter()
        qp = self.qp.build(np.asarray(q, dtype=float), np.asarray(v, dtype=float), ref)
        self.last_student_qp = qp
        x = _solve(qp, float(self.params.qp_eps_abs), MAX_ITER)
        t = qp["terms"]
        nv = self.nv
        err = float(np.linalg.norm(np.asarray(ref.com_pos, dtype=float) - t["com"]))
        if not err <= self.stop_com_error:
            raise StudentRunStopped(f"the COM is {err:.3f} m from its reference (more than {self.stop_com_error} m): "
                                    "the run stopped")
        if x is None or not np.all(np.isfinite(x)):
            out = self._python_fallback(v)
            return dataclasses.replace(out, status="not solved (numpy QP)",
                                       status_code=int(_wbc.QpStatus.max_iter_reached))
        wrenches, gen, lam = split_solution(qp, x, nv)
        tau = self.qp.B_pinv @ gen
        self._u_last = tau
        us = 1e6 * (time.perf_counter() - w0)
        return WbcOutput(tau=tau, tau_joint=self.qp.B @ tau, qdd=x[:nv].copy(), wrenches=wrenches, status="solved",
                         status_code=int(_wbc.QpStatus.solved), iterations=0, solve_time_us=us, tick_time_us=us,
                         used_fallback=False, errors=self._errors(t, ref),
                         loop_forces=lam[:self.qp.n_loop].copy(), spring_torques=np.zeros(self.n_springs))

    def _errors(self, t: dict[str, Any], ref: WbcReference) -> WbcTaskErrors:
        """The tick's task errors (reference minus measured) of the COM and the torso, the measured centroidal
        angular momentum; the feet's and the arms' are left at zero."""
        return WbcTaskErrors(
            com_pos=np.asarray(ref.com_pos, dtype=float) - t["com"],
            com_vel=np.asarray(ref.com_vel, dtype=float) - t["vcom"],
            torso_rot=pin.log3(np.asarray(ref.torso_rot, dtype=float) @ t["R_torso"].T),
            torso_angvel=np.asarray(ref.torso_angvel, dtype=float) - t["w_torso"],
            foot_pos=np.zeros((2, 3)), foot_rot=np.zeros((2, 3)), arm_posture=np.zeros(self.n_arm),
            angular_momentum=np.asarray(t["k_com"], dtype=float).copy())
