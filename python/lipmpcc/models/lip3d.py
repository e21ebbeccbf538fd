"""Step-to-step 3D linear inverted pendulum with heading (paper A §III-A, SPEC §1).

State at the start of step k:  x_k = [x, ẋ, y, ẏ, θ_h]  ([m], [m/s], [m], [m/s], [rad])
Input:                           u_k = [uˣ, uʸ, u^θ]       ([m], [m], [rad])

uˣ, uʸ place the new stance foot relative to the point mass, p = (x_k + uˣ, y_k + uʸ);
u^θ changes the heading at the support exchange. During the step the mass obeys
ẍ = ω²(x − pₓ), ω = √(g/H), so after a step of duration T

    x_{k+1} = x_k + ẋ_k sinh(ωT)/ω + uˣ(1 − cosh ωT)
    ẋ_{k+1} = ẋ_k cosh ωT − uˣ ω sinh ωT                (same for y)
    θ_{k+1} = θ_k + u^θ

i.e. x_{k+1} = A x_k + B u_k and y_k = C x_k = [x, y].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ..conventions import GRAVITY
from ..exceptions import ParameterError, StateError
from ..validation import check_field_types, finite_array, finite_vector, positive_number
from .lip import STEP_DURATION, omega

if TYPE_CHECKING:
    import control

__all__ = ["Lip3dModel", "ReachabilityRectangle", "check_state"]


def __getattr__(name: str) -> object:
    if name == "G":  # the old module constant
        import warnings

        warnings.warn("lipmpcc.models.lip3d.G is deprecated: use lipmpcc.conventions.GRAVITY; removed in lipmpcc 0.3", DeprecationWarning, stacklevel=2)
        return GRAVITY
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _check_positive(name: str, v: float) -> float:
    return positive_number(name, v, error=ParameterError)


@dataclass(frozen=True)
class Lip3dModel:
    """Step-to-step 3D-LIP.

    Attributes:
        T: step duration [s].
        H: height of the point mass [m].
        g: gravity [m/s²].
    """

    T: float = STEP_DURATION
    H: float = 0.9
    g: float = GRAVITY

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        _check_positive("T", self.T)
        _check_positive("H", self.H)
        _check_positive("g", self.g)

    @cached_property
    def omega(self) -> float:
        """ω = √(g/H) [1/s]."""
        return omega(self.H, self.g)

    @property
    def A(self) -> np.ndarray:
        """The step-to-step state matrix (5, 5)."""
        w, T = self.omega, self.T
        ch, sh = math.cosh(w * T), math.sinh(w * T)
        blk = np.array([[1.0, sh / w], [0.0, ch]])
        A = np.zeros((5, 5))
        A[0:2, 0:2] = blk
        A[2:4, 2:4] = blk
        A[4, 4] = 1.0
        return A

    @property
    def B(self) -> np.ndarray:
        """The step-to-step input matrix (5, 3)."""
        w, T = self.omega, self.T
        ch, sh = math.cosh(w * T), math.sinh(w * T)
        B = np.zeros((5, 3))
        B[0, 0] = 1.0 - ch
        B[1, 0] = -w * sh
        B[2, 1] = 1.0 - ch
        B[3, 1] = -w * sh
        B[4, 2] = 1.0
        return B

    @property
    def C(self) -> np.ndarray:
        """The output matrix (2, 5): y = [x, y]."""
        C = np.zeros((2, 5))
        C[0, 0] = 1.0
        C[1, 2] = 1.0
        return C

    def step(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """x_{k+1} = A x_k + B u_k."""
        x = check_state(x)
        u = _check_input(u)
        return self.A @ x + self.B @ u

    def com_trajectory(self, x: np.ndarray, u: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Continuous COM states within the step started at x with input u.

        Args:
            x: state at the start of the step.
            u: input of the step.
            t: times since the start of the step [s], shape (n,).

        Returns:
            (n, 4) array of [x, ẋ, y, ẏ].
        """
        x = check_state(x)
        u = _check_input(u)
        t = finite_array("t", t, None, "s", error=StateError)
        w = self.omega
        # inline rather than models.lip.lip_solution: here the pivot offset is −u exactly, where
        # lip_solution's c0 − p = x − (x + u) would round differently
        ch, sh = np.cosh(w * t), np.sinh(w * t)
        out = np.empty((t.size, 4))
        for i, (pi, vi, ui) in enumerate(((0, 1, 0), (2, 3, 1))):
            r0 = -u[ui]
            v0 = x[vi]
            out[:, 2 * i] = x[pi] + u[ui] + r0 * ch + v0 * sh / w
            out[:, 2 * i + 1] = r0 * w * sh + v0 * ch
        return out

    def ss(self) -> "control.StateSpace":
        """The step-to-step map as a discrete-time ``control.StateSpace`` (dt = T)
        with outputs y = C x, for analysis with python-control."""
        import control

        return control.ss(self.A, self.B, self.C, np.zeros((2, 3)), self.T)

    def periodic_velocity(self, step_length: float) -> float:
        """Speed at the start of a step of a symmetric periodic gait whose mass travels
        ``step_length`` [m] per step (foot at mid-step): ẋ₀ = (d/2) ω coth(ωT/2) ... [m/s]."""
        w, T = self.omega, self.T
        return 0.5 * step_length * w * math.sinh(w * T) / (math.cosh(w * T) - 1.0)


