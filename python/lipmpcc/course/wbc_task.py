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

A contact's friction pyramid can be the student's too (notebook 08's Exercise 3)::

    rows = friction_pyramid_rows(R_sole, mu)

the four rows (4, 6) on a world-axes wrench ``w = [f; τ]`` of a sole with rotation ``R_sole`` (3, 3) that say
``±f_x − μ f_z <= 0`` and ``±f_y − μ f_z <= 0`` in the sole frame (``f_sole = R_soleᵀ f``), in the order +x, −x,
+y, −y: they replace rows 0–3 of every contact's block of :func:`~lipmpcc.control.reference_qp.contact_wrench_rows`.

- :class:`StudentWbcQp`: the numpy QP with the student's COM block and/or friction rows in place of its own (with
  the right ones, the same matrices as :class:`~lipmpcc.control.reference_qp.ReferenceWbcQp` to rounding);
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

__all__ = ["ComTaskRow", "FrictionRows", "StudentWbcQp", "StudentComWbc", "StudentRunStopped", "MAX_ITER"]

#: the most iterations of a tick's cold numpy solve (a tick beyond it takes the fallback, as in C++)
MAX_ITER = 300

#: the student's function: ``com_task_row(terms, ref, kp, kd) -> (J (3, nv), b (3,))`` (see the module doc)
ComTaskRow = Callable[[dict, WbcReference, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]
#: the student's function: ``friction_pyramid_rows(R_sole (3, 3), mu) -> rows (4, 6)`` (see the module doc)
FrictionRows = Callable[[np.ndarray, float], np.ndarray]


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
    ``com_task_row``'s and/or whose friction-pyramid rows are ``friction_pyramid_rows``' (see the module doc; None:
    the library's); ``spec`` and ``params`` as for the reference QP.

    Raises:
        InvalidInputError: neither function is given, or one is not callable; at a tick, the COM block is not a
            finite (J (3, nv), b (3,)) or the friction rows not a finite (4, 6).
    """

    def __init__(self, spec: Any, params: WbcParams, com_task_row: ComTaskRow | None = None, *,
                 friction_pyramid_rows: FrictionRows | None = None) -> None:
        if com_task_row is None and friction_pyramid_rows is None:
            raise InvalidInputError("com_task_row, friction_pyramid_rows", None, "at least one student's function: "
                                    "a function (terms, ref, kp, kd) -> (J, b) or (R_sole, mu) -> rows")
        if com_task_row is not None and not callable(com_task_row):
            raise InvalidInputError("com_task_row", com_task_row, "a function (terms, ref, kp, kd) -> (J, b)")
        if friction_pyramid_rows is not None and not callable(friction_pyramid_rows):
            raise InvalidInputError("friction_pyramid_rows", friction_pyramid_rows,
                                    "a function (R_sole, mu) -> rows (4, 6)")
        self.com_gains = params.com  # the COM task's gains and weights (the library's task is off with a student's)
        if com_task_row is not None:
            params = dataclasses.replace(params, com=dataclasses.replace(params.com, weight=0.0))
        super().__init__(spec, params)
        self.com_task_row, self.friction_pyramid_rows = com_task_row, friction_pyramid_rows

    def student_block(self, t: dict[str, Any], ref: WbcReference) -> tuple[np.ndarray, np.ndarray]:
        """The student's (J (3, n), b (3,)) at the terms ``t`` (n: the QP's accelerations), checked."""
        gains = self.com_gains
        J, b = self.com_task_row(t, ref, np.asarray(gains.kp, dtype=float), np.asarray(gains.kd, dtype=float))
        J, b = np.asarray(J, dtype=float), np.asarray(b, dtype=float).reshape(-1)
        n = np.asarray(t["J_com"]).shape[1]
        if J.shape != (3, n) or b.shape != (3,) or not (np.all(np.isfinite(J)) and np.all(np.isfinite(b))):
            raise InvalidInputError("com_task_row's (J, b)", (J.shape, b.shape), f"finite arrays (3, {n}) and (3,)")
        return J, b

    def student_friction(self, R_sole: np.ndarray) -> np.ndarray:
        """The student's friction rows (4, 6) for a sole of rotation ``R_sole`` (the QP's μ), checked."""
        rows = np.asarray(self.friction_pyramid_rows(np.array(R_sole, dtype=float), float(self.mu)), dtype=float)
        if rows.shape != (4, 6) or not np.all(np.isfinite(rows)):
            raise InvalidInputError("friction_pyramid_rows(R_sole, mu)", rows.shape, "a finite array (4, 6)")
        return rows

    def _inequalities(self, t: dict[str, Any], ref: WbcReference, coords: dict[str, Any], layout: dict[str, Any],
                      J_e: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The library's inequalities, with rows 0–3 of each contact's block (its friction pyramid) the student's
        when ``friction_pyramid_rows`` is given."""
        C, lo, up = super()._inequalities(t, ref, coords, layout, J_e)
        if self.friction_pyramid_rows is None:
            return C, lo, up
        row = 0
        for i in range(2):
            if layout["contact"][i]:
                o = layout["offsets"][i]
                C[row:row + 4, :] = 0.0
                C[row:row + 4, o:o + 6] = self.student_friction(t["R_sole"][i])
                row += 11
        return C, lo, up

    def _cost(self, t: dict[str, Any], q: np.ndarray, v: np.ndarray, ref: WbcReference, coords: dict[str, Any],
              layout: dict[str, Any], metric: tuple[np.ndarray, np.ndarray] | None) -> tuple[np.ndarray, np.ndarray]:
        """The library's cost without its COM task (weight 0), plus the student's block ``‖J q̈ − b‖²_W`` (with
        ``com_task_row``; without, the library's cost)."""
        H, g = super()._cost(t, q, v, ref, coords, layout, metric)
        if self.com_task_row is None:
            return H, g
        J, b = self.student_block(t, ref)
        nv = layout["nv"]
        W = np.diag(np.asarray(self.com_gains.weight, dtype=float))
        H[:nv, :nv] += J.T @ W @ J
        g[:nv] -= J.T @ W @ b
        return H, g


class StudentComWbc(WholeBodyController):
    """A whole-body controller that solves :class:`StudentWbcQp` (the student's COM block and/or friction rows)
    every tick.

    Args:
        robot: as for :class:`~lipmpcc.control.wbc.WholeBodyController`.
        com_task_row: the student's COM block (see the module doc); None: the library's COM task.
        friction_pyramid_rows: the student's friction rows (see the module doc); None: the library's.
        params: the QP's :class:`~lipmpcc.control.wbc_types.WbcParams` (None: the robot's defaults); its
            ``qp_eps_abs`` is the numpy solve's tolerance.
        stop_com_error: a tick whose COM is further than this from its reference [m] raises
            :class:`StudentRunStopped` (a wrong row would otherwise spend minutes in hard QPs while it falls).

    :meth:`prepare` does nothing (each tick builds its own terms); :meth:`last_qp` and :meth:`last_terms` are the
    C++ controller's and stay empty: the numpy QP of the last tick is :attr:`last_student_qp`.
    """

    def __init__(self, robot: RobotDescription | str, com_task_row: ComTaskRow | None = None,
                 params: WbcParams | None = None, stop_com_error: float = 0.1, *,
                 friction_pyramid_rows: FrictionRows | None = None) -> None:
        super().__init__(robot, params, threaded=False)
        self.stop_com_error = float(stop_com_error)
        self.qp = StudentWbcQp(self.model.spec, self.params, com_task_row, friction_pyramid_rows=friction_pyramid_rows)
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
