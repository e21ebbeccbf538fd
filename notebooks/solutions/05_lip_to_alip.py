"""Solutions of notebook 05_lip_to_alip.ipynb (From the LIP to the ALIP)."""

from __future__ import annotations

import math


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
