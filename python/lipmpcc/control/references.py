"""The walking references a whole-body controller tracks: COM, swing foot, torso heading, step phase.

Between the footholds a planner chooses, this module interpolates:

- the **horizontal COM** along the LIP solution about the stance foot, at constant height
  (:class:`LipComReference`; the LIP itself is :mod:`lipmpcc.models.lip`);
- a **COM shift** in double support (a quintic, :class:`Quintic`);
- the **swing foot**: a polynomial in the step phase τ from its lift-off pose to the foothold, with
  an apex height at mid-phase, landing exactly at the foothold with zero velocity at τ = 1;
- the **torso heading**: upright, yawing from its lift-off heading to the planned heading by τ = 1.

The phase τ(t) (:class:`~lipmpcc.models.phase.PhaseClock`) is re-timed when the planned step
duration changes mid-swing, as in SPEC §2 (paper B eqs. 12–13):

    τ(t) = τ^i + (1 − τ^i)(t − t^i)/(T_des − t^i),   τ̇ = (1 − τ^i)/(T_des − t^i),

so τ stays continuous and reaches 1 exactly at the latest desired end time T_des.

Footholds, headings and end times that change during the swing are **blended**: the reference is a
nominal polynomial in τ towards the latest target plus a correction δ(t), a quintic in time that
starts with the difference (position, velocity, acceleration) between the old reference and the new
nominal at the instant of the change and vanishes, with zero velocity and acceleration, at the new end
time. Position, velocity and acceleration of the reference are therefore continuous across every
change, and the foot still lands exactly at the (latest) foothold with zero velocity at τ = 1.

Units: positions [m], times [s], angles [rad], rates [rad/s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..conventions import GRAVITY
from ..exceptions import InvalidInputError, ParameterError, StateError
from ..validation import check_field_types, finite_number
from ..models.lip import omega
from ..models.phase import PhaseClock
from ..rotations import unwrap_near

_F64 = np.dtype(np.float64)  # the float64 descriptor (``a.dtype is _F64`` is a fast exact-type test)

__all__ = [
    "LipComReference",
    "Quintic",
    "smoothstep5",
    "apex_bump",
    "SwingParams",
    "StepReference",
    "StepTrajectory",
]


# --------------------------------------------------------------------------------------------
# Helpers
# --------------------------------------------------------------------------------------------
def _vec(name: str, value: object, n: int) -> np.ndarray:
    """A copy of ``value`` as a float64 vector (n,), or StateError naming ``name`` (wrong shape, not finite)."""
    if type(value) is np.ndarray and value.dtype is _F64 and value.shape == (n,):  # the common case, quickly
        if math.isfinite(value.dot(value)) or bool(np.isfinite(value).all()):
            return value.copy()
        raise StateError(name, value, "finite numbers (no NaN or inf)")
    a = np.asarray(value, dtype=float).reshape(-1) if np.ndim(value) <= 1 else np.asarray(value)
    if a.shape != (n,):
        raise StateError(name, value, f"a vector of {n} finite numbers")
    if not np.all(np.isfinite(a)):
        raise StateError(name, value, "finite numbers (no NaN or inf)")
    return a.copy()




# --------------------------------------------------------------------------------------------
# COM along the LIP
# --------------------------------------------------------------------------------------------
class LipComReference:
    """Horizontal COM reference along the LIP about the stance foot, at constant height.

    The reference is the analytic LIP solution from an initial state (usually the measured COM
    state at touch-down) about the stance pivot. :meth:`reset` starts a new segment.

    Args:
        com_height: constant COM height H [m] (world z on flat ground).
        gravity: g [m/s²].
    """

    def __init__(self, com_height: float, gravity: float = GRAVITY) -> None:
        self.com_height = finite_number("com_height", com_height)
        self.omega = omega(com_height, gravity)
        self._t0 = 0.0
        self._c0 = np.zeros(2)
        self._v0 = np.zeros(2)
        self._p = np.zeros(2)
        self._seg = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # the segment as floats: c0, v0, p (x, y each)
        self._state: np.ndarray | None = None  # compiled_state(), built on first use after a reset

    @property
    def pivot(self) -> np.ndarray:
        """Current LIP pivot (2,) [m]."""
        return self._p.copy()

    def reset(self, t: float, com_xy: np.ndarray, com_vel_xy: np.ndarray, pivot_xy: np.ndarray) -> None:
        """Start a new LIP segment at time ``t`` [s] from a COM state about ``pivot_xy`` [m]."""
        self._t0 = finite_number("t", t)
        self._c0 = _vec("com_xy", np.asarray(com_xy, dtype=float)[:2], 2)
        self._v0 = _vec("com_vel_xy", np.asarray(com_vel_xy, dtype=float)[:2], 2)
        self._p = _vec("pivot_xy", np.asarray(pivot_xy, dtype=float)[:2], 2)
        self._seg = tuple(self._c0.tolist() + self._v0.tolist() + self._p.tolist())
        self._state: np.ndarray | None = None

    def compiled_state(self) -> np.ndarray:
        """The segment as the compiled tick reads it (:mod:`lipmpcc.control.tick_references`): (9,) float64
        t0 [s], ω [1/s], height [m], c0 (x, y) [m], v0 (x, y) [m/s], pivot (x, y) [m]; kept until :meth:`reset`."""
        if self._state is None:
            self._state = np.array([self._t0, self.omega, self.com_height, *self._seg], dtype=float)
        return self._state

    def move_pivot(self, t: float, pivot_xy: np.ndarray) -> None:
        """Continue the reference from its own state at time ``t`` [s] about a new pivot ``pivot_xy``
        [m] (a planned centre of pressure): position and velocity stay continuous, the acceleration
        changes by ``omega² (old pivot − new pivot)``."""
        c, v, _ = self.evaluate(t)
        self.reset(t, c[:2], v[:2], pivot_xy)

    def evaluate(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """COM position, velocity and acceleration (3,) each at time ``t`` [s].

        The same arithmetic as :func:`lipmpcc.models.lip.lip_solution`, on floats (one call per
        control tick).
        """
        cx, cy, vx, vy, px, py = self._seg
        w = self.omega
        tau = w * float(max(0.0, t - self._t0))
        ch, sh = math.cosh(tau), math.sinh(tau)
        dx, dy = cx - px, cy - py
        x = px + dx * ch + vx * sh / w
        y = py + dy * ch + vy * sh / w
        w2 = w**2
        return (
            np.array([x, y, self.com_height]),
            np.array([dx * w * sh + vx * ch, dy * w * sh + vy * ch, 0.0]),
            np.array([w2 * (x - px), w2 * (y - py), 0.0]),
        )


# --------------------------------------------------------------------------------------------
# Polynomials
# --------------------------------------------------------------------------------------------
def _quintic_coefficients_array(T: float, x0: np.ndarray, v0: np.ndarray, a0: np.ndarray, x1: np.ndarray,
                                v1: np.ndarray, a1: np.ndarray) -> np.ndarray:
    """The quintic's coefficients c0..c5 (6, *shape) in the local time s = t − t0 over a duration ``T`` [s], numpy on
    whole arrays of any shape: the reference arithmetic, which :func:`_quintic_coefficients` repeats per
    coordinate on floats (the same bits)."""
    c0, c1, c2 = x0, v0, a0 / 2.0
    h = x1 - (c0 + c1 * T + c2 * T**2)
    hv = v1 - (c1 + 2.0 * c2 * T)
    ha = a1 - 2.0 * c2
    c3 = (20.0 * h - 8.0 * hv * T + ha * T**2) / (2.0 * T**3)
    c4 = (-30.0 * h + 14.0 * hv * T - 2.0 * ha * T**2) / (2.0 * T**4)
    c5 = (12.0 * h - 6.0 * hv * T + ha * T**2) / (2.0 * T**5)
    return np.stack([c0, c1, c2, c3, c4, c5])


def _quintic_coefficients(T: float, x0: np.ndarray, v0: np.ndarray, a0: np.ndarray, x1: np.ndarray, v1: np.ndarray,
                          a1: np.ndarray) -> np.ndarray:
    """The (6, n) coefficients of :class:`Quintic` over a duration ``T`` [s] from its end states (float64
    vectors (n,)): the numpy expressions of ``Quintic.__init__`` evaluated per coordinate on floats, in the
    same order of operations (each numpy operation is one IEEE operation per element: the same bits), without
    the thirty small-array operations."""
    T2, T3, T4, T5 = T**2, T**3, T**4, T**5
    d3, d4, d5 = 2.0 * T3, 2.0 * T4, 2.0 * T5
    c2s, c3s, c4s, c5s = [], [], [], []
    for c0, c1, a, x, v, aa in zip(x0.tolist(), v0.tolist(), a0.tolist(), x1.tolist(), v1.tolist(), a1.tolist()):
        c2 = a / 2.0
        h = x - (c0 + c1 * T + c2 * T2)
        hv = v - (c1 + 2.0 * c2 * T)
        ha = aa - 2.0 * c2
        c2s.append(c2)
        c3s.append((20.0 * h - 8.0 * hv * T + ha * T2) / d3)
        c4s.append((-30.0 * h + 14.0 * hv * T - 2.0 * ha * T2) / d4)
        c5s.append((12.0 * h - 6.0 * hv * T + ha * T2) / d5)
    return np.array([x0.tolist(), v0.tolist(), c2s, c3s, c4s, c5s], dtype=float).reshape(6, x0.shape[0])


class Quintic:
    """Vector quintic on [t0, t1] with given position, velocity and acceleration at both ends.

    After t1 it returns the end state; before t0 it returns the start state.

    Args:
        t0, t1: start and end times [s], t1 > t0.
        x0, v0, a0: start position, velocity, acceleration (n,).
        x1, v1, a1: end position, velocity, acceleration (n,); velocity/acceleration default to 0.
    """

    def __init__(
        self,
        t0: float,
        t1: float,
        x0: np.ndarray,
        v0: np.ndarray | None = None,
        a0: np.ndarray | None = None,
        x1: np.ndarray | None = None,
        v1: np.ndarray | None = None,
        a1: np.ndarray | None = None,
    ) -> None:
        t0 = finite_number("t0", t0)
        t1 = finite_number("t1", t1)
        if t1 <= t0:
            raise ParameterError("t1", t1, f"an end time later than t0 = {t0}")
        x0 = np.atleast_1d(np.asarray(x0, dtype=float))
        z = np.zeros_like(x0)
        v0 = z if v0 is None else np.atleast_1d(np.asarray(v0, dtype=float))
        a0 = z if a0 is None else np.atleast_1d(np.asarray(a0, dtype=float))
        x1 = x0 if x1 is None else np.atleast_1d(np.asarray(x1, dtype=float))
        v1 = z if v1 is None else np.atleast_1d(np.asarray(v1, dtype=float))
        a1 = z if a1 is None else np.atleast_1d(np.asarray(a1, dtype=float))
        T = t1 - t0
        self.t0, self.t1 = t0, t1
        self._end = (x1, v1, a1)
        self._start = (x0, v0, a0)
        shape = x0.shape
        if len(shape) == 1 and v0.shape == a0.shape == x1.shape == v1.shape == a1.shape == shape:
            self._c = _quintic_coefficients(T, x0, v0, a0, x1, v1, a1)
            return
        self._c = _quintic_coefficients_array(T, x0, v0, a0, x1, v1, a1)

    def evaluate(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration at time ``t`` [s]."""
        if t >= self.t1:
            x1, v1, a1 = self._end
            return x1.copy(), v1.copy(), a1.copy()
        x, v, a = self._basis(t) @ self._c
        return x, v, a

    def _evaluate_lists(self, t: float) -> list[list[float]]:
        """:meth:`evaluate` as three lists of floats (position, velocity, acceleration), ``t < t1``."""
        return (self._basis(t) @ self._c).tolist()

    def _basis(self, t: float) -> np.ndarray:
        """Rows: the monomials of position, velocity and acceleration at ``t`` (3, 6)."""
        s = max(0.0, t - self.t0)
        s2 = s * s
        s3 = s2 * s
        return np.array(
            [
                1.0, s, s2, s3, s3 * s, s3 * s2,
                0.0, 1.0, 2.0 * s, 3.0 * s2, 4.0 * s3, 5.0 * s3 * s,
                0.0, 0.0, 2.0, 6.0 * s, 12.0 * s2, 20.0 * s3,
            ]
        ).reshape(3, 6)


