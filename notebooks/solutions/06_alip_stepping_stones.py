"""Solutions of notebook 06_alip_stepping_stones.ipynb (ALIP stepping stones)."""

from __future__ import annotations

import math

import numpy as np


def push_dcm_shift(force, t_a, t_b, params):
    """Delta z^0 = F / (m lam^2) (e^{-lam t_a} - e^{-lam t_b}) [m].

    The DCM obeys xi' = lam xi + F / (m lam) while the force acts; the shift at t_b,
    F / (m lam^2) (e^{lam (t_b - t_a)} - 1), taken back to t = 0 by e^{-lam t_b}.
    """
    lam, m = params.lam, params.mass
    k = (math.exp(-lam * t_a) - math.exp(-lam * t_b)) / (m * lam**2)
    return k * np.asarray(force, dtype=float)


def fatal_backward_force(z0_x, z_req, t_a, t_b, params):
    """F* [N] with z0_x - F* (e^{-lam t_a} - e^{-lam t_b}) / (m lam^2) = z_req."""
    lam, m = params.lam, params.mass
    k = (math.exp(-lam * t_a) - math.exp(-lam * t_b)) / (m * lam**2)
    return (z0_x - z_req) / k


def touchdown_dcm(xi_now, t, sigma, d, lam):
    """xi_TD = d + sigma e^{-lam t} (xi_now - d) [m], relative to the stance contact point.

    For the rest of the step the DCM diverges from the pivot d: (xi - d)' = lam (xi - d), so over the
    remaining T - t it grows by e^{lam (T - t)} = sigma e^{-lam t} (sigma = e^{lam T}). CasADi expressions
    in, a CasADi 2-vector out (ca.exp works on numbers and symbols alike).
    """
    import casadi as ca

    return d + sigma * ca.exp(-lam * t) * (xi_now - d)
