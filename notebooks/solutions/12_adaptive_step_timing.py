"""Solutions of notebook 12 (adaptive step timing: paper A's MPCC with paper B's step durations)."""

from __future__ import annotations

import math


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
