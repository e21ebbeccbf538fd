"""The footstep-planner contract: the one interface every planner implements.

A planner is any object with a ``name``, a ``rate_hz``, ``reset()`` and ``plan(inp) -> StepPlan``
(:class:`FootstepSource`). Every loop calls it the same way — the reduced LIP and ALIP loops
(:mod:`lipmpcc.loops.lip`, :mod:`lipmpcc.loops.alip`) and the full-body loop in MuJoCo
(:mod:`lipmpcc.loops.fullbody`) — so a planner written once runs in all three:

- **Given** (:class:`PlannerInput`): the measured state (COM position and velocity, DCM, the
  centroidal angular momentum when there is a body), the stance foot (side, position, yaw), the
  swing foot, the time since the stance foot touched down, the step index and, when the loop has
  them, the course (the stones ahead, or the path being followed) and the moving obstacles.
- **Returned** (:class:`StepPlan`): where the swing foot lands (foothold [m], yaw [rad]) and when
  (the step's duration from the stance foot's touch-down [s]); optionally a centre-of-pressure
  offset for the rest of the step (an ankle), a preview of later steps, and the planner's own
  record (e.g. the :class:`~lipmpcc.planners.mpcc.MpccResult` behind the plan).
- **Failure**: a planner that did not solve but can still answer (e.g. the previous plan, shifted)
  returns a plan whose ``status`` is not ``"ok"`` (:attr:`StepPlan.ok` is False): the loop counts
  it as a solver failure and walks on. A planner with nothing to offer raises
  :class:`~lipmpcc.exceptions.NoFallbackPlanError`; the loop stops and reports it.

Loops call ``plan`` at touch-down and then at ``rate_hz`` during the swing (re-planning within
the step, paper B); a planner that plans once per step (paper A's MPCC on the LIP) answers the
later calls with the plan it made at touch-down. On the 3D-LIP (:mod:`lipmpcc.loops.lip`) the
swing takes no time: that loop calls ``plan`` once per step, at the support exchange, when the swing
foot lands; ``time_since_touchdown`` is then the length of the step that ends, and the plan's
``duration`` the length of the step that starts on the new foot (for a planner with a fixed step
duration, the same T as in the other loops).

The loop owns its clock: on the full body the foot lands where the plan puts it and when the plan says
(to a WBC tick), whether or not it met the ground a little earlier. A planner that learns the robot's
touch-down timing itself (how early the foot meets the ground) may say so with an optional class
attribute ``compensates_touchdown = True``; the full-body loop then ends each step at the foot's first
contact after a minimum phase, and the planner re-times its plans from the executed touch-downs
(:mod:`lipmpcc.loops.base`, ``LoopParams.touchdown_timing``).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol, Sequence, Union, runtime_checkable

import numpy as np

from ..conventions import Side, parse_side
from ..exceptions import ParameterError, StateError

if TYPE_CHECKING:
    from ..obstacles import Obstacle
    from ..paths import Path
    from ..terrain import StoneSequence

__all__ = ["PlannerInput", "StepPlan", "FootstepSource", "Course", "check_rate_hz"]

#: what a loop may hand a planner as the course: the stones ahead, or the path being followed
Course = Union["StoneSequence", "Path", None]


@dataclass(frozen=True)
class PlannerInput:
    """What a loop gives a footstep planner at each of its updates (world frame, flat ground).

    Attributes:
        t: time [s].
        com_pos: COM position (3,) [m].
        com_vel: COM velocity (3,) [m/s].
        dcm: divergent component of motion ξ = c + ċ/ω (2,) [m].
        omega: the loop's LIP ω = √(g/H) [1/s].
        stance_side: the foot on the ground (:class:`~lipmpcc.conventions.Side` or its string);
            the other one swings next.
        stance_pos: stance sole (contact point) position (3,) [m].
        stance_yaw: stance foot yaw [rad].
        swing_pos: swing sole position (3,) [m].
        swing_yaw: swing foot yaw [rad].
        time_since_touchdown: time since the stance foot touched down (or since walking started) [s].
        step_index: number of touch-downs so far.
        torso_yaw: measured torso (on the LIP: the heading state) heading [rad].
        angular_momentum: centroidal angular momentum about the COM (3,) [kg m²/s], when available
            (from the last WBC tick); the angular momentum about the stance contact point, for an
            ALIP planner, is ``angular_momentum + mass · (com_pos − stance_pos) × com_vel``.
        mass: total robot mass [kg].
        course: the stones ahead (the first is the current swing foot's target) or the path
            followed, when the loop has one; None otherwise.
        obstacles: the moving obstacles the loop knows of (their clocks are the loop's time ``t``);
            empty when it knows none.
    """

    t: float
    com_pos: np.ndarray
    com_vel: np.ndarray
    dcm: np.ndarray
    omega: float
    stance_side: Side | str
    stance_pos: np.ndarray
    stance_yaw: float
    swing_pos: np.ndarray
    swing_yaw: float
    time_since_touchdown: float
    step_index: int
    torso_yaw: float
    angular_momentum: np.ndarray | None = None
    mass: float = float("nan")
    course: Course = None
    obstacles: Sequence["Obstacle"] = ()

    def __post_init__(self) -> None:
        for name, size in (("com_pos", 3), ("com_vel", 3), ("dcm", 2), ("stance_pos", 3), ("swing_pos", 3)):
            object.__setattr__(self, name, _vector(f"PlannerInput.{name}", getattr(self, name), size))
        if self.angular_momentum is not None:
            object.__setattr__(self, "angular_momentum", _vector("PlannerInput.angular_momentum", self.angular_momentum, 3))
        for name, unit in (("t", "s"), ("stance_yaw", "rad"), ("swing_yaw", "rad"), ("time_since_touchdown", "s"),
                           ("torso_yaw", "rad")):
            _real(f"PlannerInput.{name}", getattr(self, name), f"a finite number [{unit}]")
        _real("PlannerInput.omega", self.omega, "a positive LIP frequency [1/s]", positive=True)
        if not (isinstance(self.mass, numbers.Real) and not isinstance(self.mass, bool)
                and (math.isnan(self.mass) or (math.isfinite(self.mass) and self.mass > 0))):
            raise StateError("PlannerInput.mass", self.mass, "a positive mass [kg] (nan: unknown)")
        if isinstance(self.step_index, bool) or not isinstance(self.step_index, numbers.Integral) or self.step_index < 0:
            raise StateError("PlannerInput.step_index", self.step_index, "an integer >= 0")
        try:
            parse_side(self.stance_side)
        except ValueError:
            raise StateError("PlannerInput.stance_side", self.stance_side, "a Side or 'left'/'right'") from None

    @property
    def swing_side(self) -> Side:
        """The foot that swings (the one opposite the stance foot)."""
        return Side(self.stance_side).other


@dataclass(frozen=True)
class StepPlan:
    """A planner's answer: where and when the swing foot lands.

    Attributes:
        foothold: next foothold (2,) [m] in the world frame (z is the ground height under it).
        yaw: foothold yaw, also the planned torso heading at the end of the step [rad].
        duration: step duration from the stance foot's touch-down to the next touch-down [s].
        com_target: optional COM target at the end of the step (2,) or (3,) [m].
        cop_offset: optional planned centre of pressure for the rest of the step, as an offset (2,) [m]
            from the stance contact point (the LIP pivot at the step's start), world axes: the loop's
            LIP COM reference then turns about it (an ankle strategy). None: about the contact point.
        preview: optional future steps as rows (x, y, yaw, duration) [m, m, rad, s].
        cost: optional planner cost.
        solve_time: planner wall time [s].
        status: ``"ok"`` when the planner solved; anything else names how it answered without a
            solution (e.g. ``"fallback (...)"``): the loop counts it as a solver failure.
        record: the planner's own record of this plan (e.g. an
            :class:`~lipmpcc.planners.mpcc.MpccResult`), for logs and plots; None if it keeps none.
    """

    foothold: np.ndarray
    yaw: float
    duration: float
    com_target: np.ndarray | None = None
    cop_offset: np.ndarray | None = None
    preview: np.ndarray | None = None
    cost: float = float("nan")
    solve_time: float = 0.0
    status: str = "ok"
    record: object | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "foothold", _vector("StepPlan.foothold", self.foothold, 2, "position [m]"))
        _real("StepPlan.yaw", self.yaw, "a finite yaw [rad]")
        _real("StepPlan.duration", self.duration, "a positive step duration [s]", positive=True)
        if self.cop_offset is not None:
            object.__setattr__(self, "cop_offset", _vector("StepPlan.cop_offset", self.cop_offset, 2, "offset [m]",
                                                           "None or "))
        if self.com_target is not None:
            object.__setattr__(self, "com_target", _vector("StepPlan.com_target", self.com_target, (2, 3), "target [m]",
                                                           "None or "))
        if not isinstance(self.status, str):
            raise StateError("StepPlan.status", self.status, "a string (\"ok\" when the planner solved)")

    @property
    def ok(self) -> bool:
        """True when the planner solved (``status == "ok"``)."""
        return self.status == "ok"


def _vector(name: str, value: object, size: int | tuple[int, ...], what: str = "vector", prefix: str = "") -> np.ndarray:
    """``value`` as a finite float vector of ``size`` entries (a tuple: one of them), else StateError."""
    sizes = (size,) if isinstance(size, int) else size
    if type(value) is np.ndarray and value.dtype == np.float64:  # the loops' case: no conversion
        a = value.reshape(-1)
    else:
        try:
            a = np.asarray(value, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise StateError(name, value, _expected_vector(sizes, what, prefix)) from None
    # a few entries: Python's isfinite on a list costs less than numpy's call
    if a.size not in sizes or not (all(map(math.isfinite, a.tolist())) if a.size <= 8 else np.isfinite(a).all()):
        raise StateError(name, value, _expected_vector(sizes, what, prefix))
    return a


def _expected_vector(sizes: tuple[int, ...], what: str, prefix: str) -> str:
    """What :func:`_vector` expected (built only for the error: planners' loops call it every tick)."""
    return f"{prefix}a finite ({' or '.join(f'{n},' for n in sizes)}) {what}"


def _real(name: str, value: object, expected: str, positive: bool = False) -> None:
    """A finite real number (``positive``: > 0), else StateError (a bool, a string or None is refused)."""
    if type(value) is float:  # the common case, without the abstract-class check
        if math.isfinite(value) and (not positive or value > 0):
            return
        raise StateError(name, value, expected)
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or (positive and value <= 0):
        raise StateError(name, value, expected)


def check_rate_hz(planner: object, max_hz: float) -> float:
    """A planner's ``rate_hz`` [Hz] as a float, checked: a number in (0, ``max_hz``] (a loop cannot plan more
    often than it ticks; a string, NaN or 1e9 would make it stall or spin).

    Raises:
        ParameterError: naming ``planner.rate_hz``, its value and the range.
    """
    rate = getattr(planner, "rate_hz", None)
    if isinstance(rate, bool) or not isinstance(rate, numbers.Real) or not (math.isfinite(rate) and 0.0 < rate <= max_hz):
        raise ParameterError("planner.rate_hz", rate, f"a number of re-plans per second > 0 and <= {max_hz:g} Hz "
                             "(the loop's control rate)")
    return float(rate)


@runtime_checkable
class FootstepSource(Protocol):
    """A footstep planner (capture point, MPCC, ALIP-MPC, ALIP-QP, or your own).

    Attributes:
        name: planner name used in summaries (e.g. ``"capture-point"``).
        rate_hz: how often a loop calls :meth:`plan` during a swing [Hz].

    Optional attribute (not part of the protocol check): ``compensates_touchdown`` — True for a planner
    that learns the robot's touch-down timing itself (see the module doc); absent or False: the loop keeps
    each step's planned duration.
    """

    name: str
    rate_hz: float

    def reset(self) -> None:
        """Forget any internal state before a new run."""

    def plan(self, inp: PlannerInput) -> StepPlan:
        """The next foothold, heading and step duration for the current swing foot."""
