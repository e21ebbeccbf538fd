"""Solutions of notebook 13_stone_field.ipynb (a path across a stone field with a pedestrian)."""

from __future__ import annotations

import numpy as np


def one_stone_rows(centers, half_sizes, big_m):
    """The big-M rows A @ [u_x, u_y, z_1..z_m] <= b of one footstep.

    Stone j (centre c_j, half size h_j): +-(u - c_j) <= h_j + M (1 - z_j) per axis, i.e.
    +-u + M z_j <= +-c_j + h_j + M: four rows, active (the foot on the stone) when z_j = 1 and
    relaxed by M when z_j = 0. Exactly one stone: sum z <= 1 and -sum z <= -1.
    """
    c = np.asarray(centers, dtype=float)
    h = np.asarray(half_sizes, dtype=float)
    m = len(c)
    A, b = [], []
    for j in range(m):
        for axis in (0, 1):
            for sign in (1.0, -1.0):
                row = np.zeros(2 + m)
                row[axis] = sign
                row[2 + j] = big_m
                A.append(row)
                b.append(sign * c[j, axis] + h[j, axis] + big_m)
    ones = np.r_[0.0, 0.0, np.ones(m)]
    A += [ones, -ones]
    b += [1.0, -1.0]
    return np.array(A), np.array(b)
