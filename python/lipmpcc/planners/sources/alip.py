"""Paper B's ALIP-MPC and ALIP-QP as footstep sources of the full-body loop.

:class:`AlipFootstepSource` wraps :class:`~lipmpcc.planners.alip_mpc.AlipMpc` or
:class:`~lipmpcc.planners.alip_qp.AlipQp` (their ``solve(dcm_world, stance_world, stance_side,
t_since_touchdown, stones)``) as a :class:`~lipmpcc.planners.base.FootstepSource`. The loop calls
it at 25 Hz (paper B: every 40 ms), at the lift-off of each swing and then within the swing; every
call re-plans from fresh measurements and the loop re-times the swing to the planned duration
(SPEC §2, eqs. 12–13).

**Planner state from the robot** (paper B §II, eq. 2). With the COM ``c``, its velocity ``ċ``, the
centroidal angular momentum ``k`` (from the whole-body controller's last tick) and the stance contact
point ``p`` (the stance sole centre, frozen at its touch-down for the whole step), the angular
momentum about the contact point is ``L = k + m (c − p) × ċ`` and the DCM, in the stance contact
frame (axes parallel to the world's),

    ξ = (c − p)_xy + [L_y, −L_x] / (λ m z_c),     λ = √(g / z_c),

with the model's constant ``z_c`` (the loop's COM height). The planner gets ``p + ξ`` (world), the
stance foot and side, the time since touch-down and the stones ahead (world frame). The COM velocity
is taken horizontal, as in the ALIP (z_c constant; the vertical velocity after a foot impact, up to
0.08 m/s, would otherwise move ξ by ~6 mm through ``(c − p)_x ċ_z``). By default
(``centroidal_momentum=False``) ``L`` is the lumped mass's, ``m (c − p) × ċ``: the loop's whole-body QP
holds the COM on the LIP about the stance foot with the ankle, so the swinging limbs' ``k`` does not
move the COM, and adding it makes the initial DCM drift within a step. For a point mass at z_c this is
the LIP's ``c + ċ/λ``.

**Approach.** The first ``approach_steps`` footsteps (paper B: 6 to reach speed, the last on the left
foot) are planned by ``approach_planner`` on free footholds (:func:`lipmpcc.terrain.approach_footholds`),
like the reduced runs; the planner under test takes over for the first stone (a right swing).

**Step timing.** An error in the touch-down time moves the next initial DCM. The loop
ends a step when the swing foot's contact is detected, a little before its phase τ reaches 1. The
source keeps a replica of the loop's phase clock (paper B eq. 12: linear in t, re-sloped at every
update so that τ = 1 at the requested end) and learns the phase τ_c at which contact happens as a
function of the swing's travel (:class:`ContactPhaseModel`: longer swings touch down a little earlier
in phase). At each call, at time t with phase τ_i, it asks for the end time R such that τ reaches τ_c
at the planned touch-down t_td + T:

    R = t + (t_td + T − t)(1 − τ_i)/(τ_c − τ_i)        (R = T/τ_c at lift-off).

From ``hold_phase`` (τ = 0.8) on it holds its last answer: a duration changed later could hardly be
honoured before contact, and a re-plan whose duration is not applied would mislead the next step.

**Landing and touch-down corrections.** Long, fast swings land a little short of their target
(tracking lag): the source learns that error as a fraction of the swing's travel
(:class:`LandingBiasModel`) and sends a target stretched accordingly. The initial DCM measured at the
next touch-down also differs a little from the step's last estimate (end-of-swing tracking, impact);
the source learns that difference per swing side (exponential average, ``dcm_bias_gain``) and adds it
to the DCM it gives the planner.

**Ankle.** When the planner has a foot (:attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.cop_range`),
the plan's centre-of-pressure offset goes to the loop as :attr:`~lipmpcc.planners.base.StepPlan.cop_offset`;
the loop's LIP COM reference then turns about the stance contact point plus that offset (continuous in
position and velocity), so that the whole-body QP moves the centre of pressure where the planner
assumed it.

**Failures** are survived and counted. A failure of the multi-step planner is most often an infeasible
horizon: a few centimetres of DCM error leave no way to reach the four previewed stones within the
viable DCM bounds. The source then solves again at once (``relax_on_failure``) with the stones after the
next one grown by 0.05 m, 0.15 m, then free, first with the planner's limits, then with wider viability
bounds (the next foothold always stays on its stone), counted in :attr:`AlipFootstepSource.relaxed_solves`.
When that fails too, the planner's own fallback (its previous plan) is used; when there is none
(:class:`~lipmpcc.exceptions.NoFallbackPlanError`) the source aims at the centre of the next stone with
the nominal duration. Only a plain successful solve answers with the status ``"ok"``; the relaxed
re-solve, the fallback and the stone centre count as failures. Every call is kept in
:attr:`AlipFootstepSource.records` (also each plan's ``record``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Union

import numpy as np

from ...conventions import GRAVITY
from ...exceptions import InvalidInputError, NoFallbackPlanError, ParameterError
from ...validation import check_field_types, finite_vector
from ...models.alip import AlipParams, KinematicLimits, parse_side
from ...models.lip import omega
from ...terrain import Stone, StoneSequence
from ...models.phase import PhaseClock
from ..alip_common import AlipPlanResult
from ..alip_mpc import AlipMpc
from ..alip_qp import AlipQp
from ..base import PlannerInput, StepPlan

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: the planners this source drives
AlipSolver = Union[AlipMpc, AlipQp]

RECOVERY_MARGINS = (0.05, 0.15, math.inf)  # [m] growth of the later stones in a recovery solve

__all__ = [
    "RECOVERY_MARGINS",
    "AlipSourceParams",
    "AlipSourceRecord",
    "AlipFootstepSource",
    "ContactPhaseModel",
    "LandingBiasModel",
    "contact_dcm",
    "extend_course",
]


def contact_dcm(
    com: ArrayLike,
    com_vel: ArrayLike,
    centroidal_momentum: ArrayLike | None,
    contact: ArrayLike,
    mass: float,
    z_c: float,
    g: float = GRAVITY,
) -> tuple[np.ndarray, np.ndarray]:
    """DCM from the angular momentum about the contact point (paper B eq. 2).

    Args:
        com: COM position (3,) [m], world frame.
        com_vel: COM velocity (3,) [m/s].
        centroidal_momentum: angular momentum about the COM (3,) [kg m²/s] (None: zero).
        contact: contact point (2,) or (3,) [m] (z = 0 when omitted).
        mass: total mass m [kg].
        z_c: the ALIP's constant COM height [m].
        g: gravity [m/s²].

    Returns:
        ``(xi, L)``: the DCM (2,) in the world frame [m] and the angular momentum about the contact
        point (3,) [kg m²/s].
    """
    c = np.asarray(com, dtype=float).reshape(-1)
    v = np.asarray(com_vel, dtype=float).reshape(-1)
    p = np.zeros(3)
    pc = np.asarray(contact, dtype=float).reshape(-1)
    if c.shape != (3,) or v.shape != (3,) or pc.shape not in ((2,), (3,)):
        raise InvalidInputError("com/com_vel/contact", (c.shape, v.shape, pc.shape), "(3,), (3,) and (2,) or (3,) arrays")
    p[: pc.size] = pc
    k = np.zeros(3) if centroidal_momentum is None else np.asarray(centroidal_momentum, dtype=float).reshape(3)
    if not (math.isfinite(mass) and mass > 0 and math.isfinite(z_c) and z_c > 0):
        raise ParameterError("mass/z_c", (mass, z_c), "a positive mass [kg] and height [m]")
    r = c - p
    L = k + mass * np.cross(r, v)
    lam = omega(z_c, g)
    xi = p[:2] + r[:2] + np.array([L[1], -L[0]]) / (lam * mass * z_c)
    return xi, L


def extend_course(course: StoneSequence, n_extra: int) -> StoneSequence:
    """``course`` followed by ``n_extra`` free footholds that repeat its last step with the lateral
    component mirrored (the next steps after the course: alternating feet, same length)."""
    if n_extra <= 0:
        return course
    c = [np.asarray(x, dtype=float) for x in course.centers]
    sides = [int(s) for s in course.sides]
    for _ in range(int(n_extra)):
        prev = c[-2] if len(c) >= 2 else c[-1] - np.array([0.0, -sides[-1] * 0.28])
        d = c[-1] - prev
        c.append(c[-1] + np.array([d[0], -d[1]]))
        sides.append(-sides[-1])
    n = len(c) - len(course)
    extra = StoneSequence(np.array(c[len(course):]), np.full((n, 2), np.inf), np.array(sides[len(course):]),
                          np.zeros(n, bool), course.name)
    return course + extra


@dataclass(frozen=True)
class AlipSourceParams:
    """Parameters of :class:`AlipFootstepSource` beyond the planner's.

    Attributes:
        rate_hz: re-planning rate [Hz] (paper B: 25 Hz).
        contact_window: number of recent touch-downs the contact-phase model is fitted to (0: keep
            ``contact_phase``) [-].
        landing_window: number of recent touch-downs the landing-bias model is fitted to (0: send the
            planned footholds as they are) [-].
        contact_phase: initial estimate of τ_c; 1 asks the loop for the planned duration as is [-].
        contact_phase_bounds: bounds of the estimate [-].
        swing_min_remaining: the loop's :attr:`~lipmpcc.control.references.SwingParams.min_remaining` (its
            re-timing never ends a swing sooner than this after an update), for the clock replica [s].
        hold_phase: from this phase of the swing on, the source holds its last answer (no re-plan): a
            duration changed later can hardly be honoured before contact (at τ_c) [-].
        dcm_bias_gain: gain in [0, 1] of the touch-down DCM bias estimate (per swing side: how much the
            initial DCM at touch-down differs from the last estimate of the step); 0 disables it [-].
        dcm_settle_time: learn the touch-down DCM bias not from the DCM measured at the touch-down but from
            the first call this long after it, carried back to the touch-down along the new stance's LIP, so
            that the impact and double-support transient counts in the bias (0: at the touch-down) [s].
        relax_on_failure: when the planner fails, solve again at once with relaxed later stones (see the
            module docstring) before using its fallback.
        heading: yaw of every foothold and of the torso [rad] (the course runs along it; 0: +x).
        centroidal_momentum: include the centroidal angular momentum k in L (True) or use the lumped
            mass's L = m (c − p) × ċ only (False); see the module docstring.
    """

    rate_hz: float = 25.0
    contact_window: int = 12
    landing_window: int = 12
    contact_phase: float = 0.9
    contact_phase_bounds: tuple[float, float] = (0.7, 1.0)
    swing_min_remaining: float = 0.06
    relax_on_failure: bool = True
    dcm_bias_gain: float = 0.3
    hold_phase: float = 0.8
    dcm_settle_time: float = 0.0
    heading: float = 0.0
    centroidal_momentum: bool = False

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        if not (math.isfinite(self.rate_hz) and self.rate_hz > 0):
            raise ParameterError("rate_hz", self.rate_hz, "a positive re-planning rate [Hz]")
        if not (isinstance(self.contact_window, (int, np.integer)) and 0 <= self.contact_window <= 1000):
            raise ParameterError("contact_window", self.contact_window, "an integer in [0, 1000]")
        if not (isinstance(self.landing_window, (int, np.integer)) and 0 <= self.landing_window <= 1000):
            raise ParameterError("landing_window", self.landing_window, "an integer in [0, 1000]")
        lo, hi = finite_vector("contact_phase_bounds", self.contact_phase_bounds, 2, error=ParameterError)
        if not (0.5 <= lo <= hi <= 1.0):
            raise ParameterError("contact_phase_bounds", self.contact_phase_bounds, "0.5 <= low <= high <= 1")
        object.__setattr__(self, "contact_phase_bounds", (lo, hi))
        if not (math.isfinite(self.contact_phase) and lo <= self.contact_phase <= hi):
            raise ParameterError("contact_phase", self.contact_phase, f"a phase in [{lo}, {hi}]")
        if not (math.isfinite(self.dcm_bias_gain) and 0.0 <= self.dcm_bias_gain <= 1.0):
            raise ParameterError("dcm_bias_gain", self.dcm_bias_gain, "a gain in [0, 1]")
        if not (math.isfinite(self.dcm_settle_time) and 0.0 <= self.dcm_settle_time <= 0.3):
            raise ParameterError("dcm_settle_time", self.dcm_settle_time, "a time in [0, 0.3] s")
        if not (math.isfinite(self.hold_phase) and 0.0 < self.hold_phase <= 1.0):
            raise ParameterError("hold_phase", self.hold_phase, "a phase in (0, 1]")
        if not (math.isfinite(self.swing_min_remaining) and self.swing_min_remaining > 0.0):
            raise ParameterError("swing_min_remaining", self.swing_min_remaining, "a positive time [s]")
        if not math.isfinite(self.heading):
            raise ParameterError("heading", self.heading, "a finite yaw [rad]")


class ContactPhaseModel:
    """The phase τ_c at which the swing foot's contact is detected, as a function of the swing's
    horizontal travel d [m] (lift-off to foothold) and of the step's planned duration T [s]:
    τ_c = a + b (d − d̄) + c (T − T̄), fitted by least squares to the last ``window`` touch-downs with
    ridges ``ridge`` on b and ``ridge_duration`` on c (little spread in d or T: b, c → 0).

    Longer swings touch down a little earlier in phase. When the planner alternates long and short steps,
    the travel alone leaves the short steps touching down early and the long ones late, hence the
    duration term.
    """

    def __init__(
        self, prior: float, bounds: tuple[float, float], window: int, ridge: float = 0.05, ridge_duration: float = 0.002
    ) -> None:
        self.prior = float(prior)
        self.bounds = (float(bounds[0]), float(bounds[1]))
        self.window = int(window)
        self.ridge = float(ridge)
        self.ridge_duration = float(ridge_duration)
        self.samples: list[tuple[float, float, float]] = []
        self._fit = (self.prior, 0.0, 0.0, 0.0, 0.0)

    def update(self, travel: float, tau: float, duration: float = float("nan")) -> None:
        """Add the touch-down of a swing of horizontal travel ``travel`` [m] at phase ``tau``, in a step
        planned to last ``duration`` [s] (NaN: unknown, no duration term)."""
        if self.window <= 0 or not (math.isfinite(travel) and math.isfinite(tau)):
            return
        self.samples.append((float(travel), float(tau), float(duration)))
        del self.samples[: -self.window]
        d = np.array([x for x, _, _ in self.samples])
        y = np.array([v for _, v, _ in self.samples])
        T = np.array([w for _, _, w in self.samples])
        dm, ym = float(np.mean(d)), float(np.mean(y))
        if np.all(np.isfinite(T)):
            Tm = float(np.mean(T))
            X = np.column_stack([d - dm, T - Tm])
            A = X.T @ X + np.diag([self.ridge, self.ridge_duration])
            b, c = np.linalg.solve(A, X.T @ (y - ym))
            self._fit = (ym, float(b), dm, float(c), Tm)
        else:
            b = float(np.sum((d - dm) * (y - ym)) / (np.sum((d - dm) ** 2) + self.ridge))
            self._fit = (ym, b, dm, 0.0, 0.0)

    def predict(self, travel: float, duration: float = float("nan")) -> float:
        """τ_c for a swing of horizontal travel ``travel`` [m] in a step planned to last ``duration`` [s]."""
        a, b, dm, c, Tm = self._fit
        tau = a + b * (float(travel) - dm) if math.isfinite(travel) else a
        if c != 0.0 and math.isfinite(duration):
            tau += c * (float(duration) - Tm)
        return float(np.clip(tau, *self.bounds))


class LandingBiasModel:
    """Systematic landing error of the swing foot, proportional to its travel: per axis,
    (landed − target) = c (target − lift-off), c fitted by ridge regression over the last ``window``
    touch-downs (|c| <= ``max_gain``). :meth:`command` returns the target to send so that the foot lands
    on the planned one: lift-off + (target − lift-off)/(1 + c). Long fast swings land short.
    """

    def __init__(self, window: int, ridge: float = 0.05, max_gain: float = 0.1) -> None:
        self.window = int(window)
        self.ridge = float(ridge)
        self.max_gain = float(max_gain)
        self.samples: list[tuple[np.ndarray, np.ndarray]] = []
        self.gain = np.zeros(2)

    def update(self, travel: np.ndarray, error: np.ndarray) -> None:
        """Add a touch-down: swing ``travel`` = target − lift-off and ``error`` = landed − target (2,) [m]."""
        if self.window <= 0 or not (np.all(np.isfinite(travel)) and np.all(np.isfinite(error))):
            return
        self.samples.append((np.asarray(travel, dtype=float).copy(), np.asarray(error, dtype=float).copy()))
        del self.samples[: -self.window]
        d = np.array([a for a, _ in self.samples])
        e = np.array([b for _, b in self.samples])
        c = np.sum(d * e, axis=0) / (np.sum(d * d, axis=0) + self.ridge)
        self.gain = np.clip(c, -self.max_gain, self.max_gain)

    def command(self, liftoff: np.ndarray, target: np.ndarray) -> np.ndarray:
        """Foothold to send for the foot to land on ``target`` [m]."""
        return liftoff + (target - liftoff) / (1.0 + self.gain)


@dataclass(frozen=True)
class AlipSourceRecord:
    """One call of the source.

    Attributes:
        t: simulated time [s].
        step_index: footstep being planned (index in the course: touch-downs before the call).
        role: ``"approach"`` or ``"course"`` (which planner answered).
        time_since_touchdown: t̃ [s].
        stance: stance contact point (2,) [m] (frozen at its touch-down).
        stance_side: +1 left, −1 right.
        dcm: ξ from eq. 2, world frame (2,) [m] (measured; the planner got ``dcm + dcm_bias e^{λ t̃}``).
        dcm_bias: the learned touch-down bias added to the initial DCM (2,) [m].
        angular_momentum: L about the contact point (3,) [kg m²/s].
        requested_duration: duration asked of the loop (the planned one stretched so that contact,
            at the learned phase τ_c, happens at the planned time) [s].
        result: the planner's :class:`~lipmpcc.planners.alip_mpc.AlipPlanResult` (None when it failed
            with no fallback).
        status: the planner's status, ``"relaxed: ..."``, ``"fallback (...)"`` or ``"failed: ..."``.
        phase: the replica of the loop's swing phase τ at the call [-].
        contact_phase: the predicted contact phase τ_c for this swing [-].
    """

    t: float
    step_index: int
    role: str
    time_since_touchdown: float
    stance: np.ndarray
    stance_side: int
    dcm: np.ndarray
    dcm_bias: np.ndarray
    angular_momentum: np.ndarray
    requested_duration: float
    result: AlipPlanResult | None
    status: str
    phase: float
    contact_phase: float

    @property
    def planned_duration(self) -> float:
        """The planner's duration of the current step [s] (the request when it failed)."""
        return float(self.result.step_duration) if self.result is not None else self.requested_duration

    @property
    def z0(self) -> np.ndarray:
        """Initial DCM of the step in the contact frame, ξ e^{−λ t̃} − p (eq. 10) [m] (NaN when failed)."""
        return self.result.z0 if self.result is not None else np.full(2, np.nan)


