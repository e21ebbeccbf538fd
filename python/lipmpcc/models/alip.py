"""ALIP model and its divergent component of motion (DCM), paper B §II.

State, in the *stance-contact frame* (origin at the stance foot, axes parallel to the
world axes unless a yaw is given): ``s = [x_c, y_c, L^x, L^y]`` with the COM position
``(x_c, y_c)`` [m] at constant height ``z_c`` and the angular momentum about the contact
point ``L`` [kg m^2/s]::

    x_c' = L^y / (m z_c)        y_c' = -L^x / (m z_c)
    L^x' = -m g y_c - z_c F_y   L^y' =  m g x_c + z_c F_x

``F`` is an optional horizontal force on the COM [N] (a push). The DCM is
``xi = [x_c, y_c] + [L^y, -L^x] / (lambda m z_c)`` with ``lambda = sqrt(g / z_c)``;
without force ``xi' = lambda xi``.

Step-to-step map (touch-down at duration ``T`` on the foothold ``u`` given in the
current contact frame): ``z^k = sigma^k z^{k-1} - u^k`` with ``sigma = exp(lambda T)``
and ``z^k`` the initial DCM of the next step (in the next contact frame).

Sides: a footstep's *side* is that of the swing foot which lands on it, as the sign paper B's
maths needs: ``+1`` for left and ``-1`` for right (:attr:`lipmpcc.conventions.Side.sign`;
:class:`~lipmpcc.conventions.Side` values and the strings ``"left"``/``"right"`` are accepted).
Lateral footholds are ``y_TD = w_{l/r} + W`` with ``w_l = +w`` and ``w_r = -w``.

Height choice: ``z_c = 0.9`` m by default. The reference Digit v3 MJCF (47.9 kg) has its
COM 0.83 m above the foot geoms in its zero posture; Digit walks at about 0.9 m, the
lower end of the 0.9–1.0 m range quoted for it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..conventions import GRAVITY, Side
from ..conventions import parse_side as _side
from ..exceptions import InvalidInputError, ParameterError, StateError
from ..validation import check_field_types, finite_array, finite_number, positive_number
from .lip import omega

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: the sign of a left / right foot (paper B's w_l = +w, w_r = −w)
LEFT: int = Side.LEFT.sign
RIGHT: int = Side.RIGHT.sign

__all__ = [
    "LEFT",
    "RIGHT",
    "AlipParams",
    "KinematicLimits",
    "DcmBounds",
    "parse_side",
    "signed_width",
    "sigma_from_duration",
    "duration_from_sigma",
    "alip_rhs",
    "alip_flow",
    "alip_from_com",
    "com_velocity_from_alip",
    "dcm_from_alip",
    "dcm_from_com",
    "step_to_step",
    "nominal_initial_dcm",
    "viability_bounds",
    "min_forward_dcm_on_stones",
    "world_to_contact",
    "contact_to_world",
]


# ----------------------------------------------------------------------------- parameters
@dataclass(frozen=True)
class AlipParams:
    """Physical constants of the ALIP.

    Attributes:
        mass: total mass m [kg].
        z_c: constant COM height above the contact point [m].
        g: gravity [m/s^2].
    """

    mass: float = 47.9
    z_c: float = 0.9
    g: float = GRAVITY

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        for name, unit in (("mass", "kg"), ("z_c", "m"), ("g", "m/s^2")):
            positive_number(name, getattr(self, name), unit, error=ParameterError)

    @cached_property
    def lam(self) -> float:
        """lambda = sqrt(g / z_c) [1/s]."""
        return omega(self.z_c, self.g)

    @classmethod
    def digit(cls) -> "AlipParams":
        """Digit-like constants (47.9 kg, z_c = 0.9 m)."""
        return cls()


@dataclass(frozen=True)
class KinematicLimits:
    """Reachable footholds relative to the stance foot, in the contact frame (paper B §V).

    ``|x_TD| <= x_max`` and ``y_min <= side * y_TD <= y_max``.

    Attributes:
        x_max: largest forward/backward step [m].
        y_min: smallest lateral distance between the feet [m].
        y_max: largest lateral distance between the feet [m].
    """

    x_max: float = 0.6
    y_min: float = 0.1
    y_max: float = 0.5

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        if self.x_max <= 0:
            raise ParameterError("x_max", self.x_max, "> 0")
        if not 0 <= self.y_min < self.y_max:
            raise ParameterError("y_min, y_max", (self.y_min, self.y_max), "0 <= y_min < y_max")

    def box(self, side: int | str) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper corners of the reachable box for a step of ``side`` [m]."""
        s = parse_side(side)
        lo_y, hi_y = (self.y_min, self.y_max) if s == LEFT else (-self.y_max, -self.y_min)
        return np.array([-self.x_max, lo_y]), np.array([self.x_max, hi_y])

    def contains(self, u: Sequence[float], side: int | str, tol: float = 1e-9) -> bool:
        """True if the relative foothold ``u`` [m] is reachable for a step of ``side``."""
        lo, hi = self.box(side)
        u = np.asarray(u, dtype=float)
        return bool(np.all(u >= lo - tol) and np.all(u <= hi + tol))


