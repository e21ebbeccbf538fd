"""Paper B's metrics, once for both robots (:mod:`lipmpcc.studies.stepping_stones`).

A stones run is scored from the ALIP loop's log (:class:`~lipmpcc.loops.alip.AlipLoopLog`) by
:func:`~lipmpcc.loops.alip.loop_metrics`, on the ALIP and on a full body alike: a full-body run is recorded in that
log (:func:`full_body_stones_log`: the measured soles at touch-down, the loop's COM samples, the source's plans),
and :func:`stone_metrics` scores it with the planner under test's own solve times.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..loops.alip import AlipLoopLog, loop_metrics
from ..metrics import timing_stats_ms
from ..models.alip import KinematicLimits
from ..push import Push
from ..terrain import StoneSequence

if TYPE_CHECKING:  # pragma: no cover
    from ..loops.base import RunRecord
    from ..loops.fullbody.loop import LoopResult
    from ..planners.sources.alip import AlipFootstepSource, AlipSourceRecord

__all__ = ["full_body_stones_log", "stone_metrics", "stones_reached"]


def _step_fields(record: RunRecord, n: int, course: StoneSequence, recs: Sequence[AlipSourceRecord],
                 lim: KinematicLimits, tol: float, t0: float, lam: float) -> dict[str, Any]:
    """Per footstep of the first ``n`` of the loop's :class:`~lipmpcc.loops.base.RunRecord`: the measured soles at
    touch-down, their checks, durations and initial DCMs (eq. 10 at the planner's first call of each step)."""
    feet = record.footholds[:n].copy()
    sides = record.sides[:n].copy()
    in_stone = np.array([(not course.is_stone[k]) or course[k].contains(feet[k], tol) for k in range(n)], dtype=bool)
    prev = [recs[0].stance if recs else np.zeros(2)] + [feet[k] for k in range(n - 1)]
    first: dict[int, AlipSourceRecord] = {}
    for r in recs:
        first.setdefault(r.step_index, r)
    z_init = [(first[k].dcm - first[k].stance) * math.exp(-lam * first[k].time_since_touchdown) for k in sorted(first) if k <= n]
    return {
        "footholds": feet,
        "step_index": np.arange(n, dtype=int),
        "step_sides": sides,
        "durations": record.durations[:n].copy(),
        "td_times": record.touchdown_times[:n] - t0,
        "z_initial": np.array(z_init, dtype=float).reshape(-1, 2),
        "in_stone": in_stone,
        "kin_ok": np.array([lim.contains(feet[k] - prev[k], int(sides[k]), 1e-3) for k in range(n)], dtype=bool),
    }


def _plan_fields(recs: Sequence[AlipSourceRecord], t0: float) -> dict[str, Any]:
    """Per planner call: time, footstep, planned duration and foothold, timing, fallback, status."""
    return {
        "plan_t": np.array([r.t for r in recs], dtype=float) - t0,
        "plan_step": np.array([r.step_index for r in recs], dtype=int),
        "plan_t_step": np.array([r.time_since_touchdown for r in recs], dtype=float),
        "plan_T": np.array([r.planned_duration for r in recs], dtype=float),
        "plan_foothold": np.array(
            [r.result.next_foothold if r.result is not None else np.full(2, np.nan) for r in recs], dtype=float
        ).reshape(-1, 2),
        "solve_time": np.array([r.result.solve_time if r.result is not None else np.nan for r in recs], dtype=float),
        "plan_time": np.array([r.result.plan_time if r.result is not None else np.nan for r in recs], dtype=float),
        "plan_fallback": np.array([r.result is None or bool(r.result.fallback) for r in recs], dtype=bool),
        "plan_status": [r.status for r in recs],
    }


def _fall_fields(result: LoopResult, in_stone: np.ndarray, n_course: int, t0: float, reason: str) -> dict[str, Any]:
    """The failure as the ALIP loop records it: ``fall_index`` is the footstep under way (the last one
    when it landed off its stone)."""
    n = len(in_stone)
    fell = bool(result.fell)
    fall_index = None
    if fell:
        fall_index = int(len(result.touchdowns))
        if n and not in_stone[-1] and fall_index == n:
            fall_index = n - 1
    return {
        "fell": fell,
        "fall_index": fall_index,
        "fall_reason": reason,
        "fall_time": (float(result.fall_time) - t0) if fell else None,
        "completed": (not fell) and n >= n_course,
    }


def full_body_stones_log(
    result: LoopResult,
    source: AlipFootstepSource,
    course: StoneSequence,
    push_windows: Sequence[tuple[float, float, tuple[float, float]]] = (),
    pushes: Sequence[Push] = (),
    fall_reason: str = "",
    stone_tolerance: float = 0.0,
    limits: KinematicLimits | None = None,
) -> AlipLoopLog:
    """A full-body run recorded in the ALIP loop's log (:class:`~lipmpcc.loops.alip.AlipLoopLog`), the one
    record of a stones run: :func:`~lipmpcc.loops.alip.loop_metrics` scores it and the figures draw it.

    Times start at the first lift-off (the end of the weight shift). The steps come from the loop's
    :class:`~lipmpcc.loops.base.RunRecord` (``result.record``): footholds are the measured soles at touch-down;
    ``z_initial`` is the measured initial DCM of each step; ``com``/``com_vel``/``dcm`` are the loop's 400 Hz
    samples (DCM c + ċ/ω); the plan arrays are the source's records (each 25 Hz call).
    """
    lim = limits or getattr(getattr(source.planner, "params", None), "limits", None) or KinematicLimits()
    recs = source.records
    t0 = float(recs[0].t) if recs else 0.0
    log = result.log
    lam = float(source.alip.lam)
    if result.record is None:
        raise InvalidInputError("result.record", None, "the RunRecord of FullBodyLoop.run's LoopResult (its touch-downs)")
    n = min(result.record.n_steps, len(course))
    steps = _step_fields(result.record, n, course, recs, lim, stone_tolerance, t0, lam)
    return AlipLoopLog(
        sequence=course,
        t=np.asarray(log.t, dtype=float) - t0,
        com=np.asarray(log.com, dtype=float)[:, :2],
        com_vel=np.asarray(log.com_vel, dtype=float)[:, :2],
        dcm=np.asarray(log.dcm, dtype=float),
        sample_step=np.searchsorted(np.array([td.t for td in result.touchdowns]), np.asarray(log.t), side="right"),
        **steps,
        **_plan_fields(recs, t0),
        start_stance=np.asarray(recs[0].stance if recs else np.zeros(2), dtype=float),
        start_swing=None,
        **_fall_fields(result, steps["in_stone"], len(course), t0, fall_reason),
        solver_failures=int(source.solver_failures),
        pushes=tuple(pushes),
        push_windows=[(a - t0, b - t0, f) for a, b, f in push_windows],
        dcm_bounds=source.planner.params.dcm_bounds,
        lam=lam,
    )


def stone_metrics(alip_log: AlipLoopLog, source: AlipFootstepSource) -> dict[str, Any]:
    """:func:`~lipmpcc.loops.alip.loop_metrics` of a full-body run; ``solve_ms``, ``plan_ms`` and
    ``fallback_ticks`` count the planner under test only (the approach is ALIP-MPC's for every planner)."""
    m = loop_metrics(alip_log)
    recs = [r for r in source.course_records() if r.result is not None]
    m["solve_ms"] = timing_stats_ms([r.result.solve_time for r in recs])
    m["plan_ms"] = timing_stats_ms([r.result.plan_time for r in recs])
    m["fallback_ticks"] = int(sum(r.result is None or r.result.fallback for r in source.course_records()))
    return m


def stones_reached(log: AlipLoopLog) -> int:
    """The stones the run stepped onto: touch-downs on a stone of the course (on it or not)."""
    seq = log.sequence
    return int(sum(bool(seq.is_stone[int(i)]) for i in log.step_index))