class AlipFootstepSource:
    """ALIP-MPC / ALIP-QP footstep planner for :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop`.

    Implements the planner contract, :class:`~lipmpcc.planners.base.FootstepSource`. The loop must
    start with the stance foot opposite to ``course.sides[0]`` (``LoopParams(first_stance="left")``
    for paper B's courses) and end each step at the swing foot's contact (no double support).

    Args:
        planner: an :class:`~lipmpcc.planners.alip_mpc.AlipMpc` or :class:`~lipmpcc.planners.alip_qp.AlipQp`.
        course: the footholds in order, world frame: approach (free) then stones.
        approach_planner: plans the first ``approach_steps`` footsteps (None: ``planner`` throughout).
        approach_steps: number of approach footsteps.
        params: :class:`AlipSourceParams`.
        name: planner name for summaries (default: ``planner.name``).

    Attributes:
        records: every call (:class:`AlipSourceRecord`).
        alip: the planner's ALIP constants (mass, z_c).
        contact_model, landing_model: the learned timing and landing models.
        contact_phases: the measured phase at each touch-down [-].
        dcm_bias: the learned touch-down DCM bias per swing side (+1 left, −1 right) [m].
        relaxed_solves, no_fallback_failures: per role (``"approach"``, ``"course"``), the failures
            answered by a relaxed re-solve, and those with no plan to fall back on.
    """

    #: it learns the contact phase and the landing bias itself: the loop ends a step at the contact
    compensates_touchdown = True

    def __init__(
        self,
        planner: AlipSolver,
        course: StoneSequence,
        approach_planner: AlipSolver | None = None,
        approach_steps: int = 0,
        params: AlipSourceParams | None = None,
        name: str | None = None,
    ) -> None:
        if not callable(getattr(planner, "solve", None)):
            raise InvalidInputError("planner", planner, "an AlipMpc or AlipQp (an object with solve(...))")
        if approach_planner is not None and not callable(getattr(approach_planner, "solve", None)):
            raise InvalidInputError("approach_planner", approach_planner, "None or an AlipMpc/AlipQp")
        if not isinstance(course, StoneSequence) or len(course) == 0:
            raise InvalidInputError("course", course, "a non-empty StoneSequence")
        if not isinstance(approach_steps, (int, np.integer)) or not 0 <= approach_steps <= len(course):
            raise InvalidInputError("approach_steps", approach_steps, f"an integer in [0, {len(course)}]")
        self.params = params or AlipSourceParams()
        if not isinstance(self.params, AlipSourceParams):
            raise ParameterError("params", params, "an AlipSourceParams")
        self.planner = planner
        self.approach_planner = approach_planner
        self.approach_steps = int(approach_steps) if approach_planner is not None else 0
        self.alip: AlipParams = planner.params.alip
        if approach_planner is not None and approach_planner.params.alip != self.alip:
            raise ParameterError("approach_planner.params.alip", approach_planner.params.alip,
                                 f"the planner's ALIP constants {self.alip}")
        self.course = course
        h = max(self._needed(planner), self._needed(approach_planner) if approach_planner is not None else 1)
        self._course = extend_course(course, h + 4)
        self._recovery: dict[int, tuple[AlipSolver, AlipSolver]] = {}
        self.rate_hz = float(self.params.rate_hz)
        self.name = name or str(getattr(planner, "name", "alip"))
        self.reset()

    @staticmethod
    def _needed(p: AlipSolver) -> int:
        return max(int(getattr(p, "stones_needed", getattr(p, "horizon", 1))), 1)

    # ---- lifetime ----------------------------------------------------------------------------
    def reset(self) -> None:
        """Forget the plans, the records, the failure counts and the learned models."""
        sp = self.params
        self.planner.reset()
        if self.approach_planner is not None:
            self.approach_planner.reset()
        self.records: list[AlipSourceRecord] = []
        self.no_fallback_failures = {"approach": 0, "course": 0}
        self.relaxed_solves = {"approach": 0, "course": 0}
        self.contact_model = ContactPhaseModel(sp.contact_phase, sp.contact_phase_bounds, sp.contact_window)
        self.landing_model = LandingBiasModel(sp.landing_window)
        self.contact_phases: list[float] = []
        self.dcm_bias = {1: np.zeros(2), -1: np.zeros(2)}
        self._last_step = -1
        self._t_td = 0.0
        self._clock: PhaseClock | None = None  # replica of the loop's swing phase
        self._tau_c = float(sp.contact_phase)
        self._T_plan = float("nan")  # the last planned duration of this step [s]
        self._liftoff: np.ndarray | None = None  # swing sole at lift-off
        self._target: np.ndarray | None = None  # last planned foothold of this swing
        self._last_plan: StepPlan | None = None
        self._stance: np.ndarray | None = None  # stance contact point, frozen at its touch-down
        self._stance_side = 1
        self._z0_last: np.ndarray | None = None  # last measured initial DCM of this step
        self._bias_pending: tuple | None = None  # the last swing's bias, still to learn (dcm_settle_time)

    def warm_up(self) -> None:
        """Build the solvers now, outside a timed run, then :meth:`reset` (one solve from rest)."""
        st = np.asarray(self._course.centers[0], dtype=float) - np.array([0.0, float(self._course.sides[0]) * 0.28])
        for p in (self.planner, self.approach_planner):
            if p is None:
                continue
            n = self._needed(p)
            try:
                p.solve(st, st, -int(self._course.sides[0]), 0.0, [self._course[j] for j in range(n)])
            except NoFallbackPlanError:
                pass
        self.reset()

    # ---- results -----------------------------------------------------------------------------
    @property
    def solver_failures(self) -> int:
        """Failed solves of the planner under test (each answered by a relaxed re-solve, its fallback
        or a stone centre)."""
        return int(getattr(self.planner, "failures", 0))

    @property
    def approach_failures(self) -> int:
        """Failed solves of the approach planner."""
        return int(getattr(self.approach_planner, "failures", 0)) if self.approach_planner is not None else 0

    @property
    def contact_phase(self) -> float:
        """Predicted contact phase τ_c of the current swing [-]."""
        return self._tau_c

    def course_records(self) -> list[AlipSourceRecord]:
        """The records of the planner under test (footsteps from ``approach_steps`` on)."""
        return [r for r in self.records if r.role == "course"]

    # ---- learning at each touch-down ---------------------------------------------------------
    def _new_step(self, inp: PlannerInput) -> None:
        """First call of a step: learn from the touch-down that ended the last one, freeze the contact."""
        t_td = float(inp.t) - float(inp.time_since_touchdown)
        stance = np.asarray(inp.stance_pos, dtype=float)[:2].copy()
        sp = self.params
        if self._clock is not None:
            tau = self._clock.tau(t_td)
            self.contact_phases.append(tau)
            if self._liftoff is not None and self._target is not None and self._last_plan is not None:
                self.contact_model.update(float(np.linalg.norm(self._target - self._liftoff)), tau, self._T_plan)
                sent = self._last_plan.foothold  # the landing error of the foothold the loop tracked
                self.landing_model.update(sent - self._liftoff, stance - sent)
        self._bias_pending = None
        if self._stance is not None and self._z0_last is not None and sp.dcm_bias_gain > 0.0:
            # the last step's contact, touch-down time, swing side and last estimate of its initial DCM
            self._bias_pending = (self._stance, self._t_td, -self._stance_side, self._z0_last, t_td)
            if sp.dcm_settle_time <= 0.0:
                xi, _ = self._dcm(inp, self._stance)
                self._learn_bias(xi)
        self._clock = None
        self._target = None
        self._last_plan = None
        self._z0_last = None
        self._liftoff = np.asarray(inp.swing_pos, dtype=float)[:2].copy()
        self._t_td = t_td
        self._stance = stance
        self._stance_side = parse_side(inp.stance_side)
        self._last_step = int(inp.step_index)

    def _learn_bias(self, xi_td: np.ndarray) -> None:
        """Learn the touch-down DCM bias of the last swing from ``xi_td``, the DCM [m] at its touch-down
        (measured then, or carried back from after the settling time), against the step's last estimate."""
        stance, t_td_old, swing_side, z0_last, t_td = self._bias_pending
        self._bias_pending = None
        drift = (xi_td - stance) * math.exp(-self.alip.lam * (t_td - t_td_old)) - z0_last
        b = self.dcm_bias[swing_side]
        b += self.params.dcm_bias_gain * (np.clip(drift, -0.05, 0.05) - b)

    def _settled_bias(self, xi: np.ndarray, stance: np.ndarray, t: float) -> None:
        """With ``dcm_settle_time`` > 0: at the first call that late into the step, learn the bias from the
        DCM ``xi`` measured now, carried back to the touch-down along the new stance's LIP
        (ξ_td = p + (ξ − p) e^{−λ t}, ``t`` [s] since touch-down, p the pivot), so that the impact and double-support
        transient of the first instants counts in the bias. The pivot is the stance point plus the centre-of-
        pressure offset of this step's last plan (the loop's LIP turns about it)."""
        if self._bias_pending is None or t < self.params.dcm_settle_time:
            return
        pivot = stance.copy()
        plan = self._last_plan
        if plan is not None and plan.cop_offset is not None:
            pivot += np.asarray(plan.cop_offset, dtype=float)[:2]
        self._learn_bias(pivot + (xi - pivot) * math.exp(-self.alip.lam * t))

    def _dcm(self, inp: PlannerInput, contact: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        a = self.alip
        mass = float(inp.mass) if math.isfinite(inp.mass) and inp.mass > 0 else a.mass
        k = inp.angular_momentum if self.params.centroidal_momentum else None
        v = np.asarray(inp.com_vel, dtype=float)
        v = np.array([v[0], v[1], 0.0])  # the ALIP's constant height: no vertical velocity (impacts)
        return contact_dcm(inp.com_pos, v, k, np.r_[contact, inp.stance_pos[2]], mass, a.z_c, a.g)

    # ---- timing ------------------------------------------------------------------------------
    def _request(self, t: float, T: float) -> float:
        """End time to ask of the loop so that contact (at τ_c) happens at t_td + T; updates the replica
        of the loop's phase clock as the loop will (:meth:`~lipmpcc.control.references.StepTrajectory.update`)."""
        t_land = self._t_td + T
        m = self.params.swing_min_remaining
        clock = self._clock
        tau_i = 0.0 if clock is None else clock.tau(t)
        tau_c = self._tau_c
        if tau_i < tau_c - 0.005 and t_land > t:
            end = t + (t_land - t) * (1.0 - tau_i) / (tau_c - tau_i)
        elif clock is not None:  # about to land: keep the end time
            end = clock.t_end
        else:
            end = max(t_land, t + 1e-3)
        if clock is None:
            self._clock = PhaseClock(t, max(end, t + m))
        elif tau_i < 1.0 and abs(end - clock.t_end) > 1e-9:
            new_end = max(end, min(clock.t_end, t + m))
            if new_end > t and abs(new_end - clock.t_end) > 1e-9:
                clock.retime(t, new_end)
        return end

    # ---- failures ----------------------------------------------------------------------------
    def _recover(self, active: AlipSolver, xi: np.ndarray, stance: np.ndarray, side: int, t: float,
                 upcoming: list[Stone]) -> AlipPlanResult | None:
        """After a failed solve: the same problem with the stones after the next one grown by
        ``RECOVERY_MARGINS`` (the last: free), first with the planner's limits, then with wider viability
        bounds; stateless planners, cold-started. None when every try fails."""
        recs = self._recovery.get(id(active))
        if recs is None:
            wide = KinematicLimits(x_max=1.0, y_min=0.0, y_max=0.9)
            recs = (type(active)(active.params), type(active)(replace(active.params, limits=wide)))
            self._recovery[id(active)] = recs
        for rec in recs:
            for margin in RECOVERY_MARGINS:
                stones = [upcoming[0]] + [
                    Stone(tuple(s.center), tuple(np.asarray(s.size, dtype=float) + 2.0 * margin)) for s in upcoming[1:]
                ]
                rec.reset()
                try:
                    r = rec.solve(xi, stance, side, t, stones)
                except NoFallbackPlanError:
                    continue
                if not r.fallback:
                    return r
        return None

    # ---- the planner call --------------------------------------------------------------------
    def plan(self, inp: PlannerInput) -> StepPlan:
        """Next foothold and duration of the current swing foot from the ALIP planner (paper B)."""
        if not isinstance(inp, PlannerInput):
            raise InvalidInputError("inp", inp, "a lipmpcc.planners.base.PlannerInput")
        w0 = time.perf_counter()
        sp = self.params
        k = int(inp.step_index)
        if k != self._last_step:
            self._new_step(inp)
        t_now = float(inp.t)
        tau_i = 0.0 if self._clock is None else self._clock.tau(t_now)
        if self._last_plan is not None and tau_i >= min(sp.hold_phase, self._tau_c - 0.005):
            return self._last_plan  # landing: hold the answer
        role = "approach" if k < self.approach_steps else "course"
        active = self.approach_planner if role == "approach" else self.planner
        n = self._needed(active)
        if k + n > len(self._course):
            self._course = extend_course(self._course, k + n - len(self._course) + 4)
        upcoming = [self._course[j] for j in range(k, k + n)]
        side = self._stance_side
        stance = self._stance
        lam = self.alip.lam
        t = max(0.0, float(inp.time_since_touchdown))
        xi, L = self._dcm(inp, stance)
        self._settled_bias(xi, stance, t)
        self._z0_last = (xi - stance) * math.exp(-lam * t)
        bias = self.dcm_bias[-side].copy()
        xi_plan = xi + bias * math.exp(lam * t)
        res, status, T, foothold, solved = self._solve(role, active, xi_plan, stance, side, t, upcoming)
        self._T_plan = T
        self._tau_c = self.contact_model.predict(float(np.linalg.norm(foothold - self._liftoff)), T)
        duration = max(self._request(t_now, T) - self._t_td, 1e-3)
        self._target = foothold.copy()
        record = AlipSourceRecord(t_now, k, role, t, stance.copy(), side, xi, bias, L, duration, res, status, tau_i,
                                  self._tau_c)
        self.records.append(record)
        self._last_plan = self._step_plan(active, record, foothold, solved, w0)
        return self._last_plan

    def _solve(self, role: str, active: AlipSolver, xi_plan: np.ndarray, stance: np.ndarray, side: int, t: float,
               upcoming: list[Stone]) -> tuple[AlipPlanResult | None, str, float, np.ndarray, bool]:
        """The planner's answer: (result or None, status, planned duration [s], foothold [m], solved), with
        the relaxed re-solve after a failure and the next stone's centre when there is no plan at all;
        ``solved`` only for a plain successful solve."""
        n = len(upcoming)
        relaxed = False
        try:
            res: AlipPlanResult | None = active.solve(xi_plan, stance, side, t, upcoming)
            if res.fallback and self.params.relax_on_failure and n > 2:
                res2 = self._recover(active, xi_plan, stance, side, t, upcoming)
                if res2 is not None:
                    res, relaxed = res2, True
                    self.relaxed_solves[role] += 1
        except NoFallbackPlanError as exc:
            self.no_fallback_failures[role] += 1
            foothold = np.asarray(upcoming[0].center, dtype=float)
            if not np.all(np.isfinite(foothold)):
                foothold = stance + np.array([0.0, -side * 0.28])
            return None, f"failed: {exc.status}", max(float(active.params.T_nom), t + 0.05), foothold, False
        status = ("relaxed: " if relaxed else "") + res.status
        solved = not (res.fallback or relaxed)
        return res, status, float(res.step_duration), np.asarray(res.next_foothold, dtype=float), solved

    def _step_plan(self, active: AlipSolver, record: AlipSourceRecord, foothold: np.ndarray, solved: bool,
                   w0: float) -> StepPlan:
        """The loop's plan: the foothold corrected for the landing bias, the requested duration; status
        ``"ok"`` when ``solved``, else the record's."""
        res = record.result
        heading = self.params.heading
        preview = None
        cost = float("nan")
        cop = None
        solve_time = time.perf_counter() - w0
        if active.has_foot:
            cop = np.zeros(2) if res is None else np.asarray(res.cop_offset, dtype=float)
        if res is not None:
            preview = np.column_stack([res.footholds, np.full(len(res.footholds), heading), res.durations])
            cost = float(res.cost)
            solve_time = float(res.solve_time)
        return StepPlan(
            foothold=self.landing_model.command(self._liftoff, foothold),
            yaw=heading,
            duration=record.requested_duration,
            cop_offset=cop,
            preview=preview,
            cost=cost,
            solve_time=solve_time,
            status="ok" if solved else record.status,
            record=record,
        )