@dataclass(frozen=True)
class DcmBounds:
    """Viable initial-DCM intervals [m] (paper B, Proposition and eq. 6).

    Attributes:
        x: (min, max) of the sagittal initial DCM.
        y_left: (min, max) of the lateral initial DCM of a step whose swing foot is left
            (stance right).
        y_right: the same for a right swing (mirror of ``y_left``).
    """

    x: tuple[float, float]
    y_left: tuple[float, float]
    y_right: tuple[float, float]

    def y(self, swing_side: int | str) -> tuple[float, float]:
        """Lateral interval for a step whose swing foot is ``swing_side``."""
        return self.y_left if parse_side(swing_side) == LEFT else self.y_right

    def lower(self, swing_side: int | str) -> np.ndarray:
        """Lower corner (x, y) of the interval for a step whose swing foot is ``swing_side`` [m]."""
        return np.array([self.x[0], self.y(swing_side)[0]])

    def upper(self, swing_side: int | str) -> np.ndarray:
        """Upper corner (x, y) of the interval for a step whose swing foot is ``swing_side`` [m]."""
        return np.array([self.x[1], self.y(swing_side)[1]])

    def contains(self, z: Sequence[float], swing_side: int | str, tol: float = 1e-9) -> bool:
        """True if the initial DCM ``z`` [m] of a step with ``swing_side`` is viable."""
        z = np.asarray(z, dtype=float)
        return bool(
            np.all(z >= self.lower(swing_side) - tol) and np.all(z <= self.upper(swing_side) + tol)
        )

    def margin(self, z: Sequence[float], swing_side: int | str) -> float:
        """Smallest distance [m] from ``z`` to the boundary (negative when outside)."""
        z = np.asarray(z, dtype=float)
        lo, hi = self.lower(swing_side), self.upper(swing_side)
        return float(np.min(np.concatenate([z - lo, hi - z])))


# ----------------------------------------------------------------------------- validation
def parse_side(side: Side | int | str) -> int:
    """The sign of a side: ``"left"``/``Side.LEFT``/``+1`` -> ``+1``, ``"right"``/``Side.RIGHT``/``-1`` -> ``-1``.

    :func:`lipmpcc.conventions.parse_side` then :attr:`~lipmpcc.conventions.Side.sign`.

    Raises:
        InvalidInputError: anything else.
    """
    if type(side) is int and (side == 1 or side == -1):  # the common case, without the enum
        return side
    return _side(side).sign


def _vec(name: str, value: object, n: int, error: type = StateError) -> np.ndarray:
    return finite_array(name, value, (n,), error=error, what=f"a vector of {n} finite numbers")


def _check_params(params: object) -> None:
    if not isinstance(params, AlipParams):
        raise InvalidInputError("params", params, "a lipmpcc.models.alip.AlipParams")


def _pos(name: str, value: object) -> float:
    return positive_number(name, value, error=ParameterError)


def signed_width(side: int | str, w: float) -> float:
    """``w_{l/r}``: ``+w`` for a left swing foot, ``-w`` for a right one [m]."""
    return parse_side(side) * finite_number("w", w, "m", error=ParameterError)


def sigma_from_duration(T: float, lam: float) -> float:
    """sigma = exp(lambda T) for a step of duration ``T`` [s]."""
    T = finite_number("T", T, "s", error=ParameterError)
    if T < 0:
        raise ParameterError("T", T, "a finite duration >= 0 [s]")
    return math.exp(_pos("lam", lam) * T)


def duration_from_sigma(sigma: float, lam: float) -> float:
    """T = ln(sigma) / lambda [s]."""
    s = finite_number("sigma", sigma, error=ParameterError)
    if s < 1.0:
        raise ParameterError("sigma", sigma, "a finite number >= 1")
    return math.log(s) / _pos("lam", lam)


# ----------------------------------------------------------------------------- dynamics
def alip_rhs(state: Sequence[float], params: AlipParams, force: Sequence[float] = (0.0, 0.0)) -> np.ndarray:
    """Time derivative of ``[x_c, y_c, L^x, L^y]`` (eq. 1) with a COM force ``force`` [N]."""
    s = _vec("state", state, 4)
    f = _vec("force", force, 2, InvalidInputError)
    _check_params(params)
    m, zc, g = params.mass, params.z_c, params.g
    return np.array(
        [s[3] / (m * zc), -s[2] / (m * zc), -m * g * s[1] - zc * f[1], m * g * s[0] + zc * f[0]]
    )


