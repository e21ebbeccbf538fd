"""Solutions of the exercises of notebook 01_path_parametrisation."""

from __future__ import annotations

import numpy as np


def closest_on_arc(path, p, theta0):
    """ϑ* [m]: the closest point of `path` to the point p = [x, y] [m], by Newton's method from theta0 [m].

    f(ϑ) = <y_d(ϑ) − p, t(ϑ)>, f'(ϑ) = 1 + κ(ϑ) <y_d(ϑ) − p, n(ϑ)> (arc length: dt/dϑ = κ n).
    """
    p = np.asarray(p, dtype=float)
    th = float(theta0)
    for _ in range(50):
        r = path.position(th) - p
        t = path.tangent(th)
        n = np.array([-t[1], t[0]])
        f = float(r @ t)
        df = 1.0 + float(path.curvature(th)) * float(r @ n)
        step = f / df
        th -= step
        if abs(step) < 1e-12:
            break
    return th


def slope_and_curvature(path, theta, h=1e-3):
    """(φ_d [rad], κ [1/m]) at the path parameters theta [m], by central differences of path.position."""
    theta = np.asarray(theta, dtype=float)
    y0, yp, ym = path.position(theta), path.position(theta + h), path.position(theta - h)
    d1 = (yp - ym) / (2 * h)
    d2 = (yp - 2 * y0 + ym) / h**2
    phi = np.arctan2(d1[:, 1], d1[:, 0])
    kappa = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    return phi, kappa
