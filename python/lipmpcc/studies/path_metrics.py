"""Paper A's metrics of a run, once for both robots (:mod:`lipmpcc.studies.path_following`).

A run, on the LIP or on a full body, is measured as a :class:`~lipmpcc.plots.logs.PathFollowingLog` (the LIP: the
state at each support exchange, :func:`lip_path_log`; a full body: the measured COM at the touch-downs and at every
WBC tick, :func:`full_body_path_log`): the contouring, lag and Cartesian errors after the settling time, the push
recovery, the clearance, whether it overtook, and its progress along the path (:func:`progress_trace`,
:func:`assess_run`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..contouring import errors as contouring_errors
from ..loops import lip as lip_loop
from ..metrics import max_abs, rms, timing_stats_ms
from ..obstacles import Obstacle
from ..paths import Path
from ..planners.mpcc import MpccParams, MpccResult
from ..plots.logs import PathFollowingLog
from ..push import Push
from .outcome import PathAssessment, ProgressTrace, assess_progress
from .path_scenarios import FULLBODY_SETTLE_TIME, run_goal

if TYPE_CHECKING:  # pragma: no cover
    from ..loops.fullbody.loop import LoopResult
    from ..planners.sources.mpcc import MpccFootstepSource
    from ..robots import RobotDescription

__all__ = [
    "lip_path_log", "full_body_path_log", "push_recovery_times", "paper_a_fields", "summarize_lip",
    "summarize_full_body", "body_clearance_summary",
    "progress_trace", "assess_run", "OvertakeLandmarks", "overtake_landmarks",
]


def lip_path_log(log: lip_loop.LipLog) -> PathFollowingLog:
    """A LIP run as the figures read it (the step offsets are the planned [uˣ, uʸ] of each solve's u_0)."""
    return PathFollowingLog(
        t=log.t, e_contouring=log.e_contouring, e_lag=log.e_lag, e_cartesian=log.e_cartesian,
        footholds=log.footholds, sides=log.sides,
        step_offsets=np.array([p.u0[:2] for p in log.plans], dtype=float).reshape(-1, 2),
        v_avg_t=log.t[: len(log.v_avg)], v_avg=log.v_avg, v_max=log.v_max,
        tc=log.tc, com=log.com, obstacles=log.obstacles, clearance=log.clearance,
        pushes=tuple(log.pushes), progress=log.theta_final,
    )


def _closest_along(path: Path, points: np.ndarray, theta0: float = 0.0) -> np.ndarray:
    """Closest path parameters of a sequence of points, each searched around the previous one (eq. 19)."""
    out = np.empty(len(points))
    prev = theta0
    for i, p in enumerate(points):
        prev = path.closest_point(p, theta_prev=prev)
        out[i] = prev
    return out


def _closest_dense(path: Path, points: np.ndarray, stride: int = 8) -> np.ndarray:
    """Closest path parameters of a densely sampled trajectory: the local search of
    :func:`_closest_along` on every ``stride``-th point, linear interpolation in between, then three
    Newton steps on (y_d(θ) − p)·t(θ) = 0 for every point (arc length: d/dθ = 1 + κ (y_d − p)·n)."""
    n = len(points)
    if n == 0:
        return np.zeros(0)
    idx = np.unique(np.r_[np.arange(0, n, max(1, stride)), n - 1])
    theta = np.interp(np.arange(n), idx, _closest_along(path, points[idx]))
    for _ in range(3):
        r = path.position(theta) - points
        t = path.tangent(theta)
        nrm = np.column_stack([-t[:, 1], t[:, 0]])
        den = 1.0 + path.curvature(theta) * np.sum(r * nrm, axis=1)
        step = np.sum(r * t, axis=1) / np.where(np.abs(den) > 0.1, den, 1.0)
        theta = np.clip(theta - step, 0.0, path.length)
    return theta


def _committed_theta(source: MpccFootstepSource, n: int) -> np.ndarray:
    """The path parameter the MPCC committed to for each of ``n`` exchanges: a plan with step_index j is
    made in the swing that ends at touch-down j; its ϑ_0 belongs to that exchange and its ϑ_1 to the
    next. So ϑ_1 of the last plan with step_index k − 1 (k = 0: ϑ_0 of the last plan with step_index 0,
    as the LIP loop uses ϑ_init for the initial state); NaN without such a plan."""
    last_plan: dict[int, MpccResult] = {}
    for rec in source.records:
        if rec.result is not None:
            last_plan[rec.step_index] = rec.result
    th_ref = np.full(n, np.nan)
    for k in range(n):
        r = last_plan.get(0 if k == 0 else k - 1)
        if r is not None:
            th_ref[k] = r.theta[0] if k == 0 else r.theta[1]
    return th_ref


def _touchdown_errors(pos_td: np.ndarray, path: Path, th_ref: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Contouring, lag and Cartesian errors [m] of the COM positions (n, 2) at the touch-downs."""
    n = len(pos_td)
    th_td = _closest_along(path, pos_td) if n else np.zeros(0)
    e_td = contouring_errors(pos_td, path.position(th_td), path.slope(th_td)) if n else np.zeros((0, 2))
    ok = np.isfinite(th_ref)
    e_lag = np.full(n, np.nan)
    e_cart = np.full(n, np.nan)
    if np.any(ok):
        ref = path.position(th_ref[ok])
        e_lag[ok] = contouring_errors(pos_td[ok], ref, path.slope(th_ref[ok]))[:, 1]
        e_cart[ok] = np.linalg.norm(pos_td[ok] - ref, axis=1)
    return e_td[:, 0], e_lag, e_cart


def _clearance(result: LoopResult, obstacles: Sequence[Obstacle], prm: MpccParams) -> tuple[np.ndarray, np.ndarray]:
    """Obstacle centres (n_obs, m, 2) and the footprint's clearance (m,) [m] at every tick: the COM disk
    and the measured stance feet's disks (both feet in double support)."""
    log = result.log
    tc = np.asarray(log.t, dtype=float)
    obs_c = np.zeros((len(obstacles), len(tc), 2))
    clearance = np.full(len(tc), np.inf)
    stance = np.asarray(log.stance)
    for j, ob in enumerate(obstacles):
        obs_c[j] = np.atleast_2d(ob.center(tc))
        body = ob.clearance(log.com[:, :2], tc, prm.robot_radius)
        left = np.where(stance != 1, ob.clearance(log.left_foot[:, :2], tc, prm.foot_radius), np.inf)
        right = np.where(stance != 0, ob.clearance(log.right_foot[:, :2], tc, prm.foot_radius), np.inf)
        clearance = np.minimum(clearance, np.minimum(body, np.minimum(left, right)))
    return obs_c, clearance


def full_body_path_log(result: LoopResult, source: MpccFootstepSource, path: Path,
                       obstacles: Sequence[Obstacle] = (), pushes: Sequence[Push] = ()) -> PathFollowingLog:
    """Paper A's quantities of a full-body run, measured: the COM at every WBC tick and at each touch-down
    (support exchange), the landed feet, the MPCC's solves (see the module doc for the errors)."""
    log = result.log
    if result.record is None:
        raise InvalidInputError("result.record", None, "the RunRecord of FullBodyLoop.run's LoopResult (its touch-downs)")
    rec = result.record  # the touch-downs (loops.base.RunRecord)
    n = rec.n_steps
    tc = np.asarray(log.t, dtype=float)
    com = np.column_stack([log.com[:, 0], log.com_vel[:, 0], log.com[:, 1], log.com_vel[:, 1]]) if len(tc) else np.zeros((0, 4))
    theta_c = _closest_dense(path, np.asarray(log.com[:, :2], dtype=float))
    e_c = contouring_errors(log.com[:, :2], path.position(theta_c), path.slope(theta_c))[:, 0] if len(tc) else np.zeros(0)
    t_td = rec.touchdown_times.copy()
    feet = np.column_stack([rec.footholds, rec.yaws]) if n else np.zeros((0, 3))
    idx = np.clip(np.searchsorted(tc, t_td), 0, max(len(tc) - 1, 0))
    pos_td = (com[idx] if n else np.zeros((0, 4)))[:, [0, 2]]
    th_ref = _committed_theta(source, n)
    e_td, e_lag, e_cart = _touchdown_errors(pos_td, path, th_ref)
    obs_c, clearance = _clearance(result, obstacles, source.params)
    recs = [r for r in source.records if r.result is not None]
    return PathFollowingLog(
        t=t_td, e_contouring=e_td, e_lag=e_lag, e_cartesian=e_cart,
        footholds=feet, sides=rec.sides.copy(),
        step_offsets=feet[:, :2] - pos_td,
        v_avg_t=np.array([r.t for r in recs], dtype=float), v_avg=np.array([r.result.v_avg for r in recs], dtype=float),
        v_max=source.params.v_max, tc=tc, com=com, obstacles=obs_c, clearance=clearance, pushes=tuple(pushes),
        progress=float(theta_c[-1]) if len(theta_c) else 0.0, theta_c=theta_c, e_contouring_c=e_c,
        path_end_t=_path_end_time(t_td, th_ref, path.length),
    )


def _path_end_time(t_td: np.ndarray, th_ref: np.ndarray, length: float) -> float | None:
    """The time [s] of the first support exchange whose committed path parameter (:func:`_committed_theta`)
    is the path's end ``length`` [m]: the exchange at which the LIP loop stops (``"end of path"``); None when
    no exchange reached it."""
    k = np.flatnonzero(np.isfinite(th_ref) & (th_ref >= length - 1e-6))
    return float(t_td[k[0]]) if k.size else None


def push_recovery_times(log: PathFollowingLog, bound: float = 0.05, exact_end: bool = False) -> list[float]:
    """For each push, the time from its end to the first support exchange at which |contouring error| < ``bound``
    [m] (0 when it is already below; NaN when it never comes back before the end of the run) [s]. The end is the
    one the loop applied: ``Push.t_end`` on the LIP (``exact_end``), ``t_start + duration`` in MuJoCo."""
    out = []
    e = np.abs(log.e_contouring)
    for pu in log.pushes:
        t_end = pu.t_end if exact_end else pu.t_start + pu.duration
        if not np.any(log.t >= t_end):
            continue
        idx = np.flatnonzero((log.t >= t_end) & (e < bound))
        out.append(float(log.t[idx[0]] - t_end) if idx.size else float("nan"))
    return out


def _overtook(progress: float, t_end: float, obstacles: Sequence[Obstacle]) -> bool:
    """At ``t_end`` [s], the robot's footprint, ``progress`` [m] along the path, is entirely ahead of every
    obstacle along the path."""
    if not len(obstacles):
        return False
    return all(ob.path is not None and progress > ob.s0 + ob.speed * t_end + max(ob.axes) + 0.2 for ob in obstacles)


def paper_a_fields(log: PathFollowingLog, obstacles: Sequence[Obstacle], settle_time: float, t0: float = 0.0,
                   t_end: float | None = None, exact_end: bool = False) -> dict[str, Any]:
    """Paper A's summary fields of a run on either robot, from its :class:`~lipmpcc.plots.logs.PathFollowingLog`:
    the contouring (max, RMS), lag (RMS) and Cartesian (max) errors at the support exchanges ``settle_time`` [s]
    after ``t0`` [s], the least clearance, whether it overtook every obstacle by ``t_end`` [s] (None: the log's
    last time ``tc``), the progress along the path [m] and the push recovery times [s]
    (:func:`push_recovery_times`, ``exact_end``). A full body that reached the path's end (``log.path_end_t``)
    walks on in place there until its duration ends; its errors are judged up to that exchange, where the LIP
    loop stops (:func:`summarize_full_body` reports the rest apart)."""
    after = _following(log.t, log, t0, settle_time)
    ec, el, eca = log.e_contouring[after], log.e_lag[after], log.e_cartesian[after]
    if t_end is None:
        t_end = float(log.tc[-1]) if len(log.tc) else 0.0
    return {
        "contouring_error_max_m": max_abs(ec),
        "contouring_error_rms_m": rms(ec),
        "lag_error_rms_m": rms(el[np.isfinite(el)]),
        "cartesian_error_max_m": max_abs(eca[np.isfinite(eca)]),
        "min_clearance_m": float(np.min(log.clearance)) if len(obstacles) and len(log.clearance) else None,
        "overtook": bool(_overtook(float(log.progress), t_end, obstacles)),
        "progress_m": float(log.progress),
        "push_recovery_s": push_recovery_times(log, 0.05, exact_end),
        "error_settle_time_s": settle_time,
    }


def _following(t: np.ndarray, log: PathFollowingLog, t0: float, settle_time: float) -> np.ndarray:
    """The samples at times ``t`` [s] at which the run is judged following its path: ``settle_time`` [s] after
    ``t0`` [s] and, when it reached the path's end (``log.path_end_t``), not after that."""
    ok = t - t0 >= settle_time
    return ok if log.path_end_t is None else ok & (t <= log.path_end_t)


def summarize_lip(log: lip_loop.LipLog, obstacles: Sequence[Obstacle] = (), settle_time: float = 0.0) -> dict[str, Any]:
    """The summary fields of a LIP run: the loop's own (:func:`lipmpcc.loops.lip.summarize`: steps, fall, solver
    and step-duration statistics) and paper A's (:func:`paper_a_fields` of :func:`lip_path_log`, as on a full
    body; the LIP's errors are at its support exchanges, the pushes end at ``Push.t_end``)."""
    s = lip_loop.summarize(log, (), settle_time)
    t_end = float(log.t[-1]) if len(log.t) else 0.0
    s.update(paper_a_fields(lip_path_log(log), obstacles, settle_time, 0.0, t_end, exact_end=True))
    return s


def summarize_full_body(log: PathFollowingLog, result: LoopResult, source: MpccFootstepSource,
                        obstacles: Sequence[Obstacle] = (), settle_time: float = FULLBODY_SETTLE_TIME) -> dict[str, Any]:
    """The LIP runs' summary fields (:func:`summarize_lip`: paper A's by :func:`paper_a_fields`) of a full-body
    run, plus ``contouring_error_continuous_max_m`` and the loop's full-body fields."""
    t0 = float(log.tc[0]) if len(log.tc) else 0.0
    s: dict[str, Any] = {
        "steps": int(log.steps),
        "fell": bool(result.fell),
        "fall_step": int(log.steps) if result.fell else None,
        "solver_failures": int(source.solver_failures),
        "solve_ms": timing_stats_ms(source.solve_times),
    }
    s.update(paper_a_fields(log, obstacles, settle_time, t0))
    s.update({
        "contouring_error_continuous_max_m": max_abs(log.e_contouring_c[_following(log.tc, log, t0, settle_time)]),
        "v_avg_mean": float(np.mean(log.v_avg)) if len(log.v_avg) else float("nan"),
        "v_max": log.v_max,
        "duration_s": float(log.tc[-1] - t0) if len(log.tc) else 0.0,
        "step_duration_s": {
            "model": float(source.params.model.T),
            "mean_measured": float(np.mean(np.diff(log.t))) if log.steps > 1 else float("nan"),
        },
        "timing_offset_s": float(source.timing_offset),
    })
    if log.path_end_t is not None:  # the end reached: how it stood there, apart (only then: no new field otherwise)
        s["path_end_time_s"] = float(log.path_end_t - t0)
        s["contouring_error_after_end_max_m"] = max_abs(log.e_contouring_c[log.tc > log.path_end_t])
    full = result.summary()
    for k in ("fell", "steps"):
        full.pop(k, None)
    s.update(full)
    return s


def body_clearance_summary(robot: RobotDescription, obstacles: Sequence[Obstacle], result: LoopResult) -> dict[str, Any]:
    """The whole robot's least clearance to the obstacles (:class:`~lipmpcc.studies.clearance.BodyClearance`,
    on the configurations the run recorded at the video's rate): ``min_body_clearance_m`` (None without
    obstacles), when (``min_body_clearance_t_s``), which geom (``min_body_clearance_geom``), how many
    configurations (``body_clearance_samples``) and its cost (``body_clearance_ms``)."""
    if not obstacles or result.frames is None or not len(result.frames):
        return {"min_body_clearance_m": None}
    from .clearance import BodyClearance

    res = BodyClearance(robot, obstacles).measure(result.frames, result.frame_times)
    return {"min_body_clearance_m": res.min_clearance, "min_body_clearance_t_s": res.time,
            "min_body_clearance_geom": res.geom, "body_clearance_samples": res.samples,
            "body_clearance_ms": 1e3 * res.cost}


def progress_trace(run: Any, goal: str = "end") -> ProgressTrace:
    """The progress of a path-following run (:class:`~lipmpcc.studies.outcome.ProgressTrace`): on the LIP the
    closest path parameter of the state at each support exchange, on a full body of the measured COM at every
    WBC tick; each obstacle's clearance to the robot's body disk (the MPCC's ``robot_radius``) at those times
    and, for one moving along the path, its path parameter."""
    if getattr(run, "lip_log", None) is not None:  # a LIP run (path_following.LipPathRun)
        lg = run.lip_log
        t, theta, pos = lg.t, lg.theta_closest, lg.states[:, [0, 2]]
        by_loop = lg.stopped_reason == "end of path"
    else:
        t = run.log.tc
        theta = run.log.theta_c if run.log.theta_c is not None else np.zeros(len(t))
        pos, by_loop = run.log.com[:, [0, 2]], False
    n = min(len(t), len(theta), len(pos))
    t, theta, pos = np.asarray(t[:n], dtype=float), np.asarray(theta[:n], dtype=float), np.asarray(pos[:n], dtype=float)
    clear = np.zeros((len(run.obstacles), n))
    along = np.full((len(run.obstacles), n), np.nan)
    for j, ob in enumerate(run.obstacles if n else ()):
        clear[j] = ob.clearance(pos, t, run.params.robot_radius)
        if ob.path is not None:
            along[j] = ob.s0 + ob.speed * t
    speed = np.array([ob.speed if ob.path is not None else np.nan for ob in run.obstacles], dtype=float)
    planned = _planned_clearance(run, t)
    return ProgressTrace(t, theta, pos, float(run.path.length), goal, clear, along, speed, by_loop, planned,
                         _held(run, t))


def _run_plans(run: Any) -> tuple[np.ndarray, list[MpccResult]]:
    """The times [s] the run's MPCC plans were made and the plans (the LIP: one per step, the last of each
    step when re-planned within it; a full body: every solve of the source)."""
    if getattr(run, "lip_log", None) is not None:  # a LIP run (path_following.LipPathRun)
        plans = [pl for pl in run.lip_log.plans if isinstance(pl, MpccResult)]
        return np.asarray(run.lip_log.t[: len(plans)], dtype=float), plans
    recs = [r for r in getattr(run, "source").records if r.result is not None]
    return np.array([r.t for r in recs], dtype=float), [r.result for r in recs]


def _planned_clearance(run: Any, t: np.ndarray) -> np.ndarray | None:
    """(n_obs, n): at each time of ``t``, each obstacle's least clearance [m] to the COM the latest plan
    predicted over its horizon (each predicted exchange at the plan's time plus the planned durations, or
    multiples of T), the robot's body disk; NaN before the first plan; None without obstacles."""
    if not run.obstacles or not len(t):
        return None
    times, plans = _run_plans(run)
    if not plans:
        return None
    T = float(run.params.model.T)
    per_plan = np.full((len(run.obstacles), len(plans)), np.nan)
    for k, (t0, pl) in enumerate(zip(times, plans)):
        pts = np.asarray(pl.states, dtype=float)[:, [0, 2]]
        d = np.asarray(getattr(pl, "durations", None) if getattr(pl, "durations", None) is not None else [], dtype=float)
        steps = d if len(d) == len(pts) - 1 else np.full(len(pts) - 1, T)
        tk = t0 + np.r_[0.0, np.cumsum(steps)]
        for j, ob in enumerate(run.obstacles):
            per_plan[j, k] = float(np.min(ob.clearance(pts, tk, run.params.robot_radius)))
    idx = np.searchsorted(times, t, side="right") - 1
    out = np.where(idx >= 0, per_plan[:, np.clip(idx, 0, None)], np.nan)
    return out


def _held(run: Any, t: np.ndarray) -> np.ndarray | None:
    """(n_obs, n): at each time of ``t``, 1 where the latest plan held the robot in place for that obstacle
    (``MpccResult.held_by``: its fallback would have walked into it), else 0; None without obstacles."""
    if not run.obstacles or not len(t):
        return None
    times, plans = _run_plans(run)
    if not plans:
        return None
    per_plan = np.zeros((len(run.obstacles), len(plans)))
    for k, pl in enumerate(plans):
        for j in getattr(pl, "held_by", ()):
            if 0 <= j < len(run.obstacles):
                per_plan[j, k] = 1.0
    idx = np.searchsorted(times, t, side="right") - 1
    return np.where(idx >= 0, per_plan[:, np.clip(idx, 0, None)], 0.0)


def assess_run(run: Any, scenario: str) -> PathAssessment:
    """How ``run`` of ``scenario`` ended along its path (:func:`~lipmpcc.studies.outcome.assess_progress` of
    :func:`progress_trace`, the goal :func:`run_goal`), its ``progress_m`` the summary's."""
    return assess_progress(progress_trace(run, run_goal(scenario)), run.summary.get("progress_m"))


@dataclass
class OvertakeLandmarks:
    """The moments of a full-body overtaking run (notebooks 09 and 09b), from its continuous log.

    Attributes:
        ahead: (m,) the robot's lead on the obstacle along the path at each WBC tick [m] (> 0: ahead).
        i_aside, t_aside: tick and time [s] of the widest step aside to the left (least ē_c, < 0).
        passed: whether the robot drew level with the obstacle; t_pass: when [s] (nan if never).
        i_back, e_back: after the widest step aside, the tick nearest the path's right side and its ē_c [m]
            (> 0: beyond the path, on its right).
        t_cross: when [s] the COM first crossed back over the path after the step aside (None: never).
    """

    ahead: np.ndarray
    i_aside: int
    t_aside: float
    passed: bool
    t_pass: float
    i_back: int
    e_back: float
    t_cross: float | None


def overtake_landmarks(log: PathFollowingLog, obstacle: Obstacle) -> OvertakeLandmarks:
    """:class:`OvertakeLandmarks` of a full-body run's ``log`` (``tc``, ``theta_c``, ``e_contouring_c``) against
    the ``obstacle`` moving along the path (``s0`` [m], ``speed`` [m/s])."""
    if log.e_contouring_c is None or log.theta_c is None or len(log.tc) == 0:
        raise InvalidInputError("log", "a LIP or empty log", "a full-body run's log (continuous e_contouring_c)")
    tc, e_c = np.asarray(log.tc, dtype=float), np.asarray(log.e_contouring_c, dtype=float)
    ahead = np.asarray(log.theta_c, dtype=float) - (obstacle.s0 + obstacle.speed * tc)
    i_aside = int(np.argmin(e_c))
    passed = bool(np.any(ahead > 0))
    after = np.flatnonzero(tc > tc[i_aside])
    if len(after) == 0:  # the run ended at its widest step aside
        after = np.array([len(tc) - 1])
    i_back = int(after[np.argmax(e_c[after])])
    crossed = after[e_c[after] > 0]
    return OvertakeLandmarks(ahead, i_aside, float(tc[i_aside]), passed,
                             float(tc[np.argmax(ahead > 0)]) if passed else float("nan"), i_back, float(e_c[i_back]),
                             float(tc[crossed[0]]) if len(crossed) else None)
