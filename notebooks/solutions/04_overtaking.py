"""Solutions of the exercises of notebook 04_overtaking."""

from __future__ import annotations

import math

import numpy as np


def approach_steps(d0, d, R, gamma):
    """Steps k [-] (real) for the COM–obstacle distance to shrink from d0 to d [m] when b_(k+1) = (1 − γ) b_k, b = d²/R² − 1.

    (1 − γ)^k b0 = b  ⇒  k = ln(b / b0) / ln(1 − γ).
    """
    b0 = d0**2 / R**2 - 1.0
    b = d**2 / R**2 - 1.0
    return math.log(b / b0) / math.log(1.0 - gamma)


def ellipse_barrier(p, c, axes, psi, inflate):
    """b(p) [-] of the ellipse centred at c [m] with semi-axes axes = (a, b) [m] turned by psi [rad], grown by inflate [m]."""
    a, b = axes[0] + inflate, axes[1] + inflate
    rot = np.array([[math.cos(psi), -math.sin(psi)], [math.sin(psi), math.cos(psi)]])
    M = rot @ np.diag([1.0 / a**2, 1.0 / b**2]) @ rot.T
    e = np.asarray(p, dtype=float) - np.asarray(c, dtype=float)
    return float(e @ M @ e - 1.0)


def cbf_row(p_now, p_next, ob_now, ob_next, gamma):
    """Paper A's CBF (17), time-indexed: b_{k+1}(p_{k+1}) - (1 - gamma) b_k(p_k), with
    b(p) = (p - c)^T M (p - c) - 1 and ob = [c_x, c_y, m_11, m_12, m_22]; a CasADi expression (>= 0 when safe)."""

    def barrier(p, ob):
        dx, dy = p[0] - ob[0], p[1] - ob[1]
        return ob[2] * dx * dx + 2 * ob[3] * dx * dy + ob[4] * dy * dy - 1

    return barrier(p_next, ob_next) - (1 - gamma) * barrier(p_now, ob_now)
