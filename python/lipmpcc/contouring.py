"""Contouring and lag errors (paper A §II-B).

With the Cartesian error e = h(x) − y_d(θ) and the path slope φ = φ_d(θ),

    ē = P(φ) e,   P(φ) = [[ sin φ, −cos φ],
                          [−cos φ, −sin φ]],   ē = [ē_c, ē_l]

ē_c is the (approximate) normal deviation — positive when the robot is to the
*right* of the path direction — and ē_l the (approximate) lag: positive when the
robot is *behind* y_d(θ). P is orthogonal and symmetric (P = Pᵀ = P⁻¹), so

    ‖ē‖²_Q̄ = eᵀ Q e   with   Q = Pᵀ Q̄ P   (paper A eqs. 10–11),

and Q̄ = αI gives Q = αI for every φ: the Cartesian MPC is the MPCC with equal weights.
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca
import numpy as np

from .exceptions import ParameterError
from .validation import finite_array, finite_number

__all__ = ["projection", "casadi_projection", "errors", "casadi_errors", "weight_matrix", "weighted_error"]


def projection(phi: float) -> np.ndarray:
    """P(φ) (2×2) for a path slope φ [rad]."""
    finite_number("phi", phi, "rad", error=ParameterError)
    s, c = np.sin(phi), np.cos(phi)
    return np.array([[s, -c], [-c, -s]])


def casadi_projection(phi: ca.SX | ca.MX) -> ca.SX | ca.MX:
    """P(φ) as a CasADi 2×2 expression."""
    s, c = ca.sin(phi), ca.cos(phi)
    return ca.vertcat(ca.horzcat(s, -c), ca.horzcat(-c, -s))


def errors(position: Sequence[float] | np.ndarray, reference: Sequence[float] | np.ndarray, phi: float | np.ndarray,
           check: bool = True) -> np.ndarray:
    """Contouring and lag errors ē = P(φ)(p − y_d) [m].

    Args:
        position: robot position(s) [m], shape (2,) or (n, 2).
        reference: y_d(θ) [m], same shape.
        phi: path slope(s) φ_d(θ) [rad], scalar or (n,).
        check: validate the arguments (False: the caller's own float arrays of the right shapes, in a
            planner's inner loop, as ``check_finite`` in SciPy).

    Returns:
        [ē_c, ē_l], shape (2,) or (n, 2).

    Raises:
        ParameterError: shapes that differ, or NaN/inf in any argument (with ``check``).
    """
    if not check:
        return _errors(np.asarray(position, dtype=float), np.asarray(reference, dtype=float), np.asarray(phi, dtype=float))
    p = finite_array("position", position, None, "m", error=ParameterError, what="an array of shape (2,) or (n, 2)")
    r = finite_array("reference", reference, None, "m", error=ParameterError, what="an array of shape (2,) or (n, 2)")
    if p.shape != r.shape or p.ndim not in (1, 2) or p.shape[-1] != 2:
        raise ParameterError("position", p.shape, f"the same (…, 2) shape as reference {r.shape}")
    ph = finite_array("phi", phi, None, "rad", error=ParameterError, what="path slopes")
    if ph.shape not in ((), p.shape[:-1]):
        raise ParameterError("phi", ph.shape, f"a scalar or one slope per position (shape {p.shape[:-1]})")
    return _errors(p, r, ph)


def _errors(p: np.ndarray, r: np.ndarray, ph: np.ndarray) -> np.ndarray:
    e = p - r
    s, c = np.sin(ph), np.cos(ph)
    ec = s * e[..., 0] - c * e[..., 1]
    el = -c * e[..., 0] - s * e[..., 1]
    out = np.empty(ec.shape + (2,))  # np.stack([ec, el], axis=-1), without its overhead (planners' loops)
    out[..., 0], out[..., 1] = ec, el
    return out


def casadi_errors(position: ca.SX | ca.MX, reference: ca.SX | ca.MX, phi: ca.SX | ca.MX) -> ca.SX | ca.MX:
    """ē = P(φ)(p − y_d) as a CasADi 2-vector."""
    return ca.mtimes(casadi_projection(phi), position - reference)


def _diag_weights(name: str, w: Sequence[float] | np.ndarray) -> np.ndarray:
    a = np.asarray(w, dtype=float)
    if a.shape == (2, 2):
        if abs(a[0, 1]) > 0 or abs(a[1, 0]) > 0:
            raise ParameterError(name, a.tolist(), "a diagonal 2×2 matrix diag(contouring, lag)")
        a = np.diag(a)
    if a.shape != (2,) or not np.all(np.isfinite(a)) or np.any(a < 0):
        raise ParameterError(name, w, "two non-negative finite weights (contouring, lag)")
    return a


def weight_matrix(weights_bar: Sequence[float] | np.ndarray, phi: float) -> np.ndarray:
    """Q = P(φ)ᵀ diag(weights_bar) P(φ) (paper A eqs. 10–11).

    Args:
        weights_bar: (α_contouring, α_lag) or a diagonal 2×2 Q̄.
        phi: path slope [rad].
    """
    if isinstance(weights_bar, (str, bytes)):
        raise ParameterError("weights_bar", weights_bar, "two non-negative finite weights (contouring, lag)")
    try:
        qb = np.diag(_diag_weights("weights_bar", weights_bar))
    except (TypeError, ValueError) as err:
        if isinstance(err, ParameterError):
            raise
        raise ParameterError("weights_bar", weights_bar, "two non-negative finite weights (contouring, lag)") from None
    P = projection(phi)
    return P.T @ qb @ P


def weighted_error(
    position: Sequence[float] | np.ndarray,
    reference: Sequence[float] | np.ndarray,
    phi: float,
    weights_bar: Sequence[float] | np.ndarray,
) -> float:
    """‖ē‖²_Q̄ = eᵀ Q e for one sample."""
    p = finite_array("position", position, (2,), "m", error=ParameterError)
    r = finite_array("reference", reference, (2,), "m", error=ParameterError)
    e = p - r
    return float(e @ weight_matrix(weights_bar, finite_number("phi", phi, "rad", error=ParameterError)) @ e)
