"""The linear inverted pendulum (LIP): ω, its closed-form flow and the DCM — the one copy.

c̈ = ω² (c − p) with a fixed pivot p (the stance foot, or a centre of pressure), ω = √(g/H).
Every layer that needs the LIP (the 3D-LIP step-to-step model, the ALIP, the COM reference of the
full-body loop, the capture-point planner, the reduced loops) takes it from here.
"""

from __future__ import annotations

import math

import numpy as np

from ..conventions import GRAVITY
from ..exceptions import InvalidInputError, ParameterError
from ..validation import finite_array, finite_number, positive_number

__all__ = ["GRAVITY", "STEP_DURATION", "omega", "lip_solution", "dcm"]

#: paper A's step duration T [s]: the default of the 3D-LIP model and of the capture-point planner
STEP_DURATION = 0.4


def omega(com_height: float, gravity: float = GRAVITY) -> float:
    """LIP natural frequency ω = √(g/H) [1/s] for a COM height H [m] and gravity g [m/s²]."""
    try:
        h = float(com_height)
    except (TypeError, ValueError):
        raise InvalidInputError("com_height", com_height, "a finite number") from None
    if not math.isfinite(h):
        raise InvalidInputError("com_height", com_height, "a finite number")
    if h <= 0.0:
        raise ParameterError("com_height", com_height, "a positive height in metres")
    positive_number("gravity", gravity, "m/s^2", error=ParameterError)
    return math.sqrt(gravity / h)


def lip_solution(
    c0: np.ndarray, v0: np.ndarray, p: np.ndarray, omega: float, t: float | np.ndarray, check: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closed-form solution of the LIP c̈ = ω²(c − p) with a fixed pivot p.

    Args:
        c0: initial horizontal COM position (2,) [m].
        v0: initial horizontal COM velocity (2,) [m/s].
        p: pivot (stance foot / CoP) position (2,) [m].
        omega: ω = √(g/H) [1/s].
        t: elapsed time(s) since the initial state [s]; scalar or (n,).
        check: validate the arguments (False: the caller's own float arrays (2,) and finite numbers, in a
            simulation's inner loop, as ``check_finite`` in SciPy; the same numbers).

    Returns:
        ``(c, ċ, c̈)`` each (2,) for scalar ``t`` or (n, 2) [m, m/s, m/s²].
    """
    if check:
        c0 = finite_array("c0", c0, (2,), "m", finite=False)
        v0 = finite_array("v0", v0, (2,), "m/s", finite=False)
        p = finite_array("p", p, (2,), "m", finite=False)
        tt = finite_array("t", t, None, "s")
        finite_number("omega", omega, "1/s")
    else:
        tt = t
    if np.ndim(tt):
        ch, sh = np.cosh(omega * tt)[..., None], np.sinh(omega * tt)[..., None]
    else:
        ch, sh = math.cosh(omega * float(tt)), math.sinh(omega * float(tt))
    d0 = c0 - p
    c = p + d0 * ch + v0 * sh / omega
    v = d0 * omega * sh + v0 * ch
    a = omega**2 * (c - p)
    return c, v, a


def dcm(com_xy: np.ndarray, com_vel_xy: np.ndarray, omega: float) -> np.ndarray:
    """Divergent component of motion ξ = c + ċ/ω (2,) [m] (the instantaneous capture point)."""
    c = finite_array("com_xy", com_xy, (None,), "m", finite=False)
    v = finite_array("com_vel_xy", com_vel_xy, (None,), "m/s", finite=False)
    if c.size < 2 or v.size < 2:
        raise InvalidInputError("com_xy/com_vel_xy", (com_xy, com_vel_xy), "vectors of at least (x, y)")
    return c[:2] + v[:2] / finite_number("omega", omega, "1/s")
