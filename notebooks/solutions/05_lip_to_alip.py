"""Solutions of notebook 05_lip_to_alip.ipynb (From the LIP to the ALIP)."""

from __future__ import annotations

import math

import numpy as np


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


def step_map(z_prev, sigma, u):
    """Paper B eq. (8): z^k = sigma^k z^{k-1} - u^k [m] (2,)."""
    return sigma * np.asarray(z_prev, dtype=float) - np.asarray(u, dtype=float)


def sigma_bounds(lam, T_lo, T_hi):
    """(e^{lam T_lo}, e^{lam T_hi}): sigma = e^{lam T} increases with T."""
    return math.exp(lam * T_lo), math.exp(lam * T_hi)


def stone_box(u_nom, size, kin_lo, kin_hi):
    """The stone's rectangle (centre u_nom, sides size) [m] cut by the kinematic box; where they do not
    overlap on an axis, the kinematic bound nearest to the stone for both."""
    u_nom, half = np.asarray(u_nom, dtype=float), 0.5 * np.asarray(size, dtype=float)
    lo = np.maximum(u_nom - half, kin_lo)
    hi = np.minimum(u_nom + half, kin_hi)
    empty = lo > hi
    nearest = np.clip(u_nom, kin_lo, kin_hi)
    return np.where(empty, nearest, lo), np.where(empty, nearest, hi)
