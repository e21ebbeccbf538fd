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
- ``outcome``: ``"collided"``, ``"fell"``, ``"stopped_early"`` or ``"completed"``, in that precedence
  (:func:`outcome`);
- ``expected_outcome``: the outcome the study is known to have when it is a baseline expected to fail
  (e.g. ``"fell"`` for the point-foot push test), else None.

Existing fields keep their values: this module only adds fields, and fills a missing one with its default.
"""

from __future__ import annotations

import math
from typing import Any, Iterable, Mapping

from ..exceptions import InvalidInputError

__all__ = ["OUTCOMES", "outcome", "collided", "add_outcome", "run_outcome", "is_expected"]

#: the possible outcomes, most severe first (the precedence of :func:`outcome`)
OUTCOMES = ("collided", "fell", "stopped_early", "completed")


def outcome(fell: bool, collided: bool, stopped_early: str | None) -> str:
    """How a run ended: ``"collided"`` > ``"fell"`` > ``"stopped_early"`` > ``"completed"``.

    Args:
        fell: the robot fell (or the reduced model left its viable set).
        collided: the robot's geometry intersected an obstacle.
        stopped_early: why the run stopped before its set length, or None (empty: None).
    """
    if collided:
        return "collided"
    if fell:
        return "fell"
    if stopped_early:
        return "stopped_early"
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
    summary["outcome"] = outcome(bool(summary.get("fell", False)), hit, reason)
    summary["expected_outcome"] = expected_outcome
    return summary


def run_outcome(summary: Mapping[str, Any]) -> str:
    """How the run of a written ``summary`` ended, one of :data:`OUTCOMES`: its ``outcome`` field when it
    has a valid one, else :func:`outcome` of its ``fell``, ``collided`` and ``stopped_early`` (a missing
    field counts as False/None; a summary of an older lipmpcc has none of them)."""
    value = summary.get("outcome")
    if isinstance(value, str) and value in OUTCOMES:
        return value
    return outcome(bool(summary.get("fell")), bool(summary.get("collided")), summary.get("stopped_early") or None)


def is_expected(summary: Mapping[str, Any]) -> bool:
    """True when the run failed the way its study is known to (a baseline: ``expected_outcome`` equals the
    outcome, which is not ``"completed"``): reported as such, not as a failure of the run."""
    result = run_outcome(summary)
    return result != "completed" and summary.get("expected_outcome") == result
