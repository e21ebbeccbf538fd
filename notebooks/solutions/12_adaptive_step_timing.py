"""Solutions of notebook 12 (adaptive step timing: paper A's MPCC with paper B's step durations)."""

from __future__ import annotations

import math

import numpy as np


def timed_A_B(T, omega):
    """(A, B): the 3D-LIP step matrices (5, 5) and (5, 3) for a step of duration T [s], ω [1/s]."""
    ch, sh = math.cosh(omega * T), math.sinh(omega * T)
    A, B = np.zeros((5, 5)), np.zeros((5, 3))
    for i in (0, 1):                               # x then y: rows/columns 2i, 2i + 1
        A[2 * i : 2 * i + 2, 2 * i : 2 * i + 2] = [[1.0, sh / omega], [0.0, ch]]
        B[2 * i, i], B[2 * i + 1, i] = 1.0 - ch, -omega * sh
    A[4, 4], B[4, 2] = 1.0, 1.0                    # heading: θ⁺ = θ + u^θ
    return A, B


def top_speed(v_max, T_min):
    """The top average path speed [m/s] of steps advancing at most v_max [m] and lasting at least T_min [s]."""
    return v_max / T_min


def dcm_offset(t, xi0, omega, force, mass, t_on, t_off):
    """ξ(t) − p [m] at t [s] after touch-down, from ξ(0) − p = xi0 [m], under force [N] on mass [kg] over [t_on, t_off) [s]."""
    xi = float(xi0)
    for a, b, f in ((0.0, t_on, 0.0), (t_on, t_off, force), (t_off, math.inf, 0.0)):
        if t <= a:
            break
        shift = f / (mass * omega**2)              # the force moves the LIP's pivot by −F/(mω²)
        xi = (xi + shift) * math.exp(omega * (min(t, b) - a)) - shift
    return xi


def ends_sooner(force_x):
    """True when a push of force_x [N] (walking along +x) should end the step sooner than unpushed.

    A forward push adds F/(mω) > 0 to ξ̇: the DCM runs ahead and reaches its end-of-step value sooner.
    """
    return force_x > 0.0
