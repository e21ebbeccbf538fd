"""Solutions of the exercises of notebook 03_lip_mpcc."""

from __future__ import annotations

import math

import numpy as np


def lip_matrices(T, H, g=9.81):
    """(A (5, 5), B (5, 3)) of the 3D-LIP step-to-step map for step duration T [s], COM height H [m], gravity g [m/s²].

    Per axis, x(T) = x + uˣ (1 − cosh ωT) + ẋ sinh(ωT)/ω and ẋ(T) = ẋ cosh ωT − uˣ ω sinh ωT; the heading
    adds its change: θ⁺ = θ + u^θ.
    """
    w = math.sqrt(g / H)
    ch, sh = math.cosh(w * T), math.sinh(w * T)
    A1 = np.array([[1.0, sh / w], [0.0, ch]])
    b1 = np.array([1.0 - ch, -w * sh])
    A = np.zeros((5, 5))
    B = np.zeros((5, 3))
    A[0:2, 0:2] = A1
    A[2:4, 2:4] = A1
    A[4, 4] = 1.0
    B[0:2, 0] = b1
    B[2:4, 1] = b1
    B[4, 2] = 1.0
    return A, B


def best_progress(alpha, rho, c, v_max):
    """argmin over v ∈ [0, v_max] [m] of alpha (c − v)² − rho v² (alpha, rho ≥ 0; c [m])."""
    f = lambda v: alpha * (c - v) ** 2 - rho * v**2
    if alpha > rho:  # convex: the stationary point f'(v) = −2α(c − v) − 2ρv = 0, clipped
        return min(max(alpha * c / (alpha - rho), 0.0), v_max)
    return 0.0 if f(0.0) <= f(v_max) else v_max  # concave or linear: an end of the interval


def contouring_lag_cost(position, path_point, phi, q_bar):
    """Paper A eqs. (8)-(11): e = P(phi)(C x - y_d) with P = [[sin, -cos], [-cos, -sin]], and the stage's
    tracking cost q_c e_c^2 + q_l e_l^2; CasADi expressions (cost, e_c [m], e_l [m])."""
    import casadi as ca

    dx, dy = position[0] - path_point[0], position[1] - path_point[1]
    s, c = ca.sin(phi), ca.cos(phi)
    e_c = s * dx - c * dy
    e_l = -c * dx - s * dy
    return q_bar[0] * e_c**2 + q_bar[1] * e_l**2, e_c, e_l