def alip_flow(
    state: Sequence[float], t: float, params: AlipParams, force: Sequence[float] = (0.0, 0.0)
) -> np.ndarray:
    """Exact solution of the ALIP after ``t`` [s] under a constant COM force ``force`` [N].

    Per axis the ALIP is ``q'' = lambda^2 q + F/m`` (with ``q' = L^y/(m z_c)`` resp.
    ``-L^x/(m z_c)``), solved in closed form with cosh/sinh.
    """
    s = _vec("state", state, 4)
    f = _vec("force", force, 2, InvalidInputError)
    t = finite_number("t", t, "s")
    if t < 0:
        raise InvalidInputError("t", t, "a finite time >= 0 [s]")
    _check_params(params)
    m, zc, lam = params.mass, params.z_c, params.lam
    ch, sh = math.cosh(lam * t), math.sinh(lam * t)
    out = np.empty(4)
    # x axis: q = x_c, v = L^y/(m zc), offset a = F_x/(m lam^2)
    for q_i, v_sign, L_i, f_i in ((0, 1.0, 3, f[0]), (1, -1.0, 2, f[1])):
        q0 = s[q_i]
        v0 = v_sign * s[L_i] / (m * zc)
        a = f_i / (m * lam**2)
        q = (q0 + a) * ch + v0 / lam * sh - a
        v = (q0 + a) * lam * sh + v0 * ch
        out[q_i] = q
        out[L_i] = v_sign * v * m * zc
    return out


def alip_from_com(
    com_xy: Sequence[float], com_vel_xy: Sequence[float], params: AlipParams
) -> np.ndarray:
    """ALIP state ``[x_c, y_c, L^x, L^y]`` of a point mass at height ``z_c`` [m, m/s].

    ``com_xy`` is relative to the contact point; ``L^x = -m z_c y_c'``, ``L^y = m z_c x_c'``.
    """
    p = _vec("com_xy", com_xy, 2)
    v = _vec("com_vel_xy", com_vel_xy, 2)
    mz = params.mass * params.z_c
    return np.array([p[0], p[1], -mz * v[1], mz * v[0]])


def com_velocity_from_alip(state: Sequence[float], params: AlipParams) -> np.ndarray:
    """COM horizontal velocity [m/s] of an ALIP state."""
    s = _vec("state", state, 4)
    mz = params.mass * params.z_c
    return np.array([s[3] / mz, -s[2] / mz])


def dcm_from_alip(state: Sequence[float], params: AlipParams) -> np.ndarray:
    """DCM (eq. 2) of an ALIP state, in the same frame as ``state`` [m]."""
    s = _vec("state", state, 4)
    k = 1.0 / (params.lam * params.mass * params.z_c)
    return np.array([s[0] + k * s[3], s[1] - k * s[2]])


def dcm_from_com(com_xy: Sequence[float], com_vel_xy: Sequence[float], lam: float) -> np.ndarray:
    """DCM ``xi = c + c'/lambda`` [m] from a COM position and velocity (any frame)."""
    p = _vec("com_xy", com_xy, 2)
    v = _vec("com_vel_xy", com_vel_xy, 2)
    return p + v / _pos("lam", lam)


def step_to_step(z_prev: Sequence[float], sigma: float, u: Sequence[float]) -> np.ndarray:
    """Paper B eq. (8): ``z^k = sigma^k z^{k-1} - u^k`` [m]."""
    z = _vec("z_prev", z_prev, 2)
    uu = _vec("u", u, 2, InvalidInputError)
    s = finite_number("sigma", sigma)
    if s < 1.0:
        raise InvalidInputError("sigma", sigma, "a finite number >= 1")
    return s * z - uu


def nominal_initial_dcm(L: float, W: float, T: float, swing_side: int | str, lam: float, w: float) -> np.ndarray:
    """Initial DCM of a periodic gait, paper B eq. (5) [m].

    The gait repeats footholds ``[L, w_{l/r} + W]`` with duration ``T`` [s]; the result is
    the initial DCM of a step whose swing foot is ``swing_side``:
    ``[L/(e^{lam T}-1), w_{l/r}/(e^{lam T}+1) + W/(e^{lam T}-1)]``.
    """
    for name, v in (("L", L), ("W", W), ("w", w)):
        finite_number(name, v, "m", error=ParameterError)
    T = _pos("T", T)
    sig = math.exp(_pos("lam", lam) * T)
    return np.array([L / (sig - 1.0), signed_width(swing_side, w) / (sig + 1.0) + W / (sig - 1.0)])


