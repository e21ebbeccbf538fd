"""The outcome of a run, in one place: the summary fields that say how a run ended, and cannot hide.

Every study's ``summary.json`` gets them (:func:`add_outcome`), on every robot:

- ``collided`` (bool): the robot's geometry intersected an obstacle at some tick — on the reduced
  models the body disk or the stance foot (``min_clearance_m`` < 0), on a full body the MuJoCo geometry
  of the whole robot (``min_body_clearance_m`` < 0; the disk clearance when that was not measured);
- ``min_clearance_m`` (the footprint disks' least clearance [m], None without obstacles) and
  ``min_body_clearance_m`` (the whole robot's, full body only, None otherwise);
- ``solver_failures`` (int), ``relaxed_solves`` (int: the whole-body QP's relaxed re-solves, 0 on the
  reduced models), ``warnings`` (list of one-line strings);
- ``stopped_early`` (str: why the run ended before its set length, or None);
- ``outcome``: one of :data:`OUTCOMES`, in that precedence (:func:`outcome`): ``"collided"``, ``"fell"``,
  ``"stopped_early"``, then for a path-following run (paper A's studies and ``follow-path``, from its
  progress trace, :func:`assess_progress`) ``"completed"`` when the end of the path was reached,
  ``"trailing"`` (behind a slower obstacle moving along the path, the preset's choice), ``"stalled"``
  (no progress along the path for :data:`STALL_TIME_S` before the run ended), ``"incomplete"`` (a run
  whose goal is the path's end, still progressing when its set length ran out), else ``"completed"``;
  :data:`SUCCESS_OUTCOMES` are ``completed`` and ``trailing``. New values may be added: a script must
  treat a value it does not know as not a success;
- ``expected_outcome``: the outcome the study is known to have when it is a baseline expected to fail
  (e.g. ``"fell"`` for the point-foot push test), else None.

A path-following run also gets (:meth:`PathAssessment.fields`): ``reached_end`` (bool), ``progress_m``
(kept as the study computed it), ``path_length_m``, ``goal`` (``"end"``: ``follow-path``, the run is to
reach the path's end; ``"length"``: paper A's studies, which run their set number of steps or seconds
on a path longer than that), ``stall`` (None, or where and why the run stopped progressing: ``t_s``,
``progress_m``, ``position``, ``duration_s``, ``backwards_m``, ``binding``), ``trailing_obstacle``
(the index of the obstacle trailed, or None) and ``trailing_gap_m``.

Existing fields keep their values: this module only adds fields, and fills a missing one with its default.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Iterable, Mapping

import numpy as np

from ..exceptions import InvalidInputError

__all__ = [
    "OUTCOMES",
    "SUCCESS_OUTCOMES",
    "GOALS",
    "STALL_TIME_S",
    "STALL_PROGRESS_M",
    "END_TOLERANCE_M",
    "TRAILING_GAP_M",
    "TRAILING_CLOSING_M",
    "BINDING_CLEARANCE_M",
    "ProgressTrace",
    "PathAssessment",
    "assess_progress",
    "outcome",
    "collided",
    "add_outcome",
    "run_outcome",
    "is_expected",
    "is_success",
]

#: the possible outcomes, most severe first (the precedence of :func:`outcome`)
OUTCOMES = ("collided", "fell", "stopped_early", "stalled", "incomplete", "trailing", "completed")
#: the outcomes that count as a success (exit 0): the run reached its goal, or trailed a slower obstacle by the
#: preset's choice
SUCCESS_OUTCOMES = ("completed", "trailing")
#: a path-following run's goal: reach the path's end (``follow-path``), or run the set length (paper A's studies)
GOALS = ("end", "length")
#: [s] a run that gained less than :data:`STALL_PROGRESS_M` along the path over its last this many seconds stalled
STALL_TIME_S = 10.0
#: [m] the least gain of path parameter that counts as progress
STALL_PROGRESS_M = 0.10
#: [m] the end of the path is reached when the robot's closest path parameter comes this near it
END_TOLERANCE_M = 0.30
#: [m] at most this far (centre to centre, along the path) behind an obstacle moving along it, the robot trails it
TRAILING_GAP_M = 3.0
#: [m] a robot that closed the gap to the obstacle ahead by more than this over the last :data:`STALL_TIME_S` is
#: catching up (overtaking), not trailing
TRAILING_CLOSING_M = 0.5
#: [m] an obstacle that came this near the robot while it stalled is named as binding
BINDING_CLEARANCE_M = 0.25


@dataclass(frozen=True)
class ProgressTrace:
    """A path-following run's progress, what its outcome is judged on.

    Attributes:
        t: (n,) times [s], increasing.
        progress: (n,) the robot's closest path parameter (arc length) [m].
        position: (n, 2) the robot's position (its COM) [m].
        path_length: the path's length [m].
        goal: ``"end"`` (the run is to reach the path's end) or ``"length"`` (to run its set length).
        clearance: (n_obs, n) each obstacle's clearance to the robot [m] (None: no obstacles).
        along: (n_obs, n) the path parameter of each obstacle moving along the path [m], NaN for the others
            (None: no obstacles).
        along_speed: (n_obs,) each obstacle's speed along the path [m/s], NaN for the others.
        reached_end_by_loop: the loop itself stopped at the end of the path (the LIP's rule: the MPCC's
            committed path parameter reached it).
        planned_clearance: (n_obs, n) each obstacle's least clearance [m] to the robot as the planner's latest
            plan at each time predicted it over its horizon (NaN before the first plan; None: not known).
        held: (n_obs, n) whether the planner's latest plan at each time held the robot in place because its
            fallback would have walked into that obstacle (``MpccResult.held_by``; None: not known).
    """

    t: np.ndarray
    progress: np.ndarray
    position: np.ndarray
    path_length: float
    goal: str = "end"
    clearance: np.ndarray | None = None
    along: np.ndarray | None = None
    along_speed: np.ndarray | None = None
    reached_end_by_loop: bool = False
    planned_clearance: np.ndarray | None = None
    held: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.goal not in GOALS:
            raise InvalidInputError("goal", self.goal, f"one of {', '.join(GOALS)}")
        t = np.asarray(self.t, dtype=float).reshape(-1)
        p = np.asarray(self.progress, dtype=float).reshape(-1)
        pos = np.asarray(self.position, dtype=float).reshape(-1, 2)
        if not (len(t) == len(p) == len(pos)):
            raise InvalidInputError("progress trace", f"{len(t)} times, {len(p)} progress values, {len(pos)} positions",
                                    "as many of each")
        if not (math.isfinite(self.path_length) and self.path_length >= 0.0):
            raise InvalidInputError("path_length", self.path_length, "a length >= 0 [m]")
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "progress", p)
        object.__setattr__(self, "position", pos)
        for name in ("clearance", "along", "planned_clearance", "held"):
            v = getattr(self, name)
            if v is not None:
                v = np.asarray(v, dtype=float)
                v = v.reshape(-1, len(t)) if len(t) else v.reshape(len(v) if v.ndim else 0, 0)
                object.__setattr__(self, name, v)
        if self.along_speed is not None:
            object.__setattr__(self, "along_speed", np.asarray(self.along_speed, dtype=float).reshape(-1))


@dataclass(frozen=True)
class PathAssessment:
    """What a progress trace says (:func:`assess_progress`): see the module doc for the fields."""

    reached_end: bool
    progress_m: float
    path_length_m: float
    goal: str
    stall: dict[str, Any] | None = None
    trailing_obstacle: int | None = None
    trailing_gap_m: float | None = None
    no_progress_max_s: float = 0.0

    @property
    def stalled(self) -> bool:
        """The run ended stalled (:data:`STALL_TIME_S` without progress, the end not reached)."""
        return self.stall is not None

    @property
    def trailing(self) -> bool:
        """The run ended behind a slower obstacle moving along the path."""
        return self.trailing_obstacle is not None

    @property
    def incomplete(self) -> bool:
        """A run whose goal is the path's end did not reach it."""
        return self.goal == "end" and not self.reached_end

    def fields(self) -> dict[str, Any]:
        """The summary fields (``progress_m`` is the study's, not overwritten by :func:`add_outcome`)."""
        return {"reached_end": bool(self.reached_end), "progress_m": float(self.progress_m),
                "path_length_m": float(self.path_length_m), "goal": self.goal, "stall": self.stall,
                "trailing_obstacle": self.trailing_obstacle, "trailing_gap_m": self.trailing_gap_m,
                "no_progress_max_s": float(self.no_progress_max_s)}


def _last_progress(t: np.ndarray, p: np.ndarray) -> tuple[int, float]:
    """The index of the last progress event (the path parameter first exceeding the previous event's by
    :data:`STALL_PROGRESS_M`; the first sample is one) and the longest time between two events, or from the
    last one to the end [s]."""
    anchor, i_anchor, longest = p[0], 0, 0.0
    for j in range(1, len(p)):
        if p[j] >= anchor + STALL_PROGRESS_M:
            longest = max(longest, float(t[j] - t[i_anchor]))
            anchor, i_anchor = p[j], j
    return i_anchor, max(longest, float(t[-1] - t[i_anchor]))


def _planned_binding(trace: ProgressTrace, i0: int) -> tuple[list[int], np.ndarray]:
    """The obstacles the planner's predictions came within :data:`BINDING_CLEARANCE_M` of while the run
    stalled (from sample ``i0``), and each obstacle's least predicted clearance [m] (NaN: unknown)."""
    pc = trace.planned_clearance
    n_obs = 0 if trace.clearance is None else trace.clearance.shape[0]
    if pc is None or pc.shape[0] != n_obs or not pc[:, i0:].size:
        return [], np.full(n_obs, np.nan)
    window = pc[:, i0:]
    least = np.array([np.nanmin(r) if np.any(np.isfinite(r)) else np.nan for r in window])
    return [int(k) for k in np.flatnonzero(np.isfinite(least) & (least <= BINDING_CLEARANCE_M))], least


def _held_binding(trace: ProgressTrace, i0: int) -> list[int]:
    """The obstacles the planner held the robot in place for while the run stalled (from sample ``i0``)."""
    h = trace.held
    n_obs = 0 if trace.clearance is None else trace.clearance.shape[0]
    if h is None or h.shape[0] != n_obs or not h[:, i0:].size:
        return []
    return [int(k) for k in np.flatnonzero(np.any(h[:, i0:] > 0.5, axis=1))]


def _binding(trace: ProgressTrace, i0: int) -> dict[str, Any]:
    """Which obstacles were binding while the run stalled (from sample ``i0`` to the end): those the planner
    held the robot in place for, its fallback barred by them (``kind`` ``"held"``: no way out); else those
    whose clearance to the robot came within :data:`BINDING_CLEARANCE_M` (``"obstacle"``); else those the
    planner's predicted robot came that near (``"planned"``: the obstacle's barrier held the plan back); else
    none (``"planner"``), with the nearest one. ``held_obstacles`` lists the first kind's."""
    c = trace.clearance
    if c is None or not c.size:
        return {"kind": "planner", "obstacles": [], "clearance_m": [], "nearest_obstacle": None,
                "nearest_clearance_m": None, "planned_obstacles": [], "planned_clearance_m": [],
                "held_obstacles": [], "text": "no obstacle: the planner stopped advancing along the path"}
    least = np.min(c[:, i0:], axis=1)
    near = [int(k) for k in np.flatnonzero(least <= BINDING_CLEARANCE_M)]
    k = int(np.argmin(least))
    planned, predicted = _planned_binding(trace, i0)
    out: dict[str, Any] = {"obstacles": near, "clearance_m": [float(least[j]) for j in near],
                           "nearest_obstacle": k, "nearest_clearance_m": float(least[k]),
                           "planned_obstacles": planned, "planned_clearance_m": [float(predicted[j]) for j in planned],
                           "held_obstacles": _held_binding(trace, i0)}
    if out["held_obstacles"]:
        names = ", ".join(str(j) for j in out["held_obstacles"])
        out.update(kind="held", text=f"no way out: the planner found no plan and held the robot in place rather than "
                                     f"walk into obstacle{'s' if len(out['held_obstacles']) > 1 else ''} {names}")
        return out
    if near:
        names = ", ".join(f"{j} ({least[j]:.3f} m)" for j in near)
        out.update(kind="obstacle", text=f"obstacle{'s' if len(near) > 1 else ''} {names} blocked the robot "
                                         f"(clearance within {BINDING_CLEARANCE_M:g} m while it stalled)")
        return out
    if planned:
        names = ", ".join(f"{j} ({predicted[j]:.3f} m)" for j in planned)
        out.update(kind="planned", text=f"no obstacle within {BINDING_CLEARANCE_M:g} m of the robot (nearest: {k} at "
                                        f"{least[k]:.2f} m), but the planner's predictions came within it of obstacle"
                                        f"{'s' if len(planned) > 1 else ''} {names}: its barrier held the plan back")
    else:
        out.update(kind="planner", text=f"no obstacle within {BINDING_CLEARANCE_M:g} m of the robot or of its plans "
                                        f"(nearest: {k} at {least[k]:.2f} m): the planner stopped advancing along "
                                        "the path")
    return out


def _trailing(trace: ProgressTrace, reached_end: bool) -> tuple[int | None, float | None]:
    """The obstacle moving forward along the path that the robot ends behind, within :data:`TRAILING_GAP_M`
    (the nearest), held to its pace (the gap closed by less than :data:`TRAILING_CLOSING_M` over the last
    :data:`STALL_TIME_S`; a shorter run does not tell), and the gap along the path [m] (centre to centre)."""
    if reached_end or trace.along is None or trace.along_speed is None or not len(trace.t):
        return None, None
    if trace.t[-1] - trace.t[0] < STALL_TIME_S:  # too short to tell trailing from catching up
        return None, None
    i_before = int(np.searchsorted(trace.t, trace.t[-1] - STALL_TIME_S))
    best, gap = None, math.inf
    for k, (s, v) in enumerate(zip(trace.along[:, -1], trace.along_speed)):
        if not (math.isfinite(s) and math.isfinite(v) and v > 0.0):
            continue
        g = float(s - trace.progress[-1])
        closed = float(trace.along[k, i_before] - trace.progress[i_before]) - g
        # an obstacle that has walked on past the path's end (lipmpcc.obstacles.Obstacle.center) still holds a
        # robot within TRAILING_GAP_M behind it to its pace
        if 0.0 <= g <= TRAILING_GAP_M and closed < TRAILING_CLOSING_M and g < gap:
            best, gap = k, g
    return best, (gap if best is not None else None)


def assess_progress(trace: ProgressTrace, progress_m: float | None = None) -> PathAssessment:
    """Judge a path-following run from its progress trace.

    - ``reached_end``: the final closest path parameter is within :data:`END_TOLERANCE_M` of the path's end,
      or the loop stopped there (``reached_end_by_loop``).
    - ``stall``: the end not reached, and the path parameter gained less than :data:`STALL_PROGRESS_M` over
      the last :data:`STALL_TIME_S` or more (backwards counts as no progress): where the last progress was
      made (``t_s``, ``progress_m``, ``position``), for how long (``duration_s``), how far it went back since
      (``backwards_m``) and what was binding (``binding``: the obstacles within :data:`BINDING_CLEARANCE_M`).
    - ``trailing_obstacle``: the end not reached, the nearest obstacle moving forward along the path that the
      robot ends at most :data:`TRAILING_GAP_M` behind, held to its pace over the last :data:`STALL_TIME_S` (the
      run at least that long).

    Args:
        trace: the run's progress.
        progress_m: the run's final progress as its summary reports it [m] (None: the trace's last value).
    """
    t, p = trace.t, trace.progress
    final = float(p[-1]) if len(p) else 0.0
    shown = final if progress_m is None else float(progress_m)
    if not len(t):
        return PathAssessment(bool(trace.reached_end_by_loop), shown, trace.path_length, trace.goal)
    reached = bool(trace.reached_end_by_loop or final >= trace.path_length - END_TOLERANCE_M)
    i0, longest = _last_progress(t, p)
    stall = None
    if not reached and t[-1] - t[i0] >= STALL_TIME_S:
        pos = trace.position[i0]
        stall = {"t_s": float(t[i0]), "progress_m": float(p[i0]), "position": [float(pos[0]), float(pos[1])],
                 "duration_s": float(t[-1] - t[i0]), "backwards_m": float(max(0.0, np.max(p[i0:]) - final)),
                 "binding": _binding(trace, i0)}
    k, gap = _trailing(trace, reached)
    return PathAssessment(reached, shown, float(trace.path_length), trace.goal, stall, k, gap, longest)


def outcome(fell: bool, collided: bool, stopped_early: str | None, path: PathAssessment | None = None) -> str:
    """How a run ended (:data:`OUTCOMES`): ``"collided"`` > ``"fell"`` > ``"stopped_early"``, then for a
    path-following run (``path``) ``"completed"`` when it reached the end > ``"trailing"`` > ``"stalled"`` >
    ``"incomplete"`` (its goal the end) > ``"completed"``.

    Args:
        fell: the robot fell (or the reduced model left its viable set).
        collided: the robot's geometry intersected an obstacle.
        stopped_early: why the run stopped before its set length, or None (empty: None).
        path: a path-following run's :class:`PathAssessment` (None: no path to follow).
    """
    if collided:
        return "collided"
    if fell:
        return "fell"
    if stopped_early:
        return "stopped_early"
    if path is None or path.reached_end:
        return "completed"
    if path.trailing:
        return "trailing"
    if path.stalled:
        return "stalled"
    if path.incomplete:
        return "incomplete"
    return "completed"


def _finite(x: Any) -> float | None:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def collided(min_clearance_m: float | None, min_body_clearance_m: float | None = None) -> bool:
    """Whether a clearance went below zero [m]: the whole body's when measured, else the footprint's."""
    body = _finite(min_body_clearance_m)
    if body is not None:
        return body < 0.0
    disk = _finite(min_clearance_m)
    return disk is not None and disk < 0.0


def add_outcome(
    summary: dict[str, Any],
    *,
    stopped_early: str | None = None,
    result: object = None,
    expected_outcome: str | None = None,
    warnings: Iterable[str] = (),
    path: PathAssessment | None = None,
) -> dict[str, Any]:
    """Add the outcome fields (module doc) to ``summary`` in place and return it.

    Args:
        summary: the study's summary; reads ``fell``, ``min_clearance_m``, ``min_body_clearance_m`` and
            ``solver_failures`` when present.
        stopped_early: why the run ended before its set length (None: it did not).
        result: the full-body loop's result, or None: its ``relaxed_solves``, ``warnings`` and
            ``stopped_early`` are read when it has them.
        expected_outcome: the outcome a baseline is known to have (one of :data:`OUTCOMES`), or None.
        warnings: the study's own one-line warnings (the loop's come first).
        path: a path-following run's :func:`assess_progress`: its fields are added (an existing
            ``progress_m`` is kept) and it decides between the path outcomes.
    """
    if expected_outcome is not None and expected_outcome not in OUTCOMES:
        raise InvalidInputError("expected_outcome", expected_outcome, f"one of {', '.join(OUTCOMES)} or None")
    summary.setdefault("min_clearance_m", None)
    summary.setdefault("min_body_clearance_m", None)
    summary.setdefault("solver_failures", 0)
    hit = collided(summary["min_clearance_m"], summary["min_body_clearance_m"])
    summary["collided"] = hit
    summary["relaxed_solves"] = int(getattr(result, "relaxed_solves", 0) or 0)
    summary["warnings"] = [str(w) for w in getattr(result, "warnings", None) or []] + [str(w) for w in warnings]
    loop_stop = getattr(result, "stopped_early", None)
    reason = stopped_early or (str(loop_stop) if loop_stop else None)
    summary["stopped_early"] = reason
    if path is not None:
        for k, v in path.fields().items():
            if k != "progress_m" or k not in summary:
                summary[k] = v
    summary["outcome"] = outcome(bool(summary.get("fell", False)), hit, reason, path)
    summary["expected_outcome"] = expected_outcome
    return summary


def run_outcome(summary: Mapping[str, Any]) -> str:
    """How the run of a written ``summary`` ended: its ``outcome`` field when it is one of :data:`OUTCOMES`,
    else :func:`outcome` of its ``fell``, ``collided`` and ``stopped_early`` (a missing field counts as
    False/None; a summary of an older lipmpcc has none of them). A value this lipmpcc does not know (a newer
    one's) is returned as it is when those fields would call the run a success: it is never taken for one."""
    value = summary.get("outcome")
    if isinstance(value, str) and value in OUTCOMES:
        return value
    derived = outcome(bool(summary.get("fell")), bool(summary.get("collided")), summary.get("stopped_early") or None)
    if isinstance(value, str) and value and derived in SUCCESS_OUTCOMES:
        return value
    return derived


def is_success(summary: Mapping[str, Any]) -> bool:
    """The run reached its goal: its outcome is one of :data:`SUCCESS_OUTCOMES` (an unknown one is not)."""
    return run_outcome(summary) in SUCCESS_OUTCOMES


def is_expected(summary: Mapping[str, Any]) -> bool:
    """True when the run failed the way its study is known to (a baseline: ``expected_outcome`` equals the
    outcome, which is not a success): reported as such, not as a failure of the run."""
    result = run_outcome(summary)
    return result not in SUCCESS_OUTCOMES and summary.get("expected_outcome") == result
