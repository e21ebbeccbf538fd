"""A small SQP solver for condensed NLPs: the decision variables are inputs only.

When a problem's dynamics are linear, its states can be eliminated (each is an affine function of
the earlier inputs), leaving a dense NLP in the inputs ``u`` alone ("condensed")::

    min f(u, θ)   s.t.  lbg ≤ g(u, θ) ≤ ubg,   lbu ≤ u ≤ ubu

with parameters θ. :class:`CondensedSqp` solves it by sequential quadratic programming: each
iteration solves the QP

    min ½ Δᵀ H Δ + ∇f(u)ᵀ Δ   s.t.  lbg ≤ g(u) + ∇g(u) Δ ≤ ubg,  lbu ≤ u + Δ ≤ ubu

with H the exact Hessian of the Lagrangian made positive definite (non-convex costs, e.g. a concave
progress reward; :mod:`lipmpcc.solvers.convexify`: by default its eigenvalues raised to at least
``eig_floor``, or a modified Cholesky factorisation with ``convexification="modified_cholesky"``), with DAQP (a
dual active-set solver, ~10 µs on 20-variable QPs), followed by a backtracking line search on an
ℓ1 merit function (optionally trying the second-order correction of a rejected full step first). A
converged iterate is a KKT point of the original problem. Multipliers are warm-started from the previous
solve. It stops when the step is below ``tol``.

The derivatives are CasADi functions evaluated through
:class:`~lipmpcc.solvers.casadi_buffer.BufferedFunction` (optionally JIT-compiled).

Two backends run the same iterations: this module's Python loop (the readable reference) and its C++
port in ``lipmpcc._sqp`` (:mod:`lipmpcc.solvers.sqp_compiled`: Eigen, DAQP's C API and the
CasADi-generated C called directly, about ten times faster). ``backend="auto"`` (the default) takes
the C++ one when the module imports and both functions are compiled before their first evaluation (within the
JIT's size limit; the timed MPCC with obstacle slots is not: Python, see below); ``backend="cpp"`` takes it for
every problem built with ``jit=True``: a function not compiled yet is called back interpreted from C++ until its
background compile is in (the same numbers: :mod:`lipmpcc.solvers.sqp_compiled`). "auto" leaves those on Python
because the two backends' rounding differs, and a chaotic closed loop follows it: ``digit-overtake-timed`` on C++
trails the obstacle with a failed solve where the Python SQP overtakes (both backends overtake or trail, with 0–4
failed solves, from guesses nudged by 1e-14–1e-13; docs/benchmarks.md, session 41). ``LIPMPCC_SQP_BACKEND=python`` in the
environment replaces ``"auto"`` by ``"python"``. The two agree to rounding (the C++ eigenvalue clip
through the tridiagonal form and LAPACK's eigensolver differ in the last bits; the C++ DAQP starts from
the previous working set, the Python one cold), so closed-loop runs match to about 1e-10, not bit for bit.
:mod:`lipmpcc.planners.mpcc` builds the MPCC of paper A on it.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass
from typing import Sequence

import casadi as ca
import numpy as np

from .blas_threads import one_blas_thread
from .casadi_buffer import BufferedFunction
from .convexify import eigen_clip, modified_cholesky, requested_convexification
from .sqp_compiled import CompiledSqp, compiled_available, requested_backend

__all__ = ["CondensedSqp", "SqpSolution"]

_log = logging.getLogger(__name__)

#: finite stand-in for an infinite bound of a QP *step* (DAQP takes finite bounds). The QP's rows bound
#: the step ∇g Δ by ``ubg − g``; an infinite bound stays infinite whatever g is (a constraint far from
#: active, e.g. the barrier of an obstacle 100 m away, has g ~ 1e5), so it is ±_BIG on the step itself,
#: never ``_BIG − g``
_BIG = 1e4


@dataclass(frozen=True)
class SqpSolution:
    """One solve of :class:`CondensedSqp`.

    Attributes:
        found: converged (step below ``tol``) to a feasible point.
        status: ``"converged"``, ``"max_iter"``, ``"infeasible (...)"`` or ``"qp_failed (...)"``.
        iterations: SQP iterations.
        cost: f at the returned point.
        u: the returned inputs (n,).
    """

    found: bool
    status: str
    iterations: int
    cost: float
    u: np.ndarray


class CondensedSqp:
    """SQP with exact, convexified Hessians and DAQP subproblems for ``min f(u)`` s.t. bounds.

    Args:
        name: prefix of the CasADi functions (``<name>_terms``, ``<name>_merit``).
        u: the decision variables, an SX column (n,).
        params: the parameter symbols (SX columns) passed to :meth:`solve` in this order.
        cost: f(u, params), a scalar SX.
        g: the constraint functions g(u, params), an SX column (m,).
        lbg, ubg: their bounds (m,) (±inf allowed).
        lbu, ubu: the bounds of u (n,) (±inf allowed).
        max_iter: iteration limit.
        tol: the solve stops when max |step| < tol.
        jit: compile the derivatives to machine code (see :mod:`lipmpcc.solvers.casadi_buffer`).
        eig_floor: the Hessian's eigenvalues are raised to at least this (with ``"modified_cholesky"``: its
            pivots).
        convexification: how the Hessian is made positive definite (:mod:`lipmpcc.solvers.convexify`):
            ``"eigen_clip"`` (eigenvalues raised to ``eig_floor``) or ``"modified_cholesky"`` (Gill–Murray–Wright,
            the factor handed to DAQP; other iterates where the Hessian is indefinite); None (the default):
            ``LIPMPCC_SQP_CONVEXIFICATION`` from the environment when set, else ``"eigen_clip"``.
        second_order_correction: when the merit function rejects a full step shorter than this (max-norm)
            because the violation grew (the constraints' curvature: the Maratos effect, which costs extra
            iterations near a solution), try the second-order corrected step (one more QP with the same H and
            ∇g) before halving; a local remedy, rarely accepted for long steps. 0: never.
        rate_stop: > 0: also stop when the distance to the solution estimated from the contraction of the last
            two full steps is below ``rate_stop · tol`` at a feasible point (an iteration less when the steps
            shrink fast, e.g. 1e-3 then 1.5e-4); 0: only the step below ``tol``.
        backend: ``"auto"`` (C++ when ``lipmpcc._sqp`` imports and both functions are compiled before their first
            evaluation, ``BufferedFunction.eager``, else Python; ``LIPMPCC_SQP_BACKEND`` in the environment
            overrides it), ``"cpp"`` (C++ for functions built with ``jit``, compiled or called back until they are,
            or an InvalidInputError) or ``"python"``.

    Attributes:
        backend: the backend that runs :meth:`solve` (``"cpp"`` or ``"python"``).
        lam: the constraint multipliers kept for the next solve's warm start (m,).
        trace: None, or a list that receives (iteration, alpha, max |du|, QP iterations) per iteration.
        qp_time: accumulated time in the QP solver [s]; qp_iters: accumulated QP iterations.
    """

    def __init__(
        self,
        name: str,
        u: ca.SX,
        params: Sequence[ca.SX],
        cost: ca.SX,
        g: ca.SX,
        lbg: Sequence[float],
        ubg: Sequence[float],
        lbu: Sequence[float],
        ubu: Sequence[float],
        max_iter: int = 100,
        tol: float = 1e-4,
        jit: bool = False,
        eig_floor: float = 1.0,
        second_order_correction: float = 0.0,
        rate_stop: float = 0.0,
        backend: str = "auto",
        convexification: str | None = None,
    ) -> None:
        self.convexification = requested_convexification(convexification)
        self.max_iter = max_iter
        self.tol = tol
        self.lbg = np.array(lbg, dtype=float)
        self.ubg = np.array(ubg, dtype=float)
        lam = ca.SX.sym("lam", g.shape[0])
        lag = cost + ca.dot(lam, g)
        self.f_all = BufferedFunction(
            f"{name}_terms",
            [u, *params, lam],
            [cost, ca.gradient(cost, u), g, ca.jacobian(g, u), ca.hessian(lag, u)[0]],
            jit=jit,
        )
        self.f_merit = BufferedFunction(f"{name}_merit", [u, *params], [cost, g], jit=jit)
        self.nu = int(u.shape[0])
        self.m = int(g.shape[0])
        lo, hi = np.asarray(lbu, dtype=float), np.asarray(ubu, dtype=float)
        self.lbu = np.where(np.isfinite(lo), lo, -_BIG)
        self.ubu = np.where(np.isfinite(hi), hi, _BIG)
        self._lo_g = np.where(np.isfinite(self.lbg), self.lbg, -_BIG)
        self._hi_g = np.where(np.isfinite(self.ubg), self.ubg, _BIG)
        self._free_lo = ~np.isfinite(self.lbg)  # rows with no lower / upper bound
        self._free_hi = ~np.isfinite(self.ubg)
        self._free_lo_rows = self.nu + np.flatnonzero(self._free_lo)  # the same rows of [Δ, ∇g Δ]
        self._free_hi_rows = self.nu + np.flatnonzero(self._free_hi)
        self._sense = np.zeros(self.nu + self.m, dtype=np.int32)
        self.lam = np.zeros(self.m)
        self.eig_floor = eig_floor
        self.second_order_correction = float(second_order_correction)
        self.rate_stop = float(rate_stop)
        self.trace: list[tuple[int, float, float, float]] | None = None
        self.qp_time = 0.0
        self.qp_iters = 0
        self._compiled = self._compiled_backend(requested_backend(backend), lbu, ubu)
        self.backend = "python" if self._compiled is None else "cpp"

    def _compiled_backend(self, backend: str, lbu: Sequence[float], ubu: Sequence[float]) -> CompiledSqp | None:
        """The C++ solver for ``backend`` (``"auto"``: when possible; ``"cpp"``: required), or None."""
        if backend == "python":
            return None
        if backend == "auto" and not (compiled_available() and self.f_all.eager and self.f_merit.eager):
            return None
        try:
            return CompiledSqp(
                self.f_all, self.f_merit, self.lbg, self.ubg, np.asarray(lbu, dtype=float), np.asarray(ubu, dtype=float),
                max_iter=self.max_iter, tol=self.tol, eig_floor=self.eig_floor,
                convexification=self.convexification, second_order_correction=self.second_order_correction, rate_stop=self.rate_stop,
            )
        except RuntimeError as exc:  # the library cannot be loaded by the module (dlopen, symbols)
            if backend == "cpp":
                raise
            _log.warning("CondensedSqp %s: the C++ backend is unavailable (%s); using Python", self.f_all.function.name(), exc)
            return None

    def violation(self, g: np.ndarray) -> float:
        """ℓ1 constraint violation of the constraint values ``g``."""
        return float(np.maximum(self.lbg - g, 0.0).sum() + np.maximum(g - self.ubg, 0.0).sum())

    def solve(self, u0: np.ndarray, params: Sequence[np.ndarray]) -> SqpSolution:
        """Solve from the initial guess ``u0`` (any shape with n elements) for the parameter values, on one
        BLAS thread (:mod:`lipmpcc.solvers.blas_threads`: threaded OpenBLAS stalls small ``eigh`` calls)."""
        if self._compiled is not None:
            return self._solve_compiled(u0, params)
        with one_blas_thread():
            return self._solve(u0, params)

    def _solve_compiled(self, u0: np.ndarray, params: Sequence[np.ndarray]) -> SqpSolution:
        """:meth:`solve` on the C++ backend (the same iterations as :meth:`_solve`); keeps ``lam``, the QP
        counters and the trace as the Python loop does."""
        res = self._compiled.solve(u0, params, self.lam, self.trace is not None)
        self.lam = np.asarray(res.lam)
        self.qp_time += res.qp_time
        self.qp_iters += res.qp_iters
        if self.trace is not None:
            self.trace.extend(res.trace)
        return SqpSolution(res.found, res.status, res.iterations, res.cost, np.asarray(res.u))

    def _solve(self, u0: np.ndarray, params: Sequence[np.ndarray]) -> SqpSolution:
        u = np.clip(u0.reshape(-1).astype(float), self.lbu, self.ubu)
        lam = self.lam
        status = "max_iter"
        it = 0
        f_all = self.f_all
        for i, v in enumerate(params):  # the parameters stay bound for every evaluation of this solve
            f_all.set_arg(1 + i, v)
            self.f_merit.set_arg(1 + i, v)
        i_lam = 1 + len(params)
        merit: tuple[np.ndarray, float, float] | None = None  # (point, cost, violation) of the accepted step
        prev_size = math.inf
        for it in range(1, self.max_iter + 1):
            f_all.set_arg(i_lam, lam)
            cost, grad, g, Jg, H = f_all.evaluate(u)  # views, valid until the next f_all evaluation
            cost = float(cost[0])
            Jg = Jg.copy()
            H = self._convexified(H)
            du, exitflag, info = self._qp(H, grad, Jg, *self._qp_bounds(u, g))
            if exitflag < 1:
                self.lam = np.zeros(self.m)
                return SqpSolution(False, f"qp_failed (daqp exitflag {exitflag})", it, cost, u)
            du = np.asarray(du)
            lam_qp = np.asarray(info["lam"])[self.nu :]
            alpha, step, lam_qp, merit = self._line_search(u, du, grad, g, cost, lam_qp, (H, Jg))
            u = np.clip(u + step, self.lbu, self.ubu)
            lam = lam + alpha * (lam_qp - lam)
            if self.trace is not None:
                self.trace.append((it, alpha, float(np.max(np.abs(du))), float(info["iterations"])))
            size = float(np.max(np.abs(step)))
            if size < self.tol or self._contracted(size, prev_size, alpha, merit):
                status = "converged"
                break
            prev_size = size
        if merit is not None and np.array_equal(merit[0], u):  # the line search evaluated this very point
            c_f, viol = merit[1], merit[2]
        else:
            c_n, g_f = self.f_merit.evaluate(u)
            c_f, viol = float(c_n[0]), self.violation(g_f)
        feasible = viol < 1e-6
        found = feasible and status == "converged"
        if not feasible:
            status = f"infeasible ({status})"
        self.lam = lam if found else np.zeros(self.m)
        return SqpSolution(found, status, it, c_f, u)

    def _convexified(self, H: np.ndarray) -> np.ndarray:
        """The QP's positive definite Hessian from the Lagrangian's ``H`` (its lower triangle read)."""
        if self.convexification == "eigen_clip":
            return eigen_clip(H, self.eig_floor)
        R, e = modified_cholesky(H, self.eig_floor)
        A = np.tril(H) + np.tril(H, -1).T
        A[np.diag_indices_from(A)] += e
        return A  # = RᵀR (the C++ backend hands DAQP R itself)

    def _contracted(self, size: float, prev_size: float, alpha: float, merit: tuple[np.ndarray, float, float] | None) -> bool:
        """With ``rate_stop``: whether a full step of max-norm ``size`` after one of ``prev_size`` leaves the
        iterate within ``tol`` of the solution, estimated from their contraction r = size / prev_size < 0.5
        (the steps left add up to about size·r / (1 − r)), at a feasible point (violation below 5e-7 before the
        clip to the bounds, half the threshold of ``found``)."""
        if not self.rate_stop or alpha != 1.0 or merit is None or merit[2] >= 5e-7 or not math.isfinite(prev_size):
            return False
        r = size / prev_size
        return r < 0.5 and size * r / (1.0 - r) < self.rate_stop * self.tol

    def _qp(self, H: np.ndarray, grad: np.ndarray, Jg: np.ndarray, blo: np.ndarray, bhi: np.ndarray) -> tuple[np.ndarray, int, dict]:
        """DAQP on min ½ΔᵀHΔ + ∇fᵀΔ s.t. blo ≤ [Δ, ∇g Δ] ≤ bhi, its time and iterations counted:
        (Δ, exit flag, info)."""
        import daqp

        _t = time.perf_counter()
        d, _, exitflag, info = daqp.solve(H, grad, Jg, bhi, blo, self._sense)
        self.qp_time += time.perf_counter() - _t
        self.qp_iters += int(info["iterations"])
        return d, exitflag, info

    def _qp_bounds(self, u: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The QP's bounds on [Δ, ∇g Δ]: the input bounds minus u, the constraint bounds minus g, and ±_BIG
        on the step where a constraint has no bound (whatever g is)."""
        nu = self.nu
        lo, hi = np.empty(nu + self.m), np.empty(nu + self.m)
        np.subtract(self.lbu, u, out=lo[:nu])
        np.subtract(self._lo_g, g, out=lo[nu:])
        np.subtract(self.ubu, u, out=hi[:nu])
        np.subtract(self._hi_g, g, out=hi[nu:])
        lo[self._free_lo_rows] = -_BIG
        hi[self._free_hi_rows] = _BIG
        return lo, hi

    def _line_search(
        self, u: np.ndarray, du: np.ndarray, grad: np.ndarray, g: np.ndarray, cost: float, lam_qp: np.ndarray,
        qp: tuple[np.ndarray, np.ndarray],
    ) -> tuple[float, np.ndarray, np.ndarray, tuple[np.ndarray, float, float] | None]:
        """Backtracking step length on the ℓ1 merit function f + ν·violation (Armijo, at most 10 halvings;
        with ``second_order_correction``, a rejected full step that raised the violation is corrected first).

        Returns (α, the step taken, the QP multipliers of that step, (point, f, violation) at the accepted
        step or None when no halving was accepted). The parameters are those bound by :meth:`solve`; ``qp``
        is the QP's (H, ∇g).
        """
        nu_merit = max(1e2, 2.0 * float(np.max(np.abs(lam_qp), initial=0.0)))
        viol = self.violation(g)
        phi0 = cost + nu_merit * viol
        dphi = float(grad @ du) - nu_merit * viol
        slack = 1e-12 * max(1.0, abs(phi0))
        alpha = 1.0
        for _ in range(10):
            step = alpha * du
            u_n = u + step
            c_n, g_n = self.f_merit.evaluate(u_n)
            c_n, v_n = float(c_n[0]), self.violation(g_n)
            phi_n = c_n + nu_merit * v_n
            if phi_n <= phi0 + 1e-4 * alpha * min(dphi, 0.0) + slack:
                return alpha, step, lam_qp, (u_n, c_n, v_n)
            if alpha == 1.0 and v_n > viol and float(np.max(np.abs(du))) < self.second_order_correction:
                corrected = self._corrected_step(u, du, grad, g_n - qp[1] @ du, qp, nu_merit, phi0 + 1e-4 * min(dphi, 0.0) + slack)
                if corrected is not None:
                    return corrected
            alpha *= 0.5
        return alpha, alpha * du, lam_qp, None

    def _corrected_step(
        self, u: np.ndarray, du: np.ndarray, grad: np.ndarray, g_c: np.ndarray, qp: tuple[np.ndarray, np.ndarray],
        nu_merit: float, phi_max: float,
    ) -> tuple[float, np.ndarray, np.ndarray, tuple[np.ndarray, float, float]] | None:
        """The second-order correction of a full step ``du`` that the merit function rejected because the
        constraints' curvature raised the violation (the Maratos effect): the QP again with the constraint
        values g(u + du) − ∇g du instead of g(u) (Nocedal & Wright, eq. 15.36). Returns the line search's
        answer for the corrected step when its merit is at most ``phi_max``, else None."""
        d, exitflag, info = self._qp(qp[0], grad, qp[1], *self._qp_bounds(u, g_c))
        if exitflag < 1:
            return None
        d = np.asarray(d)
        u_c = u + d
        c_n, g_n = self.f_merit.evaluate(u_c)
        c_n, v_n = float(c_n[0]), self.violation(g_n)
        if c_n + nu_merit * v_n > phi_max:
            return None
        return 1.0, d, np.asarray(info["lam"])[self.nu :], (u_c, c_n, v_n)