def viability_bounds(lam: float, T_min: float, limits: KinematicLimits = KinematicLimits()) -> DcmBounds:
    """Largest invariant intervals of the initial DCM under the step limits (Proposition).

    Sagittal (eq. 6): ``[-x_max, x_max] / (e^{lam T_min} - 1)``. Lateral, for a left swing
    with ``y_min <= u_y <= y_max`` followed by a right swing mirrored: the extreme periodic
    two-step cycles at ``T_min`` give
    ``[(s y_min - y_max)/(s^2 - 1), (s y_max - y_min)/(s^2 - 1)]``, ``s = e^{lam T_min}``.
    Outside these intervals no admissible sequence of steps with ``T >= T_min`` keeps the DCM
    bounded: the robot falls.
    """
    s = math.exp(_pos("lam", lam) * _pos("T_min", T_min))
    x = (-limits.x_max / (s - 1.0), limits.x_max / (s - 1.0))
    a, b = limits.y_min, limits.y_max
    yl = ((s * a - b) / (s * s - 1.0), (s * b - a) / (s * s - 1.0))
    yr = (-yl[1], -yl[0])
    return DcmBounds(x=x, y_left=yl, y_right=yr)


def min_forward_dcm_on_stones(stance_x: float, near_edges: Sequence[float], lam: float, T_max: float) -> float:
    """Least forward initial DCM of the current step from which the robot can still reach every stone ahead [m].

    Along a course whose stones all lie ahead (paper B's profiles, x forward), a DCM behind the stance
    foot (z < 0) runs away backwards while every next foothold is further forward, so ``z^k >= 0`` is
    necessary at every step. By eq. (8), ``z^K = sigma^K ... sigma^1 z^0 - sum_k (prod_{j>k} sigma^j) u^k``:
    it grows with every ``sigma`` (while z >= 0) and falls with every foothold ``x_k`` (the coefficient
    of ``x_k`` is ``(sigma^{k+1} - 1) prod_{j>k+1} sigma^j > 0``). Its best case is therefore the
    longest steps in time, ``sigma = e^{lam T_max}``, onto the near edge of every stone, and the least
    viable ``z^0`` follows backwards from ``z^K = 0``:
    ``z_req = (z_req + e_k - e_{k-1}) / e^{lam T_max}``, ``e_{-1} = stance_x``.
    Below it every planner falls (a necessary condition, whatever the lateral motion).

    Args:
        stance_x: forward position of the stance foot [m].
        near_edges: forward position of the near (rear) edge of each stone still to step on, in order [m].
        lam: ALIP constant λ = √(g/z_c) [1/s].
        T_max: longest step duration [s].
    """
    x0 = float(stance_x)
    if not math.isfinite(x0):
        raise InvalidInputError("stance_x", stance_x, "a finite position [m]")
    e = np.asarray(near_edges, dtype=float)
    if e.ndim != 1 or e.size == 0 or not np.all(np.isfinite(e)):
        raise InvalidInputError("near_edges", near_edges, "a non-empty 1-D sequence of finite positions [m]")
    steps = np.diff(np.concatenate([[x0], e]))
    if np.any(steps < 0.0):
        raise InvalidInputError("near_edges", near_edges, "stones not behind the stance foot, in increasing order")
    sig = math.exp(_pos("lam", lam) * _pos("T_max", T_max))
    z = 0.0
    for u in steps[::-1]:
        z = (z + float(u)) / sig
    return z


# ----------------------------------------------------------------------------- frames
def _rot(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s], [s, c]])


def _points(name: str, value: object) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(name, value, "an (x, y) point or an (n, 2) array [m]") from None
    if a.shape[-1:] != (2,) or a.ndim > 2 or not np.all(np.isfinite(a)):
        raise InvalidInputError(name, value, "an (x, y) point or an (n, 2) array of finite numbers [m]")
    return a


def world_to_contact(p_world: ArrayLike, stance_world: ArrayLike, yaw: float = 0.0) -> np.ndarray:
    """Express world points [m] in the contact frame at ``stance_world`` rotated by ``yaw`` [rad]."""
    p = _points("p_world", p_world)
    o = _vec("stance_world", stance_world, 2, InvalidInputError)
    return (p - o) @ _rot(finite_number("yaw", yaw, "rad"))


def contact_to_world(p_contact: ArrayLike, stance_world: ArrayLike, yaw: float = 0.0) -> np.ndarray:
    """Inverse of :func:`world_to_contact` [m]."""
    p = _points("p_contact", p_contact)
    o = _vec("stance_world", stance_world, 2, InvalidInputError)
    return p @ _rot(finite_number("yaw", yaw, "rad")).T + o