def smoothstep5(tau: float) -> tuple[float, float, float]:
    """Quintic blend s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ and its first two derivatives in τ (τ clipped to [0, 1])."""
    t = min(1.0, max(0.0, tau))
    s = t**3 * (10.0 + t * (-15.0 + 6.0 * t))
    ds = 30.0 * t**2 * (1.0 - t) ** 2
    dds = 60.0 * t * (1.0 - t) * (1.0 - 2.0 * t)
    return s, ds, dds


def apex_bump(tau: float) -> tuple[float, float, float]:
    """Bump b(τ) = 64 τ³(1 − τ)³: 0 at τ = 0 and 1 with zero slope and curvature, peak 1 at τ = ½.

    Returns b, db/dτ, d²b/dτ² (τ clipped to [0, 1]).
    """
    t = min(1.0, max(0.0, tau))
    u = 1.0 - t
    b = 64.0 * t**3 * u**3
    db = 192.0 * t**2 * u**2 * (u - t)
    ddb = 384.0 * t * u * (u * u - 3.0 * t * u + t * t)
    return b, db, ddb


# --------------------------------------------------------------------------------------------
# Swing foot + torso heading for one step
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SwingParams:
    """Shape and blending parameters of the swing-foot trajectory.

    Attributes:
        apex_height: height of the swing foot above the mean of its lift-off and landing heights
            at τ = ½ [m].
        freeze_phase: after this phase, foothold and heading changes are ignored (the landing
            target is locked) [-].
        min_remaining: a re-timing never puts the end time closer than this to the current time [s].
    """

    apex_height: float = 0.10
    freeze_phase: float = 0.85
    min_remaining: float = 0.06

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        if not (math.isfinite(self.apex_height) and 0.0 <= self.apex_height <= 0.5):
            raise ParameterError("apex_height", self.apex_height, "a height in [0, 0.5] m")
        if not (math.isfinite(self.freeze_phase) and 0.0 < self.freeze_phase <= 1.0):
            raise ParameterError("freeze_phase", self.freeze_phase, "a phase in (0, 1]")
        if not (math.isfinite(self.min_remaining) and self.min_remaining > 0.0):
            raise ParameterError("min_remaining", self.min_remaining, "a positive time in seconds")


