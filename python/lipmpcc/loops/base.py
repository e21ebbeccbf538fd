"""The run contract: what every loop (LIP, ALIP, full body) is given and gives back.

The planner contract (:mod:`lipmpcc.planners.base`) fixes what a footstep planner is given at each call
and what it answers. This module fixes the same for a *run*:

- **Given**: a :class:`Course` (the path followed, the moving obstacles, the stepping stones: whatever the
  run has) and a :class:`PushSchedule` (pushes at absolute times, or timed from the touch-down that
  starts a footstep). Every loop hands the course to the planner at every call
  (``PlannerInput.course`` and ``PlannerInput.obstacles``) and arms the schedule's footstep-timed pushes
  at its touch-downs (:meth:`PushSchedule.arm`).
- **Given back**: a :class:`RunRecord` besides the loop's own log (``log.record``, ``result.record``):
  per footstep the planned and executed foothold and duration, the landing error [m] and the timing
  error [s], and the pushes as they were applied (absolute times).

What a loop may read from a planner beyond :class:`~lipmpcc.planners.base.StepPlan` is two small
protocols on ``StepPlan.record``, never a concrete planner class: :class:`PathProgress` (a planner that
tracks a path parameter ϑ, e.g. paper A's MPCC) and :class:`TimedRecord` (a planner that times its own
calls, e.g. paper B's ALIP planners). From the planner itself a loop reads one optional attribute,
``compensates_touchdown`` (:func:`touchdown_timing`).

**The loop owns its clock.** On the full body a swing foot usually meets the ground a little before the
planned time. A planner that learns that offset itself (the shipped capture-point, MPCC and ALIP sources:
``compensates_touchdown = True``) has each step end at the first contact after a minimum phase; for any
other planner (a student's, written against the planner contract only) the loop keeps the planned time, so
the foot lands where and when the plan says (``LoopParams.touchdown_timing = "auto"``, the default).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable, Protocol, Sequence, runtime_checkable

import numpy as np

from ..exceptions import InvalidInputError
from ..obstacles import Obstacle
from ..paths import Path
from ..planners.base import StepPlan
from ..push import Push
from ..terrain import StoneSequence

__all__ = ["Course", "PushSchedule", "RunRecord", "PathProgress", "TimedRecord", "has_path_progress", "read_timed", "resolve_course",
           "resolve_schedule", "compensates_touchdown", "touchdown_timing"]


@runtime_checkable
class PathProgress(Protocol):
    """A plan record of a planner that follows a path by a path parameter ϑ [m] (paper A's MPCC).

    Attributes:
        theta_init: ϑ of the measured state the plan started from [m].
        theta: the planned ϑ at the step instants (N+1,) [m] (``theta[1]``: at the end of this step).
        v_avg: the mean path progress per step over the horizon [m].
        status: the solver's status.
    """

    theta_init: float
    theta: np.ndarray
    status: str

    @property
    def v_avg(self) -> float: ...


@runtime_checkable
class TimedRecord(Protocol):
    """A plan record that times its planner's whole call (paper B's ALIP planners).

    Attributes:
        plan_time: wall time of the planner call [s].
        status: the solver's status.
    """

    plan_time: float
    status: str


def has_path_progress(record: object) -> bool:
    """Whether a plan record follows :class:`PathProgress` (the same test as ``isinstance(record, PathProgress)``,
    without its cost at every step)."""
    return record is not None and all(hasattr(record, n) for n in ("theta_init", "theta", "status", "v_avg"))


def read_timed(record: object) -> tuple[float, str] | None:
    """``(plan_time [s], status)`` of a plan record that follows :class:`TimedRecord`, else None (the same test
    as ``isinstance(record, TimedRecord)``, without its cost at every planner tick)."""
    plan_time, status = getattr(record, "plan_time", None), getattr(record, "status", None)
    if plan_time is None or status is None:
        return None
    return plan_time, status


def compensates_touchdown(planner: object) -> bool:
    """Whether ``planner`` compensates the robot's touch-down timing itself (its optional attribute
    ``compensates_touchdown`` is True: it learns how early or late the foot meets the ground and plans for it);
    False for a planner without the attribute (one written against the planner contract only)."""
    return getattr(planner, "compensates_touchdown", False) is True


def touchdown_timing(setting: str, planner: object) -> str:
    """Who times a full-body touch-down, ``"planner"`` or ``"loop"``, for the loop's ``setting``
    (``LoopParams.touchdown_timing``): ``"auto"`` is ``"planner"`` for a planner that
    :func:`compensates_touchdown`, else ``"loop"``; ``"planner"`` and ``"loop"`` are kept.

    Raises:
        InvalidInputError: ``setting`` is none of the three.
    """
    if setting == "auto":
        return "planner" if compensates_touchdown(planner) else "loop"
    if setting not in ("planner", "loop"):
        raise InvalidInputError("touchdown_timing", setting, "'planner', 'loop' or 'auto'")
    return setting


@dataclass(frozen=True)
class Course:
    """What a run walks: a path to follow, moving obstacles, stepping stones (any of them).

    Attributes:
        path: the path followed (:class:`~lipmpcc.paths.Path`), or None.
        obstacles: the moving obstacles (their clocks are the loop's time) [m, m/s].
        stones: the footholds in order (:class:`~lipmpcc.terrain.StoneSequence`, footstep ``k`` lands on
            ``stones[k]``), or None.
    """

    path: Path | None = None
    obstacles: tuple[Obstacle, ...] = ()
    stones: StoneSequence | None = None

    def __post_init__(self) -> None:
        if self.path is not None and not isinstance(self.path, Path):
            raise InvalidInputError("course.path", self.path, "a lipmpcc.paths.Path or None")
        if isinstance(self.obstacles, (str, bytes, Obstacle)) or not hasattr(self.obstacles, "__iter__"):
            raise InvalidInputError("course.obstacles", self.obstacles, "a sequence of lipmpcc.obstacles.Obstacle")
        obstacles = tuple(self.obstacles)
        for i, ob in enumerate(obstacles):
            if not isinstance(ob, Obstacle):
                raise InvalidInputError(f"course.obstacles[{i}]", ob, "a lipmpcc.obstacles.Obstacle")
        object.__setattr__(self, "obstacles", obstacles)
        if self.stones is not None and not isinstance(self.stones, StoneSequence):
            raise InvalidInputError("course.stones", self.stones, "a lipmpcc.terrain.StoneSequence or None")

    def stones_ahead(self, step_index: int) -> StoneSequence | None:
        """The stones from footstep ``step_index`` on (the swing foot's target first); None without stones
        or past the last one."""
        q = self.stones
        if q is None or step_index >= len(q):
            return None
        k = max(0, int(step_index))
        return StoneSequence(q.centers[k:], q.sizes[k:], q.sides[k:], q.is_stone[k:], q.name)

    def planner_course(self, step_index: int) -> StoneSequence | Path | None:
        """``PlannerInput.course`` at footstep ``step_index``: the stones ahead when the course has stones,
        else the path (or None)."""
        if self.stones is not None:
            return self.stones_ahead(step_index)
        return self.path


def _pushes(name: str, pushes: Iterable[Push]) -> tuple[Push, ...]:
    if isinstance(pushes, (str, bytes, Push)) or not hasattr(pushes, "__iter__"):
        raise InvalidInputError(name, pushes, "a sequence of lipmpcc.push.Push")
    items = tuple(pushes)
    for i, p in enumerate(items):
        if not isinstance(p, Push):
            raise InvalidInputError(f"{name}[{i}]", p, "a lipmpcc.push.Push(force [N], t_start [s], duration [s])")
    return items


@dataclass(frozen=True)
class PushSchedule:
    """The pushes of a run: at absolute times (``step=None``) or timed from the touch-down that starts
    footstep ``step`` (:class:`~lipmpcc.push.Push`).

    A loop applies :attr:`absolute` from the start and calls :meth:`arm` at each touch-down (and at the
    start, for footstep 0) to turn that footstep's pushes into absolute ones.
    """

    pushes: tuple[Push, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "pushes", _pushes("schedule.pushes", self.pushes))

    @property
    def absolute(self) -> tuple[Push, ...]:
        """The pushes with absolute times, in order."""
        return tuple(p for p in self.pushes if p.step is None)

    @property
    def step_timed(self) -> tuple[Push, ...]:
        """The pushes timed from footsteps, in order."""
        return tuple(p for p in self.pushes if p.step is not None)

    def arm(self, step: int, t_touchdown: float) -> list[Push]:
        """The pushes of footstep ``step`` made absolute: each window shifted by ``t_touchdown`` [s], the time
        of the touch-down that starts that footstep (force and body kept; ``step`` dropped)."""
        return [Push.between(p.force, t_touchdown + p.t_start, t_touchdown + p.t_end, body=p.body)
                for p in self.pushes if p.step == step]


def resolve_course(course: Course | None, path: Path | None = None, obstacles: Sequence[Obstacle] = (),
                   stones: StoneSequence | None = None) -> Course:
    """A loop's :class:`Course` from its new argument ``course`` or its old ones (``path``, ``obstacles``,
    ``stones``); InvalidInputError when both forms are given."""
    old = path is not None or stones is not None or (obstacles is not None and len(tuple(obstacles)) > 0)
    if course is not None:
        if not isinstance(course, Course):
            raise InvalidInputError("course", course, "a lipmpcc.loops.base.Course or None")
        if old:
            raise InvalidInputError("course", course, "None when path / obstacles / stones are given (one or the other)")
        return course
    return Course(path, tuple(obstacles or ()), stones)


def resolve_schedule(schedule: PushSchedule | None, pushes: Iterable[Push] = ()) -> PushSchedule:
    """A loop's :class:`PushSchedule` from its new argument ``schedule`` or its old one ``pushes``;
    InvalidInputError when both are given."""
    items = _pushes("pushes", pushes)
    if schedule is not None:
        if not isinstance(schedule, PushSchedule):
            raise InvalidInputError("schedule", schedule, "a lipmpcc.loops.base.PushSchedule or None")
        if items:
            raise InvalidInputError("schedule", schedule, "None when pushes are given (one or the other)")
        return schedule
    return PushSchedule(items)


@dataclass
class RunRecord:
    """What every loop gives back, per footstep k (touch-down order) [m, s].

    Attributes:
        touchdown_times: (n,) when footstep k's foot landed [s].
        sides: (n,) its side (+1 left, −1 right).
        planned_footholds: (n, 2) where the last plan before the touch-down put it [m].
        footholds: (n, 2) where it landed [m] (the plan's on the reduced models).
        planned_durations: (n,) the step duration [s] the last plan asked for (from the previous touch-down).
        durations: (n,) the executed step duration [s].
        pushes: the pushes as applied (absolute times).
        plans: every planner answer as (t [s], footstep index, :class:`~lipmpcc.planners.base.StepPlan`).
        fell: the run ended in a fall.
        yaws: (n,) the landed feet's yaw [rad] (the full body's measured soles), or None (the reduced models).
    """

    touchdown_times: np.ndarray
    sides: np.ndarray
    planned_footholds: np.ndarray
    footholds: np.ndarray
    planned_durations: np.ndarray
    durations: np.ndarray
    pushes: tuple[Push, ...] = ()
    plans: list[tuple[float, int, StepPlan]] = field(default_factory=list)
    fell: bool = False
    yaws: np.ndarray | None = None

    def __post_init__(self) -> None:
        self.touchdown_times = np.asarray(self.touchdown_times, dtype=float).reshape(-1)
        self.sides = np.asarray(self.sides, dtype=int).reshape(-1)
        self.planned_footholds = np.asarray(self.planned_footholds, dtype=float).reshape(-1, 2)
        self.footholds = np.asarray(self.footholds, dtype=float).reshape(-1, 2)
        self.planned_durations = np.asarray(self.planned_durations, dtype=float).reshape(-1)
        self.durations = np.asarray(self.durations, dtype=float).reshape(-1)
        self.pushes = tuple(self.pushes)
        if self.yaws is not None:
            self.yaws = np.asarray(self.yaws, dtype=float).reshape(-1)
        n = len(self.touchdown_times)
        for name in ("sides", "planned_footholds", "footholds", "planned_durations", "durations") + (
                ("yaws",) if self.yaws is not None else ()):
            if len(getattr(self, name)) != n:
                raise InvalidInputError(f"RunRecord.{name}", len(getattr(self, name)), f"{n} rows (one per touch-down)")

    @property
    def n_steps(self) -> int:
        """Number of touch-downs."""
        return len(self.touchdown_times)

    @property
    def landing_error(self) -> np.ndarray:
        """(n,) distance from each planned foothold to where the foot landed [m]."""
        return np.linalg.norm(self.footholds - self.planned_footholds, axis=1)

    @property
    def timing_error(self) -> np.ndarray:
        """(n,) executed minus planned step duration [s] (> 0: the foot landed late)."""
        return self.durations - self.planned_durations

    def summary(self) -> dict[str, float | int | None]:
        """Largest landing [m] and timing [s] errors (None without steps)."""
        some = self.n_steps > 0
        return {
            "steps": self.n_steps,
            "landing_error_max_m": float(np.max(self.landing_error)) if some else None,
            "timing_error_max_s": float(np.max(np.abs(self.timing_error))) if some else None,
        }

