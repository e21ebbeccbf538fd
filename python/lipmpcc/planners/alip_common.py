"""What paper B's two planners, the ALIP-MPC and the ALIP-QP, share.

- :class:`AlipPlanResult`: the result of one solve (both planners);
- input checks and stone handling: :func:`stone_arrays`, :func:`pad_stones`, :func:`check_xy`,
  :func:`check_time_since_touchdown`;
- :class:`AlipStepParams`: the step-timing parameters both have (durations, limits, width, ALIP
  constants) — their validation and derived values, defined once;
- :class:`AlipPlanner`: their face onto the planner contract (:mod:`lipmpcc.planners.base`):
  ``plan(PlannerInput) -> StepPlan``, with the solve itself in ``solve(dcm_world, stance_world,
  stance_side, t_since_touchdown, stones) -> AlipPlanResult``.
"""

from __future__ import annotations

import math
import warnings
from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Sequence, Union, overload

import numpy as np

from ..exceptions import InvalidInputError, ParameterError, StateError
from ..exclusive import exclusive
from ..models.alip import AlipParams, DcmBounds, KinematicLimits, viability_bounds
from ..terrain import STONE_SIZE, Stone, StoneSequence
from ..validation import finite_number, positive_number
from .base import PlannerInput, StepPlan

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "AlipPlanResult",
    "Stones",
    "stone_arrays",
    "pad_stones",
    "check_xy",
    "check_time_since_touchdown",
    "AlipStepParams",
    "AlipPlanner",
    "to_step_plan",
    "DCM_TARGETS",
]

#: how a planner reads the stones ahead: a StoneSequence, a list of Stone, or (n, 2) centres [m]
Stones = Union[StoneSequence, Sequence[Stone], "ArrayLike"]

#: the foothold whose periodic gait sets the initial-DCM target (see AlipMpcParams.dcm_target)
DCM_TARGETS = ("next", "current")


# ----------------------------------------------------------------------------- result
@dataclass
class AlipPlanResult:
    """Output of one planner call (ALIP-MPC or ALIP-QP).

    Attributes:
        next_foothold: world position of the next foothold [m].
        step_duration: planned duration of the current step, from its touch-down [s].
        time_to_touchdown: ``step_duration - t`` [s].
        footholds: (N, 2) planned world footholds of the preview [m].
        durations: (N,) planned step durations [s].
        u: (N, 2) footholds relative to the previous foothold [m].
        z: (N, 2) initial DCM of each following step, in its contact frame [m].
        sigma: (N,) exp(lambda T).
        z0: initial DCM of the current step (eq. 10) [m].
        success: the solver converged to a feasible plan.
        fallback: the returned plan is the previous one (held or shifted).
        status: solver status string.
        cost: paper objective at the returned plan (NaN for a fallback).
        iterations: solver iterations.
        solve_time: wall time of the solver call [s].
        plan_time: wall time of the whole planner call [s].
        solver: "sqp", "ipopt" or "proxqp".
        cop_offset: planned offset (2,) [m] of the centre of pressure from the stance contact point
            for the rest of the current step (zero for a point foot, ``cop_range = (0, 0)``, and for
            a fallback).
    """

    next_foothold: np.ndarray
    step_duration: float
    time_to_touchdown: float
    footholds: np.ndarray
    durations: np.ndarray
    u: np.ndarray
    z: np.ndarray
    sigma: np.ndarray
    z0: np.ndarray
    success: bool
    fallback: bool
    status: str
    cost: float
    iterations: int
    solve_time: float
    plan_time: float = 0.0
    solver: str = ""
    cop_offset: np.ndarray = field(default_factory=lambda: np.zeros(2))


# ----------------------------------------------------------------------------- inputs
def stone_arrays(stones: Stones, default_size: Sequence[float] = STONE_SIZE) -> tuple[np.ndarray, np.ndarray]:
    """Centres (n, 2) and sizes (n, 2) [m] from a list of :class:`Stone`, a
    :class:`~lipmpcc.terrain.StoneSequence` (its own read-only arrays, checked when it was built), or an
    (n, 2) array of centres."""
    if isinstance(stones, StoneSequence):
        # checked when it was built (finite centres, sizes > 0 or inf, equal lengths) and read-only since
        if len(stones.centers) == 0:
            raise InvalidInputError("stones", stones, "at least one upcoming stone")
        return stones.centers, stones.sizes
    if isinstance(stones, (list, tuple)) and stones and all(isinstance(x, Stone) for x in stones):
        c = np.array([x.center for x in stones], float)
        s = np.array([x.size for x in stones], float)
    else:
        try:
            c = np.asarray(stones, float)
        except (TypeError, ValueError):
            raise InvalidInputError("stones", stones, "Stone objects or an (n, 2) array of stone centres [m]") from None
        if c.ndim != 2 or c.shape[1] != 2:
            raise InvalidInputError("stones", stones, "Stone objects or an (n, 2) array of stone centres [m]")
        s = np.tile(np.asarray(default_size, float), (len(c), 1))
    if len(c) == 0:
        raise InvalidInputError("stones", stones, "at least one upcoming stone")
    if c.shape != s.shape or not np.all(np.isfinite(c)) or np.any(np.isnan(s)) or np.any(s <= 0):
        raise InvalidInputError("stones", stones, "finite stone centres and sizes > 0 [m]")
    return c, s