@dataclass(frozen=True)
class StepReference:
    """References of one instant of a step.

    Attributes:
        tau: step phase τ [-].
        swing_pos, swing_vel, swing_acc: swing-foot (sole) position/velocity/acceleration (3,) [m, m/s, m/s²].
        swing_yaw, swing_yaw_rate, swing_yaw_acc: swing-foot yaw [rad, rad/s, rad/s²] (roll = pitch = 0).
        torso_yaw, torso_yaw_rate, torso_yaw_acc: torso heading [rad, rad/s, rad/s²] (upright).
    """

    tau: float
    swing_pos: np.ndarray
    swing_vel: np.ndarray
    swing_acc: np.ndarray
    swing_yaw: float
    swing_yaw_rate: float
    swing_yaw_acc: float
    torso_yaw: float
    torso_yaw_rate: float
    torso_yaw_acc: float


class StepTrajectory:
    """Swing-foot and torso-heading references over one step, with re-timing and blending.

    The reference vector is r = [x, y, z, ψ_foot, ψ_torso] (5,). Its nominal part is a polynomial in τ:

        r_nom(τ) = r_0 + (r_f − r_0)·s(τ) + e_z·h·b(τ),

    with s the quintic blend (:func:`smoothstep5`), b the apex bump (:func:`apex_bump`) and h the apex
    height. A change of target or end time adds a correction δ(t) (a :class:`Quintic` vanishing at the
    end time) so that r, ṙ and r̈ are continuous.

    Args:
        t_start: lift-off time [s].
        t_end: desired landing time [s].
        start_pos: swing-foot (sole) lift-off position (3,) [m].
        start_yaw: swing-foot yaw at lift-off [rad].
        target_pos: foothold (3,) [m].
        target_yaw: foothold yaw [rad].
        torso_start_yaw: torso heading at lift-off [rad].
        torso_target_yaw: planned heading at the end of the step [rad]; defaults to ``target_yaw``.
        params: :class:`SwingParams`.
    """

    def __init__(
        self,
        t_start: float,
        t_end: float,
        start_pos: np.ndarray,
        start_yaw: float,
        target_pos: np.ndarray,
        target_yaw: float,
        torso_start_yaw: float,
        torso_target_yaw: float | None = None,
        params: SwingParams | None = None,
    ) -> None:
        self.params = params or SwingParams()
        self.phase = PhaseClock(t_start, t_end)
        p0 = _vec("start_pos", start_pos, 3)
        pf = _vec("target_pos", target_pos, 3)
        yaw0 = finite_number("start_yaw", start_yaw)
        tyaw0 = finite_number("torso_start_yaw", torso_start_yaw)
        yawf = unwrap_near(finite_number("target_yaw", target_yaw), yaw0)
        tyawf = yawf if torso_target_yaw is None else finite_number("torso_target_yaw", torso_target_yaw)
        tyawf = unwrap_near(tyawf, tyaw0)
        self._r0 = np.array([p0[0], p0[1], p0[2], yaw0, tyaw0])
        self._bump = np.array([0.0, 0.0, self.params.apex_height, 0.0, 0.0])
        self._r0_f = self._r0.tolist()  # float copies for the per-tick evaluation
        self._bump_f = self._bump.tolist()
        self._set_target(np.array([pf[0], pf[1], pf[2], yawf, tyawf]))
        self._corr: Quintic | None = None
        self.n_updates = 0

    def _set_target(self, rf: np.ndarray) -> None:
        self._rf = rf
        # per coordinate of r: (r_0, r_f - r_0, apex height) as floats, for the per-tick evaluation
        self._rdh = tuple(zip(self._r0_f, (rf - self._r0).tolist(), self._bump_f))
        self._state: np.ndarray | None = None

    def compiled_state(self) -> np.ndarray:
        """The trajectory as the compiled tick reads it (:mod:`lipmpcc.control.tick_references`): (51,) float64
        phase segment (t^i [s], τ^i, T_des [s]), per coordinate of r (r_0, r_f − r_0, apex height), then the
        correction (1 or 0, t0 [s], t1 [s], its 6 × 5 coefficients row by row); kept until the next change."""
        if self._state is None:
            corr = self._corr
            tail = [0.0] * 33 if corr is None else [1.0, corr.t0, corr.t1, *corr._c.ravel().tolist()]
            self._state = np.array([*self.phase.segment(), *(x for row in self._rdh for x in row), *tail], dtype=float)
        return self._state

    # -- accessors --------------------------------------------------------------------------
    @property
    def start_pos(self) -> np.ndarray:
        """Lift-off position (3,) [m]."""
        return self._r0[:3].copy()

    @property
    def target_pos(self) -> np.ndarray:
        """Current foothold (3,) [m]."""
        return self._rf[:3].copy()

    @property
    def target_yaw(self) -> float:
        """Current foothold yaw [rad]."""
        return float(self._rf[3])

    @property
    def torso_target_yaw(self) -> float:
        """Current planned torso heading at the end of the step [rad]."""
        return float(self._rf[4])

    @property
    def t_end(self) -> float:
        """Current desired landing time [s]."""
        return self.phase.t_end

    # -- evaluation -------------------------------------------------------------------------
    def _nominal_lists(self, t: float, tau: float) -> tuple[list[float], list[float], list[float]]:
        """Nominal r, ṙ, r̈ as lists of floats (elementwise the arithmetic of :meth:`_nominal`)."""
        td = self.phase.tau_dot(t)
        s, ds, dds = smoothstep5(tau)
        b, db, ddb = apex_bump(tau)
        rdh = self._rdh
        r = [r0 + d * s + h * b for r0, d, h in rdh]
        dr = [(d * ds + h * db) * td for _, d, h in rdh]
        ddr = [(d * dds + h * ddb) * td * td for _, d, h in rdh]
        return r, dr, ddr

    def _nominal(self, t: float, tau: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if tau is None:
            tau = self.phase.tau(t)
        r, dr, ddr = self._nominal_lists(t, tau)
        return np.array(r), np.array(dr), np.array(ddr)

    def _full_lists(self, t: float, tau: float) -> tuple[list[float], list[float], list[float]]:
        """r, ṙ, r̈ (nominal + correction) as lists of floats: the nominal terms of
        :meth:`_nominal_lists`, then the correction added, in the same order of operations."""
        corr = self._corr
        if corr is None or t >= corr.t1:
            return self._nominal_lists(t, tau)
        td = self.phase.tau_dot(t)
        s, ds, dds = smoothstep5(tau)
        b, db, ddb = apex_bump(tau)
        c, dc, ddc = corr._evaluate_lists(t)
        rdh = self._rdh
        r = [r0 + d * s + h * b + ci for (r0, d, h), ci in zip(rdh, c)]
        dr = [(d * ds + h * db) * td + ci for (_, d, h), ci in zip(rdh, dc)]
        ddr = [(d * dds + h * ddb) * td * td + ci for (_, d, h), ci in zip(rdh, ddc)]
        return r, dr, ddr

    def _full(self, t: float, tau: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if tau is None:
            tau = self.phase.tau(t)
        r, dr, ddr = self._full_lists(t, tau)
        return np.array(r), np.array(dr), np.array(ddr)

    def evaluate(self, t: float) -> StepReference:
        """The references at time ``t`` [s]."""
        tau = self.phase.tau(t)
        r, dr, ddr = self._full_lists(t, tau)
        ref = object.__new__(StepReference)  # frozen dataclass, filled without its per-field setattr
        ref.__dict__.update(
            tau=tau,
            swing_pos=np.array(r[:3]),
            swing_vel=np.array(dr[:3]),
            swing_acc=np.array(ddr[:3]),
            swing_yaw=r[3],
            swing_yaw_rate=dr[3],
            swing_yaw_acc=ddr[3],
            torso_yaw=r[4],
            torso_yaw_rate=dr[4],
            torso_yaw_acc=ddr[4],
        )
        return ref

    # -- updates ----------------------------------------------------------------------------
    def update(
        self,
        t: float,
        target_pos: np.ndarray | None = None,
        target_yaw: float | None = None,
        t_end: float | None = None,
        torso_target_yaw: float | None = None,
    ) -> bool:
        """Change the foothold, heading and/or landing time at time ``t`` [s], blending smoothly.

        Target changes after :attr:`SwingParams.freeze_phase` are ignored. A new end time is clamped
        to at least ``t + min_remaining`` (or to the current end time when that is sooner); asking for
        the current end time again changes nothing. Returns True when something changed.

        Args:
            t: current time [s].
            target_pos: new foothold (3,) [m] or None to keep it.
            target_yaw: new foothold yaw [rad] or None.
            t_end: new desired landing time [s] or None.
            torso_target_yaw: new torso heading at the end of the step [rad] or None to keep it.
        """
        t = finite_number("t", t)
        tau = self.phase.tau(t)
        if tau >= 1.0:
            return False
        rf = self._rf.copy()
        locked = tau >= self.params.freeze_phase
        if not locked:
            if target_pos is not None:
                rf[:3] = _vec("target_pos", target_pos, 3)
            if target_yaw is not None:
                rf[3] = unwrap_near(finite_number("target_yaw", target_yaw), self._rf[3])
            if torso_target_yaw is not None:
                rf[4] = unwrap_near(finite_number("torso_target_yaw", torso_target_yaw), self._rf[4])
        new_end = self.phase.t_end
        if t_end is not None and abs(finite_number("t_end", t_end) - new_end) > 1e-9:
            # never closer than min_remaining to now, unless the current end already is
            new_end = max(float(t_end), min(new_end, t + self.params.min_remaining))
        target_changed = float(np.max(np.abs(rf - self._rf))) > 1e-9
        time_changed = abs(new_end - self.phase.t_end) > 1e-9
        if not (target_changed or time_changed):
            return False
        r_old, dr_old, ddr_old = self._full(t)
        self._set_target(rf)
        if time_changed:
            self.phase.retime(t, new_end)
        r_new, dr_new, ddr_new = self._nominal(t)
        self._corr = Quintic(
            t,
            self.phase.t_end,
            r_old - r_new,
            dr_old - dr_new,
            ddr_old - ddr_new,
            x1=np.zeros(5),
        )
        self._state = None
        self.n_updates += 1
        return True
