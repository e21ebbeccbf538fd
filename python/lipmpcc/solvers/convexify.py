"""Convexifications of an SQP's Hessian: a positive definite matrix for the QP subproblem.

The MPCC's Hessian of the Lagrangian is indefinite at every iterate (a concave progress reward, the
obstacles' barrier rows and the path's curvature weighted by their multipliers: on recorded fixed-T
problems its smallest eigenvalue lies between −1.6e6 and −18, its largest up to 7e6). Two ways to
make it positive definite, selected by :class:`~lipmpcc.solvers.condensed_sqp.CondensedSqp`'s
``convexification``:

- ``"eigen_clip"`` (the default, the reference): the symmetric eigendecomposition H = V Λ Vᵀ with the
  eigenvalues raised to at least ``floor`` — the nearest such matrix in the Frobenius norm; O(n³) with a
  large constant (a tridiagonal reduction and QR iterations: half of the C++ SQP's time at n = 20).
- ``"modified_cholesky"``: Gill, Murray and Wright's modified Cholesky factorisation (Practical
  Optimization, 1981, §4.4.2.2; Nocedal & Wright, Numerical Optimization, Algorithm 3.4) without
  pivoting: H + E = L D Lᵀ with E ≥ 0 diagonal, each pivot d_j = max(|c_jj|, θ_j²/β², floor) where c_jj is
  the pivot of the elimination so far, θ_j the largest |c_ij| below it and β² = max(γ, ξ/√(n²−1), ε) (γ, ξ
  the largest diagonal / off-diagonal magnitude of H) bounds the factor's entries (|l_ij|·√d_j ≤ β). One
  Cholesky sweep (n³/6 multiply-adds), and its factor R = √D Lᵀ is handed to DAQP as it is (DAQP's
  ``problem_type`` 2), so DAQP skips its own factorisation. When every pivot of H is at least ``floor``
  (in particular when H's smallest eigenvalue is: the pivots of a positive definite matrix lie between its
  extreme eigenvalues, and |c_ij|² ≤ c_ii c_jj ≤ γ c_jj keeps θ_j²/β² ≤ c_jj), E = 0 and H is unchanged.
  Negative curvature is reflected (|c_jj|) rather than clipped onto ``floor``, so the steps differ from
  the eigenvalue clip's where H is indefinite; a converged iterate is a KKT point either way.

These functions are the readable references of the C++ backend's (``cpp/sqp/src/condensed_sqp.cpp``).
"""

from __future__ import annotations

import math
import os

import numpy as np

from ..exceptions import InvalidInputError

__all__ = ["CONVEXIFICATIONS", "CONVEXIFICATION_ENV", "requested_convexification", "PARTIAL_EIGEN_ENV",
           "requested_partial_eigen", "eigen_clip", "modified_cholesky"]

#: the convexifications of :class:`~lipmpcc.solvers.condensed_sqp.CondensedSqp` (the first is the default)
CONVEXIFICATIONS = ("eigen_clip", "modified_cholesky")
#: environment variable that sets the convexification of every CondensedSqp built without one (e.g. for a study run)
CONVEXIFICATION_ENV = "LIPMPCC_SQP_CONVEXIFICATION"
#: environment variable: "1" makes the C++ SQP's eigenvalue clip the partial one (tridiagonal form, only the
#: eigenvectors below the floor) by default; unset or "0": Eigen's full eigendecomposition (the Python reference's)
PARTIAL_EIGEN_ENV = "LIPMPCC_SQP_PARTIAL_EIGEN"


def requested_partial_eigen(flag: bool | None) -> bool:
    """``flag``, or when None whether ``LIPMPCC_SQP_PARTIAL_EIGEN`` is "1" (default: False, the full
    eigendecomposition). Off by default because the partial clip's rounding-level differences (≤ 2.5e-15
    relative) move chaotic closed loops: Digit v3's Cartesian MPC behind the 0.1 m/s obstacle overtook it with
    the partial clip and trails it with the full one (docs/benchmarks.md)."""
    if flag is not None:
        return bool(flag)
    env = os.environ.get(PARTIAL_EIGEN_ENV, "").strip()
    if env not in ("", "0", "1"):
        raise InvalidInputError(PARTIAL_EIGEN_ENV, env, "0 or 1 (environment variable)")
    return env == "1"


def requested_convexification(name: str | None) -> str:
    """``name``, or when None the value of ``LIPMPCC_SQP_CONVEXIFICATION`` when set, else ``"eigen_clip"``."""
    if name is None:
        env = os.environ.get(CONVEXIFICATION_ENV, "").strip().lower()
        if env and env not in CONVEXIFICATIONS:
            raise InvalidInputError(CONVEXIFICATION_ENV, env, f"one of {', '.join(CONVEXIFICATIONS)} (environment variable)")
        return env or CONVEXIFICATIONS[0]
    if name not in CONVEXIFICATIONS:
        raise InvalidInputError("convexification", name, f"one of {', '.join(CONVEXIFICATIONS)}")
    return name


def eigen_clip(H: np.ndarray, floor: float) -> np.ndarray:
    """H (symmetric, its lower triangle read as numpy's ``eigh`` does) with its eigenvalues raised to at least
    ``floor``: V max(Λ, floor) Vᵀ."""
    w, V = np.linalg.eigh(H)
    return (V * np.maximum(w, floor)) @ V.T


def modified_cholesky(H: np.ndarray, floor: float) -> tuple[np.ndarray, np.ndarray]:
    """Gill–Murray–Wright's modified Cholesky factorisation of the symmetric ``H`` (n × n, its lower triangle
    read) with the pivot floor ``floor`` > 0 (see the module docstring).

    Returns (R, e): R upper triangular with H + diag(e) = RᵀR (R = √D Lᵀ), e ≥ 0 the diagonal added (all zero
    when every pivot of H is at least ``floor``).
    """
    n = H.shape[0]
    A = np.tril(H) + np.tril(H, -1).T  # symmetric from the lower triangle
    diag = np.abs(np.diag(A))
    gamma = float(diag.max(initial=0.0))
    xi = float(np.abs(A - np.diag(np.diag(A))).max(initial=0.0))
    beta2 = max(gamma, xi / math.sqrt(n * n - 1.0) if n > 1 else 0.0, np.finfo(float).eps)
    L = np.zeros((n, n))  # unit lower triangular, its diagonal left zero here
    d = np.zeros(n)
    e = np.zeros(n)
    for j in range(n):
        # column j of the partial elimination: c_ij = a_ij − Σ_{s<j} d_s l_is l_js (i ≥ j)
        c = A[j:, j] - L[j:, :j] @ (d[:j] * L[j, :j])
        theta = float(np.abs(c[1:]).max(initial=0.0))
        d[j] = max(abs(c[0]), theta * theta / beta2, floor)
        e[j] = d[j] - c[0]
        L[j + 1 :, j] = c[1:] / d[j]
    L[np.diag_indices(n)] = 1.0
    R = np.sqrt(d)[:, None] * L.T
    return R, e
