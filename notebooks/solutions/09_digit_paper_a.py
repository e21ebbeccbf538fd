"""Solutions of notebook 09 (paper A on the full-body robot)."""

from __future__ import annotations

import numpy as np

from lipmpcc.contouring import errors


def exchange_state(c, v, p, omega, tau):
    """(c_T, v_T): COM position [m] and velocity [m/s] tau [s] ahead on the LIP about the foot p [m] (all (2,))."""
    c, v, p = (np.asarray(a, dtype=float) for a in (c, v, p))
    ch, sh = np.cosh(omega * tau), np.sinh(omega * tau)
    return p + (c - p) * ch + v * sh / omega, (c - p) * omega * sh + v * ch


def touchdown_contouring(path, tc, com_xy, t_td):
    """ē_c [m] of the COM at each touch-down time t_td [s], from the COM (m, 2) [m] logged at times tc (m,) [s]."""
    tc, com_xy = np.asarray(tc, dtype=float), np.asarray(com_xy, dtype=float)
    idx = np.clip(np.searchsorted(tc, np.asarray(t_td, dtype=float)), 0, len(tc) - 1)
    pos = com_xy[idx]
    theta, prev = np.empty(len(pos)), 0.0
    for i, p in enumerate(pos):  # eq. 19, each search near the previous closest point
        prev = path.closest_point(p, theta_prev=prev)
        theta[i] = prev
    return errors(pos, path.position(theta), path.slope(theta))[:, 0]

