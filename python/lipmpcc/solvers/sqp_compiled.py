"""The C++ condensed SQP (the private module ``lipmpcc._sqp``) behind a validating Python interface.

:class:`~lipmpcc.solvers.condensed_sqp.CondensedSqp` runs its solve loop here when ``lipmpcc._sqp`` is importable
and its two CasADi functions are compiled before their first evaluation (``BufferedFunction.eager``; with
``backend="cpp"``: built for the JIT, ``BufferedFunction.jit``): the same
iterations, step for step (the Python class stays the readable reference; ``tests/solvers/
test_sqp_compiled.py`` checks that both give the same iterates), with Eigen's symmetric eigensolver
for the convexification, DAQP's C API for the subproblems and the CasADi-generated C called directly
(the cached library loaded with ``dlopen``). A function not compiled yet (too large to be compiled before its first
evaluation: the timed MPCC with obstacle slots; compiled in the background) is evaluated interpreted, called back
from C++ (:meth:`BufferedFunction.eval_into`), until its library is ready; then the library is called directly.
Both give the same numbers to the bit, so the results do not depend on when the compile ends, and such problems
run on the C++ SQP (when asked: ``backend="cpp"``) from their first solve. Nothing here is needed by users.
"""

from __future__ import annotations

import math
import os
from typing import Any, Callable, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from .casadi_buffer import BufferedFunction
from .convexify import CONVEXIFICATIONS, requested_partial_eigen

__all__ = ["compiled_available", "compiled_function", "requested_backend", "CompiledSqp", "BACKENDS"]

#: the SQP backends: ``"auto"`` (C++ when possible), ``"cpp"`` (C++ or an error), ``"python"``
BACKENDS = ("auto", "cpp", "python")
#: environment variable that replaces the default backend ``"auto"`` (e.g. ``python`` for a reference run)
BACKEND_ENV = "LIPMPCC_SQP_BACKEND"


def compiled_available() -> bool:
    """Whether the compiled module ``lipmpcc._sqp`` imports."""
    try:
        from .. import _sqp  # noqa: F401
    except ImportError:
        return False
    return True


def compiled_function(name: str) -> Callable[..., Any] | None:
    """The function ``name`` of ``lipmpcc._sqp`` (e.g. ``"lip_rollout"``), or None when the module (or that
    function: an older build) is missing."""
    try:
        from .. import _sqp
    except ImportError:
        return None
    return getattr(_sqp, name, None)


def requested_backend(backend: str) -> str:
    """The backend asked for: ``backend``, or for ``"auto"`` the value of ``LIPMPCC_SQP_BACKEND`` when set."""
    if backend not in BACKENDS:
        raise InvalidInputError("backend", backend, f"one of {', '.join(BACKENDS)}")
    if backend == "auto":
        env = os.environ.get(BACKEND_ENV, "").strip().lower() or "auto"
        if env not in BACKENDS:
            raise InvalidInputError(BACKEND_ENV, env, f"one of {', '.join(BACKENDS)} (environment variable)")
        return env
    return backend


def _vector(name: str, value: Any, size: int) -> np.ndarray:
    """``value`` as a finite float64 vector of ``size`` elements (any shape), else InvalidInputError."""
    a = np.asarray(value, dtype=float).reshape(-1)
    if a.size != size:
        raise InvalidInputError(name, value, f"{size} values", f"got {a.size}")
    if not np.isfinite(a).all():
        raise InvalidInputError(name, value, "finite values")
    return a


