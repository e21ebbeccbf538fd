"""Solutions of notebook 10 (paper B on the full-body robot)."""

from __future__ import annotations

import math

import numpy as np


def dcm_about_contact(c, v, p, m, zc):
    """ξ (2,) [m, world frame]: the DCM from the angular momentum about the contact point p [m] (lumped mass), c [m] and v [m/s] (3,)."""
    c, v = np.asarray(c, dtype=float), np.asarray(v, dtype=float)
    r = c - np.array([p[0], p[1], 0.0])
    L = m * np.cross(r, v)                      # angular momentum of the lumped mass about the contact point
    lam = math.sqrt(9.81 / zc)
    return c[:2] + np.array([L[1], -L[0]]) / (lam * m * zc)


def count_violations(footholds, step_index, course):
    """Number of footholds (n, 2) [m] on stones whose centre lies outside their stone's rectangle."""
    n = 0
    for p, k in zip(np.asarray(footholds, dtype=float), np.asarray(step_index, dtype=int)):
        if not course.is_stone[k]:
            continue
        half = 0.5 * np.asarray(course.sizes[k], dtype=float)
        if np.any(np.abs(p - np.asarray(course.centers[k], dtype=float)) > half):
            n += 1
    return n
