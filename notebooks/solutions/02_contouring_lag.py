"""Solutions of the exercises of notebook 02_contouring_lag."""

from __future__ import annotations

import numpy as np


def contouring_lag(p, yd, phi):
    """(ē_c, ē_l) [m] of the robot at p = [x, y] [m] for the reference point yd [m] with path slope phi [rad].

    ē_c = −nᵀe (positive to the right), ē_l = −tᵀe (positive behind), e = p − yd.
    """
    e = np.asarray(p, dtype=float) - np.asarray(yd, dtype=float)
    t = np.array([np.cos(phi), np.sin(phi)])
    n = np.array([-np.sin(phi), np.cos(phi)])
    return np.array([-n @ e, -t @ e])


def true_errors(path, p, theta_k):
    """(e_c, e_l) [m]: the true contouring and lag errors of the robot at p [m] for the path parameter theta_k [m]."""
    p = np.asarray(p, dtype=float)
    th_star = path.closest_point(p)
    phi = path.slope(th_star)
    n = np.array([-np.sin(phi), np.cos(phi)])
    e_c = -float(n @ (p - path.position(th_star)))
    return e_c, float(theta_k - th_star)