class CompiledSqp:
    """The C++ SQP for the problem of two functions built for the JIT (see :class:`CondensedSqp`).

    Args:
        terms: ``terms(u, θ…, λ) -> (f, ∇f, g, ∇g, ∇²L)``, built with ``jit=True`` (compiled, or called back
            interpreted until its background compile is swapped in: :meth:`refresh`).
        merit: ``merit(u, θ…) -> (f, g)``, likewise.
        lbg, ubg: the constraints' bounds (m,) (±inf allowed).
        lbu, ubu: the inputs' bounds (n,) (±inf allowed).
        max_iter, tol, eig_floor, second_order_correction, rate_stop: as in :class:`CondensedSqp`.
        convexification: ``"eigen_clip"`` or ``"modified_cholesky"`` (:mod:`lipmpcc.solvers.convexify`).
        partial_eigen: the eigenvalue clip as H + Σ (floor − λ_i) v_i v_iᵀ over the eigenvalues below the floor only
            (the tridiagonal form's eigenvalues by the rational QL method, those eigenvectors by inverse iteration:
            at n = 20 about 70 % of the CPU time of the full eigendecomposition and rebuild; the same matrix to
            rounding; the full one when it cannot vouch for its result); False: Eigen's full eigendecomposition;
            None (the default): ``$LIPMPCC_SQP_PARTIAL_EIGEN`` == "1", else False
            (:func:`~lipmpcc.solvers.convexify.requested_partial_eigen`).
        warm_start: DAQP from the working set of the previous QP (of this or the last solve; a cold retry when
            that fails) instead of cold as ``daqp.solve``: the same QP solutions up to rounding in about a tenth
            of the QP iterations (the fixed-T MPCC: 5 instead of 56 per solve, half the QP time); False: the
            reference's QP iterations exactly.

    Raises:
        InvalidInputError: a function is not compiled, or the module is missing.
    """

    def __init__(
        self, terms: BufferedFunction, merit: BufferedFunction, lbg: np.ndarray, ubg: np.ndarray, lbu: np.ndarray,
        ubu: np.ndarray, *, max_iter: int, tol: float, eig_floor: float, second_order_correction: float, rate_stop: float,
        warm_start: bool = True, convexification: str = "eigen_clip", partial_eigen: bool | None = None,
    ) -> None:
        for name, f in (("terms", terms), ("merit", merit)):
            if not f.jit:
                raise InvalidInputError(name, f.function.name(), "a JIT-compiled function (BufferedFunction(jit=True))")
        try:
            from .. import _sqp
        except ImportError as exc:
            raise InvalidInputError("backend", "cpp", "an importable lipmpcc._sqp", str(exc)) from None
        if int(max_iter) < 0 or not (math.isfinite(tol) and tol > 0):
            raise InvalidInputError("max_iter, tol", (max_iter, tol), "max_iter >= 0 and tol > 0")
        settings = _sqp.SqpSettings()
        settings.max_iter = int(max_iter)
        settings.tol = float(tol)
        settings.eig_floor = float(eig_floor)
        if convexification not in CONVEXIFICATIONS:
            raise InvalidInputError("convexification", convexification, f"one of {', '.join(CONVEXIFICATIONS)}")
        if convexification == "modified_cholesky" and not (math.isfinite(eig_floor) and eig_floor > 0):
            raise InvalidInputError("eig_floor", eig_floor, "a finite value > 0 for the modified Cholesky factorisation")
        settings.convexification = (_sqp.Convexification.EigenClip if convexification == "eigen_clip"
                                    else _sqp.Convexification.ModifiedCholesky)
        settings.second_order_correction = float(second_order_correction)
        settings.rate_stop = float(rate_stop)
        settings.warm_start = bool(warm_start)
        settings.partial_eigen = requested_partial_eigen(partial_eigen)
        self._sqp, self._functions = _sqp, (terms, merit)
        if not hasattr(_sqp.CondensedSqp, "replace_functions") and (terms.so is None or merit.so is None):
            # a module built before the callbacks (session 41): compiled functions only (a RuntimeError: "auto" falls
            # back to Python)
            raise RuntimeError("lipmpcc._sqp cannot call back a function that is not compiled yet (rebuild it)")
        arr = [np.asarray(b, dtype=float).reshape(-1) for b in (lbg, ubg, lbu, ubu)]
        self._impl = _sqp.CondensedSqp(self._native(terms), self._native(merit), *arr, settings)
        #: whether a function is still called back interpreted (then :meth:`refresh` looks for its library)
        self.callbacks = terms.so is None or merit.so is None
        self.nu = int(self._impl.nu)
        self.m = int(self._impl.m)
        self._param_sizes = [int(self._impl.param_size(i)) for i in range(self._impl.n_params)]

    def _native(self, f: BufferedFunction) -> Any:
        """``f`` for the C++ SQP: its compiled library, or a callback to :meth:`BufferedFunction.eval_into`."""
        if f.so is not None and f.symbol is not None:
            return self._sqp.CasadiFunction(str(f.so), f.symbol)
        return self._sqp.CasadiFunction(f.eval_into, f.in_sizes, f.out_shapes, f.function.name())

    def refresh(self) -> None:
        """Call the compiled library of a function that was called back so far, once its background compile is
        in (the same numbers, faster; the warm start kept)."""
        new = [None, None]
        for i, f in enumerate(self._functions):
            f.poll()
            if self._impl.uses_callback(i) and f.so is not None:
                new[i] = self._native(f)
        if new[0] is not None or new[1] is not None:
            self._impl.replace_functions(*new)
        self.callbacks = bool(self._impl.uses_callback(0) or self._impl.uses_callback(1))

    def solve(self, u0: np.ndarray, params: Sequence[np.ndarray], lam: np.ndarray, record_trace: bool = False) -> Any:
        """One solve from ``u0`` (n elements, any shape) with the parameter values (flattened in C order, as
        ``BufferedFunction.set_arg``) and the warm-start multipliers ``lam`` (m,); returns ``_sqp.SqpResult``
        (found, status, iterations, cost, u, lam for the next solve, qp_time [s], qp_iters, trace)."""
        if self.callbacks:
            self.refresh()
        try:  # the sizes and finiteness are checked in C++ (a ValueError); the checks below only name the culprit
            return self._impl.solve(np.asarray(u0, dtype=float).reshape(-1),
                                    [np.asarray(v, dtype=float).reshape(-1) for v in params],
                                    np.asarray(lam, dtype=float).reshape(-1), bool(record_trace))
        except (ValueError, TypeError):
            self._check(u0, params, lam)
            raise

    def _check(self, u0: Any, params: Sequence[Any], lam: Any) -> None:
        """InvalidInputError naming the first argument of :meth:`solve` of the wrong size or not finite."""
        if len(params) != len(self._param_sizes):
            raise InvalidInputError("params", f"{len(params)} arrays", f"{len(self._param_sizes)} parameter arrays")
        _vector("u0", u0, self.nu)
        for i, (v, n) in enumerate(zip(params, self._param_sizes)):
            _vector(f"params[{i}]", v, n)
        _vector("lam", lam, self.m)
