"""Solutions of notebook 05_lip_to_alip.ipynb (From the LIP to the ALIP)."""

from __future__ import annotations

import math

import numpy as np

from lipmpcc.conventions import GRAVITY


def dcm_from_lip_state(com_xy, com_vel_xy, H, g=GRAVITY):
    """DCM xi = c + c'/omega [m] of a point mass at height H [m], omega = sqrt(g/H)."""
    w = math.sqrt(g / H)
    return np.asarray(com_xy, dtype=float) + np.asarray(com_vel_xy, dtype=float) / w


def lip_step_matrices(T, H, g=GRAVITY):
    """One axis of the step-to-step LIP: x'' = w^2 (x - p), p = x_k + u, over a step of T [s].

    x(t) = p + (x_k - p) cosh(wt) + x'_k sinh(wt)/w with x_k - p = -u, so
    x_{k+1} = x_k + x'_k sinh(wT)/w + u (1 - cosh wT) and x'_{k+1} = x'_k cosh wT - u w sinh wT.
    """
    w = math.sqrt(g / H)
    ch, sh = math.cosh(w * T), math.sinh(w * T)
    A1 = np.array([[1.0, sh / w], [0.0, ch]])
    B1 = np.array([1.0 - ch, -w * sh])
    return A1, B1


def sagittal_viability_bound(x_max, lam, T_min):
    """Paper B eq. (6): [-x_max, x_max] / (e^{lam T_min} - 1) [m]."""
    d = math.exp(lam * T_min) - 1.0
    return -x_max / d, x_max / d


def least_forward_dcm(stance_x, near_edges, lam, T_max):
    """Backward recursion z <- (z + (e_k - e_{k-1})) / e^{lam T_max} from z = 0 [m]."""
    sigma = math.exp(lam * T_max)
    points = [float(stance_x), *map(float, near_edges)]
    z = 0.0
    for a, b in reversed(list(zip(points[:-1], points[1:]))):
        z = (z + (b - a)) / sigma
    return z
