"""Solutions of notebook 07_robot_walking.ipynb (the robot, and walking without an MPC)."""

import math

import numpy as np

GRAVITY = 9.81  # [m/s²]


def touchdown_times(t, fz, threshold, min_air):
    """Landing times [s]: the first sample above ``threshold`` [N] after at least ``min_air`` [s] at or below it."""
    t = np.asarray(t, dtype=float)
    fz = np.asarray(fz, dtype=float)
    out = []
    air_since = None  # when the foot last left the ground (None: on the ground)
    for tk, fk in zip(t, fz):
        if fk <= threshold:
            if air_since is None:
                air_since = tk
        else:
            if air_since is not None and tk - air_since >= min_air:
                out.append(tk)
            air_since = None
    return np.array(out)


def capture_point_step(dcm_xy, stance_xy, omega, T, step_length, step_width, swing_left, yaw):
    """p_next = ξ_end − R(ψ) b at the start of a step of duration T [s]."""
    stance = np.asarray(stance_xy, dtype=float)
    xi_end = stance + (np.asarray(dcm_xy, dtype=float) - stance) * math.exp(omega * T)
    sigma = math.exp(omega * T)
    s = 1.0 if swing_left else -1.0
    b = np.array([step_length / (sigma - 1.0), -s * step_width / (sigma + 1.0)])
    c, sn = math.cos(yaw), math.sin(yaw)
    return xi_end - np.array([[c, -sn], [sn, c]]) @ b