def check_state(x: np.ndarray) -> np.ndarray:
    """Validate a 3D-LIP state (finite 5-vector)."""
    return finite_array("x", x, (5,), error=StateError, what="a 5-vector [x, xdot, y, ydot, heading]")


def _check_input(u: np.ndarray) -> np.ndarray:
    """Validate a 3D-LIP input (finite 3-vector)."""
    return finite_array("u", u, (3,), error=StateError, what="a 3-vector [ux, uy, u_theta]")


@dataclass(frozen=True)
class ReachabilityRectangle:
    """Foot placement bounds in the new heading frame (paper A eq. 15).

    The foot offset u = [uˣ, uʸ] rotated into the frame of heading θ_k + u^θ must lie in
    ``forward`` × ``lateral`` where the lateral interval is ``(inner, outer)`` to the stance
    side: [inner, outer] for a left stance foot, [−outer, −inner] for a right one.

    Attributes:
        forward: (min, max) forward offset [m].
        lateral: (inner, outer) lateral offset to the stance side [m]; inner may be negative
            (crossing over).
        heading: (min, max) heading change u^θ per step [rad].
    """

    forward: tuple[float, float] = (-0.35, 0.35)
    lateral: tuple[float, float] = (0.05, 0.35)
    heading: tuple[float, float] = (-0.3, 0.3)

    def __post_init__(self) -> None:
        for name in ("forward", "lateral", "heading"):
            lo, hi = finite_vector(name, getattr(self, name), 2, error=ParameterError)
            if lo >= hi:
                raise ParameterError(name, (lo, hi), "finite (min, max) with min < max")
        if self.lateral[1] <= 0:
            raise ParameterError("lateral", self.lateral, "an outer bound > 0 [m]")

    def bounds(self, side: int) -> tuple[np.ndarray, np.ndarray]:
        """(lb, ub) of [uˣ_local, uʸ_local, u^θ] for a stance foot on ``side`` (+1 left, −1 right)."""
        if side not in (1, -1):
            raise ParameterError("side", side, "+1 (left stance) or -1 (right stance)")
        inner, outer = self.lateral
        lat = (inner, outer) if side == 1 else (-outer, -inner)
        lb = np.array([self.forward[0], lat[0], self.heading[0]])
        ub = np.array([self.forward[1], lat[1], self.heading[1]])
        return lb, ub

    def contains(self, u: np.ndarray, heading_new: float, side: int, tol: float = 1e-6) -> bool:
        """True when input u lies in the rectangle for the new heading [rad] and side."""
        c, s = math.cos(heading_new), math.sin(heading_new)
        local = np.array([c * u[0] + s * u[1], -s * u[0] + c * u[1], u[2]])
        lb, ub = self.bounds(side)
        return bool(np.all(local >= lb - tol) and np.all(local <= ub + tol))