def pad_stones(c: np.ndarray, s: np.ndarray, n: int, stance: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The first ``n`` regions; fewer stones are extended beyond the last one by repeating the last
    step with its lateral component mirrored (alternating feet), as free regions. With ``n`` or more
    stones the result is a view of ``c`` and ``s`` (read it, do not write into it)."""
    if len(c) >= n:
        return c[:n], s[:n]
    c, s = list(c[:n]), list(s[:n])
    while len(c) < n:
        prev = c[-2] if len(c) >= 2 else stance
        d = c[-1] - prev
        c.append(c[-1] + np.array([d[0], -d[1]]))
        s.append(np.array([np.inf, np.inf]))
    return np.array(c), np.array(s)


def check_xy(name: str, v: ArrayLike, err: type[InvalidInputError] = StateError) -> np.ndarray:
    """``v`` as a finite (x, y) pair [m]; ``err`` names it otherwise."""
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        raise err(name, v, "an (x, y) pair of finite numbers [m]") from None
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise err(name, v, "an (x, y) pair of finite numbers [m]")
    return a


def check_time_since_touchdown(t: float) -> float:
    """``t`` as a finite time since touch-down in [0, 100] [s]."""
    try:
        v = float(t)
    except (TypeError, ValueError):
        raise StateError("t_since_touchdown", t, "a finite time >= 0 [s]") from None
    if not math.isfinite(v) or v < 0 or v > 100.0:
        raise StateError("t_since_touchdown", t, "a finite time in [0, 100] [s]")
    return v


# ----------------------------------------------------------------------------- parameters
class AlipStepParams:
    """The step-timing parameters of both ALIP planners (a mixin of their frozen dataclasses).

    The dataclass defines ``T_nom``, ``T_min``, ``T_max`` [s], ``limits`` (:class:`KinematicLimits`),
    ``w`` [m], ``replan_period`` [s], ``min_time_to_touchdown`` [s], ``dcm_target`` and ``alip``
    (:class:`AlipParams`).
    """

    T_nom: float
    T_min: float
    T_max: float
    limits: KinematicLimits
    w: float
    replan_period: float
    min_time_to_touchdown: float
    dcm_target: str
    alip: AlipParams

    def _check_step_params(self, positive: Sequence[str] = ()) -> None:
        """Validate the shared fields, and the named extra ones as finite numbers > 0."""
        if self.dcm_target not in DCM_TARGETS:
            raise ParameterError("dcm_target", self.dcm_target, "'next' or 'current'")
        for name in ("T_nom", "T_min", "T_max", "w", "replan_period", *positive):
            positive_number(name, getattr(self, name), error=ParameterError)
        if not self.T_min <= self.T_nom <= self.T_max or self.T_min == self.T_max:
            raise ParameterError(
                "T_min, T_nom, T_max", (self.T_min, self.T_nom, self.T_max), "0 < T_min <= T_nom <= T_max, T_min < T_max [s]"
            )
        m = finite_number("min_time_to_touchdown", self.min_time_to_touchdown, "s", error=ParameterError)
        if not 0 <= m < self.T_max:
            raise ParameterError("min_time_to_touchdown", m, "0 <= value < T_max [s]")
        if not isinstance(self.limits, KinematicLimits):
            raise ParameterError("limits", self.limits, "a KinematicLimits")
        if not isinstance(self.alip, AlipParams):
            raise ParameterError("alip", self.alip, "an AlipParams")

    @property
    def lam(self) -> float:
        """λ = √(g/z_c) of the ALIP constants [1/s]."""
        return self.alip.lam

    @property
    def dcm_bounds(self) -> DcmBounds:
        """The viable initial-DCM intervals for these limits and T_min (paper B eq. 6)."""
        return viability_bounds(self.lam, self.T_min, self.limits)

    def scaled(self, length: float = 1.0, width: float = 1.0, time: float = 1.0) -> "AlipStepParams":
        """These parameters on a robot of another size: the forward reach ``limits.x_max`` times ``length``,
        the nominal step width ``w`` and the smallest lateral distance ``limits.y_min`` times ``width`` (the hips'
        spacing), the lateral reach beyond the nominal width, ``limits.y_max - w``, times ``length`` (the legs'), the step durations
        (``T_nom``, ``T_min``, ``T_max``, ``min_time_to_touchdown``) times ``time`` (ratios, 1: unchanged;
        the planner rate, weights and stone size are kept). All three 1 returns ``self`` as is."""
        for name, v in (("length", length), ("width", width), ("time", time)):
            positive_number(name, v, error=ParameterError)
        if (length, width, time) == (1.0, 1.0, 1.0):
            return self
        lim = self.limits
        w = self.w * width
        limits = KinematicLimits(x_max=lim.x_max * length, y_min=lim.y_min * width,
                                 y_max=w + max(lim.y_max - self.w, 0.0) * length)
        return replace(self, T_nom=self.T_nom * time, T_min=self.T_min * time, T_max=self.T_max * time,  # type: ignore[type-var]
                       min_time_to_touchdown=self.min_time_to_touchdown * time, w=w, limits=limits)


# ----------------------------------------------------------------------------- the contract
class AlipPlanner(ABC):
    """The face of an ALIP planner onto the planner contract (a mixin of AlipMpc and AlipQp).

    :meth:`plan` with a :class:`~lipmpcc.planners.base.PlannerInput` reads the DCM, the stance foot
    and side, the time since touch-down and the stones ahead (``inp.course``, a StoneSequence whose
    first stone is the swing foot's target) and calls :meth:`solve`; the
    :class:`~lipmpcc.planners.base.StepPlan` keeps the stance foot's yaw (the ALIP planners do not
    turn), carries the :class:`AlipPlanResult` as ``record``, the preview of the later footholds, the
    centre-of-pressure offset when the planner has a foot, and the status ``"ok"`` unless the solver
    failed and the previous plan answers (``"fallback (...)"``).
    """

    name: str
    params: AlipStepParams

    @property
    def rate_hz(self) -> float:
        """Re-planning rate [Hz]: 1 / ``params.replan_period`` (paper B: 25 Hz)."""
        return 1.0 / self.params.replan_period

    @property
    def has_foot(self) -> bool:
        """True when the planner chooses a centre-of-pressure offset (an ankle)."""
        return False

    @abstractmethod
    def reset(self) -> None:
        """Forget the previous plan and the warm start (a new run)."""

    @abstractmethod
    def solve(
        self, dcm_world: ArrayLike, stance_world: ArrayLike, stance_side: int | str, t_since_touchdown: float,
        stones: Stones,
    ) -> AlipPlanResult:
        """Plan the next footholds and step durations (see the planner's own docstring)."""

    @overload
    def plan(self, inp: PlannerInput) -> StepPlan: ...

    @overload
    def plan(self, dcm_world: ArrayLike, stance_world: ArrayLike, stance_side: int | str, t_since_touchdown: float,
             stones: Stones) -> AlipPlanResult: ...

    @exclusive("planner")
    def plan(self, *args: object, **kwargs: object) -> StepPlan | AlipPlanResult:
        """The planner contract: ``plan(inp: PlannerInput) -> StepPlan``.

        The old form ``plan(dcm_world, stance_world, stance_side, t_since_touchdown, stones) ->
        AlipPlanResult`` still works but is deprecated: it is :meth:`solve`.
        """
        if len(args) == 1 and not kwargs and isinstance(args[0], PlannerInput):
            return self._plan_input(args[0])
        if len(args) + len(kwargs) == 1:
            value = args[0] if args else next(iter(kwargs.values()))
            raise InvalidInputError("inp", value, "a lipmpcc.planners.base.PlannerInput")
        warnings.warn(
            f"{type(self).__name__}.plan(dcm_world, stance_world, stance_side, t_since_touchdown, stones) is "
            f"deprecated: call {type(self).__name__}.solve(...) with these arguments, or plan(PlannerInput)",
            DeprecationWarning,
            stacklevel=2,
        )
        return self.solve(*args, **kwargs)  # type: ignore[arg-type]

    def _plan_input(self, inp: PlannerInput) -> StepPlan:
        if not isinstance(inp.course, StoneSequence):
            raise InvalidInputError("inp.course", inp.course, "the stones ahead, a StoneSequence (next stone first)")
        res = self.solve(inp.dcm, np.asarray(inp.stance_pos, dtype=float)[:2], inp.stance_side,
                         inp.time_since_touchdown, inp.course)
        return to_step_plan(res, float(inp.stance_yaw), self.has_foot)


def to_step_plan(res: AlipPlanResult, yaw: float, has_foot: bool) -> StepPlan:
    """The :class:`~lipmpcc.planners.base.StepPlan` of an ALIP plan (every foothold at ``yaw`` [rad])."""
    preview = np.empty((len(res.footholds), 4))  # rows (x, y, yaw, duration)
    preview[:, 0:2] = res.footholds
    preview[:, 2] = yaw
    preview[:, 3] = res.durations
    return StepPlan(
        foothold=res.next_foothold,
        yaw=yaw,
        duration=float(res.step_duration),
        cop_offset=res.cop_offset if has_foot else None,
        preview=preview,
        cost=float(res.cost),
        solve_time=float(res.solve_time),
        status=res.status if res.fallback else "ok",
        record=res,
    )
