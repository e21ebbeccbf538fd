"""Paper A's studies on the full-body robot: ``circle``, ``circle-push``, ``overtake`` with ``--robot digit_like``
(or ``--robot PATH.xml``).

The MPCC (:mod:`lipmpcc.planners.mpcc`) drives the full-body loop (:mod:`lipmpcc.loops.fullbody.loop`:
MuJoCo at 2 kHz, the C++ whole-body QP at 400 Hz) through :class:`~lipmpcc.planners.mpcc_source.MpccFootstepSource`,
re-planning at 15 Hz within each swing (paper A Fig. 4). :mod:`lipmpcc.scenarios.path_following` dispatches
here when ``--robot`` is not ``lip``.

**Model choices (documented in the summary's ``params``).**

- The MPCC's LIP: T = the robot description's ``step_duration`` (0.4 s for digit_like, the LIP runs'
  step duration; 0.35 s for Digit v3, which at 0.4 s walks beside the 0.6 m/s obstacle without passing
  it) and H = the loop's constant COM height, the robot's standing COM height (0.953 m for digit_like),
  so that the MPCC, the loop's LIP COM reference and the exchange-state prediction share one ω = √(g/H). The source asks the loop for T minus the
  learned early-touch-down offset, so the real steps last ≈ T.
- Reachability rectangle: forward (−0.35, 0.35) m and heading (−0.3, 0.3) rad as on the LIP, but the
  lateral offset of the new foot from the COM at the exchange is (0.10, 0.40) m instead of (0.05, 0.35):
  with the LIP's 0.05 m the MPCC (which pays ‖u‖²_R) puts Digit's feet 0.09–0.12 m apart, closer than
  the legs allow (the capture-point walker keeps ≥ 0.14 m); with 0.10 m they stay at least 0.14 m apart
  (about 0.2 m when walking straight). The lower bound is the robot description's ``min_lateral_step``
  (0.10 m for digit_like, 0.16 m for Digit v3, whose tarsi touch below that).
- Obstacle margin 0.10 m (0.05 m on the LIP): the barriers hold at the step instants only, and the full
  body sways between them. With 0.05 m the inner foot's barrier (obstacle + 0.1 m foot disk) and the COM's
  (obstacle + 0.2 m body disk) are only just compatible at the smallest lateral foot offset, and the MPCC
  braked beside the 0.6 m/s obstacle instead of passing it (clearance −1 mm).
- Weights, ρ, v_max = 0.3 m/step, N = 5: paper A's presets (:class:`~lipmpcc.planners.mpcc.MpccParams`).
- The Cartesian MPC also weighs the planned heading against the path's tangent
  (``heading_weight`` = 20, :data:`FULLBODY_CARTESIAN_HEADING_WEIGHT`; paper A weighs only the heading
  change, 5). The rectangle's lateral bound holds in the new heading frame, so turning the next foot
  by its full 0.3 rad lets a backward step (starting, or trailing at 0.1 m/s) meet the bound with less
  sideways offset: cheaper under ‖u‖²_R. Paper A's cost leaves that turn free, and with Digit v3's
  0.16 m bound the robot turned step after step (−1.9 rad in 8 s) and fell; digit_like's Cartesian
  error goes from 0.013 to 0.024 m. The MPCC keeps paper A's cost: going around the obstacle needs
  those turns (with the weight, digit_like fell beside it), and on the circle the weight halves the
  progress.

**Scenarios.** The path starts at the robot's standing COM, heading along its torso (+x for digit_like):

- ``circle``: counter-clockwise circle of radius 2 m (1.25 turns of path); default 45 s (a full lap at
  ≈ 0.3 m/s), 10 s in fast mode.
- ``circle-push``: the same under paper A's pushes: U[−50, 50] N in a uniform horizontal direction on the
  torso for 0.1 s, at random instants at most 2 s apart (:func:`lipmpcc.loops.lip.random_pushes`,
  seeded by ``--seed``).
- ``overtake``: a 40 m straight line; a cylinder of radius 0.25 m starts ``OBSTACLE_START`` = 1.0 m ahead
  of the robot and moves along it at ``--obstacle-speed`` (paper A: 0.6 m/s for the MPCC, 0.1 m/s for the
  Cartesian MPC). Default 30 s (MPCC) / 25 s (Cartesian).

``--steps`` stops after that many touch-downs, ``--duration`` after that many simulated seconds (whichever
comes first when both are given, as for ``walk``).

**Metrics** (consistent with :mod:`lipmpcc.loops.lip`; errors of the *measured* COM):

- at each touch-down (support exchange) k: the contouring error is the signed distance to the path at
  the closest point (eq. 19, local search); the lag error is ē_l with respect to the path parameter the
  MPCC committed to for this exchange — ϑ_1 of the last plan made for the previous exchange; the
  Cartesian error is ‖c_k − y_d(that ϑ)‖;
- ``contouring_error_continuous_max_m``: the contouring error of the COM at every WBC tick (400 Hz)
  after the settle time (it includes the lateral sway within each step);
- ``min_clearance_m``: robot footprint (COM disk 0.2 m + disks of 0.1 m around the measured stance
  feet, both feet in double support) to the obstacle surface, at every WBC tick of the whole run;
- errors are judged after ``SETTLE_TIME`` = 3 s (start from rest: COM shift, first steps).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any, Callable, Sequence

import numpy as np

from .. import config
from ..contouring import errors as contouring_errors
from ..exceptions import InvalidInputError
from ..metrics import max_abs, rms, timing_stats_ms
from ..models.lip3d import Lip3dModel, ReachabilityRectangle
from ..obstacles import Obstacle, obstacles_from_json
from ..paths import ArcPath, LinePath, Path, load_path_csv
from ..planners.mpcc import MpccParams
from . import RunOptions, RunResult

STEP_DURATION = 0.4  # [s] the MPCC's T on the full body
FULLBODY_RECTANGLE = ReachabilityRectangle(forward=(-0.35, 0.35), lateral=(0.10, 0.40), heading=(-0.3, 0.3))
FULLBODY_OBSTACLE_MARGIN = 0.10  # [m] barrier margin on the full body (0.05 on the LIP); see the module doc
FULLBODY_CARTESIAN_HEADING_WEIGHT = 20.0  # the Cartesian MPC's heading-error weight on the full body; see the module doc
CIRCLE_RADIUS = 2.0  # [m]
CIRCLE_TURNS = 1.25  # path length in turns (the run stops before its end)
LINE_LENGTH = 40.0  # [m]
OBSTACLE_RADIUS = 0.25  # [m] paper A
OBSTACLE_START = 1.0  # [m] ahead of the robot along the path
PAPER_SPEED = {"mpcc": 0.6, "cartesian": 0.1}  # [m/s] paper A §IV-B
SETTLE_TIME = 3.0  # [s]
DEFAULT_DURATION = {  # [s] (full, fast)
    "circle": (45.0, 10.0),
    "circle-push": (45.0, 10.0),
    "overtake-mpcc": (30.0, 25.0),
    "overtake-cartesian": (25.0, 15.0),
}


# --------------------------------------------------------------------------------------------
# Parameters and set-up
# --------------------------------------------------------------------------------------------
def fullbody_params(
    scenario: str,
    planner: str,
    com_height: float,
    min_lateral_step: float | None = None,
    step_duration: float | None = None,
) -> MpccParams:
    """Paper A's MPCC preset of ``scenario`` / ``planner`` for the full body (see the module doc).

    Args:
        scenario: ``"circle"``, ``"circle-push"`` or ``"overtake"``.
        planner: ``"mpcc"`` or ``"cartesian"``.
        com_height: the loop's constant COM height [m] (the LIP's H).
        min_lateral_step: lower bound of the lateral reachability [m] (the robot description's
            ``min_lateral_step``); None: that of :data:`FULLBODY_RECTANGLE` (0.10 m).
        step_duration: the LIP's step duration T [s] (the robot description's ``step_duration``);
            None: :data:`STEP_DURATION` (0.4 s).
    """
    if not (math.isfinite(com_height) and com_height > 0.0):
        raise InvalidInputError("com_height", com_height, "a positive COM height [m]")
    T = STEP_DURATION if step_duration is None else step_duration
    if isinstance(T, bool) or not isinstance(T, (int, float)) or not (math.isfinite(T) and 0.2 <= T <= 1.0):
        raise InvalidInputError("step_duration", step_duration, "a step duration in [0.2, 1.0] [s]")
    rect = FULLBODY_RECTANGLE
    if min_lateral_step is not None:
        if not (math.isfinite(min_lateral_step) and 0.0 <= min_lateral_step < rect.lateral[1]):
            raise InvalidInputError("min_lateral_step", min_lateral_step, f"a lateral offset in [0, {rect.lateral[1]}) [m]")
        rect = ReachabilityRectangle(forward=rect.forward, lateral=(float(min_lateral_step), rect.lateral[1]), heading=rect.heading)
    kw = {"model": Lip3dModel(T=float(T), H=float(com_height)), "rectangle": rect,
          "obstacle_margin": FULLBODY_OBSTACLE_MARGIN}
    if planner == "cartesian":
        return MpccParams.overtake_cartesian(heading_weight=FULLBODY_CARTESIAN_HEADING_WEIGHT, **kw)
    if planner != "mpcc":
        raise InvalidInputError("planner", planner, "'mpcc' or 'cartesian'")
    return MpccParams.circle(**kw) if scenario.startswith("circle") else MpccParams.overtake_mpcc(**kw)


def standing_state(loop: Any) -> tuple[np.ndarray, float]:
    """The robot's standing COM (3,) [m] and torso yaw [rad] (resets the loop's simulator)."""
    sim = loop.sim
    sim.reset(loop.robot.standing_reset)  # keyframe or standing qpos (Digit v3 has no keyframe)
    com = np.asarray(sim.com(), dtype=float)
    R = np.asarray(sim.torso_pose().rotation, dtype=float)
    return com, math.atan2(R[1, 0], R[0, 0])


def circle_path(start: Sequence[float], heading: float, radius: float = CIRCLE_RADIUS) -> Path:
    """Counter-clockwise circle of ``radius`` [m] through ``start`` with tangent ``heading`` [rad]."""
    return ArcPath.circle(radius, start=(float(start[0]), float(start[1])), heading=float(heading), turns=CIRCLE_TURNS)


def line_path(start: Sequence[float], heading: float, length: float = LINE_LENGTH) -> Path:
    """Straight line of ``length`` [m] from ``start`` along ``heading`` [rad]."""
    s = np.asarray(start[:2], dtype=float)
    return LinePath(tuple(s), tuple(s + length * np.array([math.cos(heading), math.sin(heading)])))


def loop_pushes(pushes: Sequence[Any]) -> list[Any]:
    """Planar pushes (:class:`lipmpcc.loops.lip.Push`) as torso pushes of the full-body loop."""
    from ..loops.fullbody.loop import Push

    return [Push(t_start=p.t_start, force=(float(p.force[0]), float(p.force[1]), 0.0), duration=p.duration) for p in pushes]


# --------------------------------------------------------------------------------------------
# Log in the reduced runs' terms, and metrics
# --------------------------------------------------------------------------------------------
@dataclass
class FullBodyPathLog:
    """A full-body path-following run in the terms of :class:`~lipmpcc.loops.lip.LipLog`, so that
    the paper A figures (:mod:`lipmpcc.plots.path_following`) draw it.

    Per touch-down k (support exchange; measured):
        t: (n,) times [s]; footholds: (n, 3) landed foot [x, y, yaw]; sides: (n,) +1 left / −1 right;
        com_td: (n, 4) COM [x, ẋ, y, ẏ]; step_offsets: (n, 2) foot − COM at touch-down [m] (paper A's
        u = [uˣ, uʸ] as realised); e_contouring, e_lag, e_cartesian: (n,) [m] (NaN where undefined).
    Per MPCC solve (15 Hz):
        v_avg_t: (p,) times [s]; v_avg: (p,) (1/N) Σ v [m]; v_max [m]; solve_time: (p,) [s]; status.
    Continuous (every WBC tick):
        tc: (m,) [s]; com: (m, 4) [x, ẋ, y, ẏ]; theta_c: (m,) closest path parameter [m];
        e_contouring_c: (m,) [m]; obstacles: (n_obs, m, 2) centres [m]; clearance: (m,) [m].
    """

    t: np.ndarray
    footholds: np.ndarray
    sides: np.ndarray
    com_td: np.ndarray
    step_offsets: np.ndarray
    e_contouring: np.ndarray
    e_lag: np.ndarray
    e_cartesian: np.ndarray
    v_avg_t: np.ndarray
    v_avg: np.ndarray
    v_max: float
    solve_time: np.ndarray
    status: list[str]
    tc: np.ndarray
    com: np.ndarray
    theta_c: np.ndarray
    e_contouring_c: np.ndarray
    obstacles: np.ndarray
    clearance: np.ndarray
    pushes: list[Any] = field(default_factory=list)
    path_length: float = 0.0
    theta_final: float = 0.0

    @property
    def steps(self) -> int:
        return len(self.t)


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


def build_log(result: Any, source: Any, path: Path, obstacles: Sequence[Obstacle] = (), pushes: Sequence[Any] = ()) -> FullBodyPathLog:
    """Paper A's quantities from a full-body run.

    Args:
        result: the :class:`~lipmpcc.loops.fullbody.loop.LoopResult`.
        source: the :class:`~lipmpcc.planners.mpcc_source.MpccFootstepSource` that drove it.
        path: the reference path.
        obstacles: the run's obstacles.
        pushes: the run's pushes (planar, :class:`lipmpcc.loops.lip.Push`), for the figures.
    """
    log = result.log
    prm = source.params
    tds = result.touchdowns
    n = len(tds)
    # ---- continuous COM ----
    tc = np.asarray(log.t, dtype=float)
    com = np.column_stack([log.com[:, 0], log.com_vel[:, 0], log.com[:, 1], log.com_vel[:, 1]]) if len(tc) else np.zeros((0, 4))
    theta_c = _closest_dense(path, np.asarray(log.com[:, :2], dtype=float))
    e_c = (
        contouring_errors(log.com[:, :2], path.position(theta_c), path.slope(theta_c))[:, 0] if len(tc) else np.zeros(0)
    )
    # ---- per touch-down ----
    t_td = np.array([td.t for td in tds], dtype=float)
    feet = np.array([[td.pos[0], td.pos[1], td.yaw] for td in tds], dtype=float).reshape(n, 3)
    sides = np.array([1 if td.side == "left" else -1 for td in tds], dtype=int)
    idx = np.clip(np.searchsorted(tc, t_td), 0, max(len(tc) - 1, 0))
    com_td = com[idx] if n else np.zeros((0, 4))
    pos_td = com_td[:, [0, 2]]
    offsets = feet[:, :2] - pos_td
    th_td = _closest_along(path, pos_td) if n else np.zeros(0)
    e_td = contouring_errors(pos_td, path.position(th_td), path.slope(th_td)) if n else np.zeros((0, 2))
    # the path parameter committed to for exchange k (touchdowns[k]): a plan with step_index j is made in
    # the swing that ends at touchdowns[j]; its ϑ_0 belongs to that exchange and its ϑ_1 to the next one.
    # So: ϑ_1 of the last plan with step_index k − 1 (k = 0: ϑ_0 of the last plan with step_index 0, as
    # lip_loop uses ϑ_init for the initial state)
    last_plan: dict[int, Any] = {}
    for rec in source.records:
        if rec.result is not None:
            last_plan[rec.step_index] = rec.result
    th_ref = np.full(n, np.nan)
    for k in range(n):
        if k == 0:
            r = last_plan.get(0)
            th_ref[k] = r.theta[0] if r is not None else np.nan
        else:
            r = last_plan.get(k - 1)
            th_ref[k] = r.theta[1] if r is not None else np.nan
    ok = np.isfinite(th_ref)
    e_lag = np.full(n, np.nan)
    e_cart = np.full(n, np.nan)
    if np.any(ok):
        ref = path.position(th_ref[ok])
        e_lag[ok] = contouring_errors(pos_td[ok], ref, path.slope(th_ref[ok]))[:, 1]
        e_cart[ok] = np.linalg.norm(pos_td[ok] - ref, axis=1)
    # ---- obstacles and clearance (COM disk + stance-feet disks, measured) ----
    n_obs = len(obstacles)
    obs_c = np.zeros((n_obs, len(tc), 2))
    clearance = np.full(len(tc), np.inf)
    stance = np.asarray(log.stance)
    for j, ob in enumerate(obstacles):
        obs_c[j] = np.atleast_2d(ob.center(tc))
        body = ob.clearance(log.com[:, :2], tc, prm.robot_radius)
        left = np.where(stance != 1, ob.clearance(log.left_foot[:, :2], tc, prm.foot_radius), np.inf)
        right = np.where(stance != 0, ob.clearance(log.right_foot[:, :2], tc, prm.foot_radius), np.inf)
        clearance = np.minimum(clearance, np.minimum(body, np.minimum(left, right)))
    recs = [r for r in source.records if r.result is not None]
    return FullBodyPathLog(
        t=t_td,
        footholds=feet,
        sides=sides,
        com_td=com_td,
        step_offsets=offsets,
        e_contouring=e_td[:, 0],
        e_lag=e_lag,
        e_cartesian=e_cart,
        v_avg_t=np.array([r.t for r in recs], dtype=float),
        v_avg=np.array([r.result.v_avg for r in recs], dtype=float),
        v_max=prm.v_max,
        solve_time=np.array([r.result.solve_time for r in recs], dtype=float),
        status=[r.status for r in source.records],
        tc=tc,
        com=com,
        theta_c=theta_c,
        e_contouring_c=e_c,
        obstacles=obs_c,
        clearance=clearance,
        pushes=list(pushes),
        path_length=path.length,
        theta_final=float(theta_c[-1]) if len(theta_c) else 0.0,
    )


def summarize(log: FullBodyPathLog, result: Any, source: Any, obstacles: Sequence[Obstacle] = (), settle_time: float = SETTLE_TIME) -> dict[str, Any]:
    """The reduced runs' summary fields (:func:`lipmpcc.loops.lip.summarize`) for a full-body run, plus
    ``contouring_error_continuous_max_m`` and the loop's full-body fields."""
    t0 = float(log.tc[0]) if len(log.tc) else 0.0
    after = log.t - t0 >= settle_time
    after_c = log.tc - t0 >= settle_time
    ec = log.e_contouring[after]
    el = log.e_lag[after]
    eca = log.e_cartesian[after]
    el = el[np.isfinite(el)]
    eca = eca[np.isfinite(eca)]
    progress = float(log.theta_final)
    overtook = False
    if len(obstacles):
        t_end = float(log.tc[-1]) if len(log.tc) else 0.0
        overtook = all(
            ob.path is not None and progress > ob.s0 + ob.speed * t_end + max(ob.axes) + 0.2 for ob in obstacles
        )
    s: dict[str, Any] = {
        "steps": int(log.steps),
        "fell": bool(result.fell),
        "fall_step": int(log.steps) if result.fell else None,
        "solver_failures": int(source.solver_failures),
        "solve_ms": timing_stats_ms(source.solve_times),
        "contouring_error_max_m": max_abs(ec),
        "contouring_error_rms_m": rms(ec),
        "contouring_error_continuous_max_m": max_abs(log.e_contouring_c[after_c]),
        "lag_error_rms_m": rms(el),
        "cartesian_error_max_m": max_abs(eca),
        "min_clearance_m": float(np.min(log.clearance)) if len(obstacles) and len(log.clearance) else None,
        "overtook": bool(overtook),
        "progress_m": progress,
        "v_avg_mean": float(np.mean(log.v_avg)) if len(log.v_avg) else float("nan"),
        "v_max": log.v_max,
        "push_recovery_s": push_recovery_times(log, 0.05),
        "error_settle_time_s": settle_time,
        "duration_s": float(log.tc[-1] - t0) if len(log.tc) else 0.0,
        "step_duration_s": {
            "model": float(source.params.model.T),
            "mean_measured": float(np.mean(np.diff(log.t))) if log.steps > 1 else float("nan"),
        },
        "timing_offset_s": float(source.timing_offset),
    }
    full = result.summary()
    for k in ("fell", "steps"):
        full.pop(k, None)
    s.update(full)
    return s


def push_recovery_times(log: FullBodyPathLog, bound: float = 0.05) -> list[float]:
    """For each push, the time from its end to the first touch-down at which |contouring error| < ``bound``
    [m] (NaN when it never comes back before the end of the run) [s]."""
    out = []
    e = np.abs(log.e_contouring)
    for pu in log.pushes:
        t_end = pu.t_start + pu.duration
        if not np.any(log.t >= t_end):
            continue
        idx = np.flatnonzero((log.t >= t_end) & (e < bound))
        out.append(float(log.t[idx[0]] - t_end) if idx.size else float("nan"))
    return out


# --------------------------------------------------------------------------------------------
# A run
# --------------------------------------------------------------------------------------------
@dataclass
class FullBodyPathRun:
    """Everything a full-body paper A run produces.

    Attributes:
        result: the loop's :class:`~lipmpcc.loops.fullbody.loop.LoopResult`.
        log: :class:`FullBodyPathLog` (the paper's quantities).
        summary: the summary fields (:func:`summarize`).
        source: the MPCC footstep source (its records hold every solve).
        loop: the :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop` (its ``sim.model`` renders the video).
        path: the reference path; obstacles: the obstacles; params: the MPCC parameters.
    """

    result: Any
    log: FullBodyPathLog
    summary: dict[str, Any]
    source: Any
    loop: Any
    path: Path
    obstacles: list[Obstacle]
    params: MpccParams


def simulate(
    robot: Any,
    scenario: str,
    planner: str = "mpcc",
    path: Path | None = None,
    obstacles: Sequence[Obstacle] | Callable[[Path], Sequence[Obstacle]] | None = None,
    obstacle_speed: float | None = None,
    pushes: Sequence[Any] = (),
    duration: float | None = None,
    n_steps: int | None = None,
    record_video: bool = False,
    progress: bool = False,
    settle_time: float = SETTLE_TIME,
    loop: Any | None = None,
) -> FullBodyPathRun:
    """Run one of paper A's studies on a full-body robot.

    Args:
        robot: a :class:`~lipmpcc.robot.RobotDescription` (``load_robot("digit_like")``).
        scenario: ``"circle"``, ``"circle-push"`` or ``"overtake"`` (picks the weights and the default
            path and obstacle).
        planner: ``"mpcc"`` or ``"cartesian"``.
        path: reference path (world frame); None: the scenario's, starting at the standing COM.
        obstacles: obstacles, or a function of the path that makes them (e.g. from a JSON file with
            obstacles moving along the path); None: the scenario's (overtake: one cylinder
            ``OBSTACLE_START`` ahead).
        obstacle_speed: speed of the default obstacle [m/s] (None: paper A's for the planner).
        pushes: planar torso pushes (:class:`lipmpcc.loops.lip.Push`).
        duration: simulated time [s] (None with ``n_steps`` None: the scenario's default).
        n_steps: stop after this many touch-downs.
        record_video: record configurations for a video.
        progress: progress bar.
        settle_time: errors are judged after this time [s].
        loop: an existing :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop` to reuse its simulator and
            whole-body controller (its planner is replaced).
    """
    from ..planners.mpcc_source import MpccFootstepSource
    from ..loops.fullbody.loop import FullBodyLoop, LoopParams

    if scenario not in ("circle", "circle-push", "overtake"):
        raise InvalidInputError("scenario", scenario, "'circle', 'circle-push' or 'overtake'")
    if planner not in ("mpcc", "cartesian"):
        raise InvalidInputError("--planner", planner, "'mpcc' or 'cartesian' for this scenario")
    if duration is not None and not (math.isfinite(duration) and duration > 0.0):
        raise InvalidInputError("--duration", duration, "a positive simulated time [s]")
    probe = loop if loop is not None else FullBodyLoop(robot, planner=None)
    com0, yaw0 = standing_state(probe)
    H = float(com0[2])
    prm = fullbody_params(scenario, planner, H, min_lateral_step=robot.min_lateral_step,
                          step_duration=robot.step_duration)
    if path is None:
        path = circle_path(com0[:2], yaw0) if scenario.startswith("circle") else line_path(com0[:2], yaw0)
    if obstacles is None:
        obstacles = []
        if scenario == "overtake":
            speed = PAPER_SPEED[planner] if obstacle_speed is None else float(obstacle_speed)
            obstacles = [Obstacle.circle(OBSTACLE_RADIUS, path=path, s0=min(OBSTACLE_START, path.length), speed=speed)]
    elif callable(obstacles):
        obstacles = obstacles(path)
    obstacles = list(obstacles)
    if duration is None and n_steps is None:
        key = scenario if scenario.startswith("circle") else f"overtake-{planner}"
        duration = float(config.horizon(*DEFAULT_DURATION[key]))
    source = MpccFootstepSource(path, prm, obstacles, name=planner)
    source.warm_up()  # build/JIT the solvers before the timed run
    loop = FullBodyLoop(robot, planner=source, params=LoopParams(com_height=H), sim=probe.sim, wbc=probe.wbc)
    result = loop.run(duration=duration, n_steps=n_steps, pushes=loop_pushes(pushes), progress=progress, record_video=record_video)
    log = build_log(result, source, path, obstacles, pushes)
    summary = summarize(log, result, source, obstacles, settle_time)
    summary["stopped_reason"] = (
        "fell" if result.fell else ("steps" if n_steps is not None and result.n_steps >= n_steps else "duration")
    )
    return FullBodyPathRun(result=result, log=log, summary=summary, source=source, loop=loop, path=path, obstacles=obstacles, params=prm)


# --------------------------------------------------------------------------------------------
# Frames and video (path and obstacles drawn into the MuJoCo scene)
# --------------------------------------------------------------------------------------------
def _scene_recorder(run: FullBodyPathRun, settings: Any) -> Any:
    """A video recorder that also draws the reference path (red, on the floor, within 4 m of the robot) and
    the obstacles at the time of each frame (the MuJoCo model has neither)."""
    import mujoco

    from ..sim import render

    path, obstacles = run.path, run.obstacles
    pts = path.position(np.arange(0.0, path.length + 1e-9, 0.1))
    red = np.array([0.85, 0.1, 0.1, 1.0], dtype=np.float32)
    grey = np.array([0.45, 0.45, 0.5, 0.75], dtype=np.float32)
    eye = np.eye(3).reshape(-1)

    class SceneRecorder(render.VideoRecorder):
        t = 0.0  # time of the frame being rendered [s]

        def render(self, data: Any) -> np.ndarray:
            r = getattr(self, "_renderer", None)
            if r is None or not hasattr(self, "_camera"):  # pragma: no cover - recorder internals changed
                return super().render(data)
            r.update_scene(data, camera=self._camera, scene_option=self._option)
            scn = r.scene
            com = np.asarray(data.subtree_com[0][:2])
            near = np.linalg.norm(pts - com, axis=1) < 4.0
            for a, b, ok in zip(pts[:-1], pts[1:], near[:-1] & near[1:]):
                if ok and scn.ngeom < scn.maxgeom:
                    g = scn.geoms[scn.ngeom]
                    mujoco.mjv_initGeom(g, mujoco.mjtGeom.mjGEOM_CAPSULE, np.zeros(3), np.zeros(3), eye, red)
                    mujoco.mjv_connector(g, mujoco.mjtGeom.mjGEOM_CAPSULE, 0.012, np.r_[a, 0.005], np.r_[b, 0.005])
                    scn.ngeom += 1
            for ob in obstacles:
                if scn.ngeom >= scn.maxgeom:
                    break
                c = np.asarray(ob.center(self.t), dtype=float)
                psi = float(ob.heading(self.t))
                R = np.array([[math.cos(psi), -math.sin(psi), 0.0], [math.sin(psi), math.cos(psi), 0.0], [0.0, 0.0, 1.0]])
                kind = mujoco.mjtGeom.mjGEOM_CYLINDER if ob.is_circle else mujoco.mjtGeom.mjGEOM_ELLIPSOID
                size = np.array([ob.axes[0], ob.axes[1], 0.5])
                mujoco.mjv_initGeom(scn.geoms[scn.ngeom], kind, size, np.r_[c, 0.5], R.reshape(-1), grey)
                scn.ngeom += 1
            return r.render().copy()

    return SceneRecorder(run.loop.sim.model, settings)


def render_frames(
    run: FullBodyPathRun, times: Sequence[float] | None = None, settings: Any = None, size: tuple[int, int] = (640, 480)
) -> tuple[list[np.ndarray], np.ndarray]:
    """Render a run recorded with ``record_video=True``, with its path and obstacles drawn in.

    Args:
        run: the run.
        times: wanted times [s] (the nearest recorded frames); None: every recorded frame.
        settings: :class:`~lipmpcc.sim.render.VideoSettings` (None: tracking the torso, seen from behind
            on its right, 4.5 m away).
        size: (width, height) of the images [px] when ``settings`` is None.

    Returns:
        (RGB images, their times [s]).
    """
    import mujoco

    from ..sim import render

    frames, ftimes = run.result.frames, run.result.frame_times
    if frames is None or len(frames) == 0:
        raise InvalidInputError("run", "no recorded frames", "a run simulated with record_video=True")
    idx = np.arange(len(frames)) if times is None else np.unique(
        [int(np.argmin(np.abs(ftimes - float(t)))) for t in times]
    )
    if settings is None:
        settings = render.VideoSettings(width=int(size[0]), height=int(size[1]), fps=run.loop.params.video_fps,
                                        track_body=run.loop.robot.torso_body, distance=4.5, azimuth=35.0, elevation=-20.0)
    model = run.loop.sim.model
    data = mujoco.MjData(model)
    images = []
    with _scene_recorder(run, settings) as rec:
        for i in idx:
            data.qpos[:] = frames[i]
            mujoco.mj_forward(model, data)
            rec.t = float(ftimes[i])
            images.append(rec.render(data))
    return images, np.asarray(ftimes)[idx]


def write_video(run: FullBodyPathRun, path: str | FsPath, size: tuple[int, int] | None = None, every: int | None = None) -> FsPath:
    """Write the run's video with its path and obstacles drawn in.

    Args:
        run: a run simulated with ``record_video=True``.
        path: ``.mp4`` (needs imageio-ffmpeg) or ``.gif``.
        size: (width, height) [px]; None: 640×480 for MP4, 400×300 for GIF.
        every: keep every ``every``-th recorded frame; None: all for MP4 (30 fps), every 2nd for GIF
            (15 fps), which keeps a 45 s GIF near 20 MB.
    """
    from ..sim import render

    gif = FsPath(path).suffix.lower() == ".gif"
    size = size or ((400, 300) if gif else (640, 480))
    every = max(1, int(every or (2 if gif else 1)))
    times = run.result.frame_times[::every] if run.result.frame_times is not None else None
    images, _ = render_frames(run, times, size=size)
    return FsPath(render.save_frames(images, path, run.loop.params.video_fps / every))


# --------------------------------------------------------------------------------------------
# CLI entry points (called by lipmpcc.scenarios.path_following when --robot is not "lip")
# --------------------------------------------------------------------------------------------
def _video(run: FullBodyPathRun, opts: RunOptions) -> list[FsPath]:
    """``OUT/SCENARIO.mp4`` (``.gif`` without imageio-ffmpeg) when ``--video`` is given."""
    if not opts.video or run.result.frames is None or len(run.result.frames) == 0:
        return []
    from ..sim import render

    suffix = ".mp4" if ".mp4" in render.video_formats() else ".gif"
    return [write_video(run, FsPath(opts.out) / f"{opts.scenario}{suffix}")]


def run(opts: RunOptions, scenario: str, planner: str, pushes_fn: Any = None) -> RunResult:
    """A full-body paper A study from the CLI options (robot, path, obstacles, steps/duration, video)."""
    from ..plots import path_following as plots
    from ..robot import load_robot

    robot = load_robot(opts.robot)
    path = load_path_csv(opts.path) if opts.path else None
    obstacles = (lambda p: obstacles_from_json(opts.obstacles, p)) if opts.obstacles else None
    duration = opts.duration
    key = scenario if scenario.startswith("circle") else f"overtake-{planner}"
    if duration is None and opts.steps is None:
        duration = float(config.horizon(*DEFAULT_DURATION[key]))
    t_end = duration if duration is not None else 5.0 + float(opts.steps)  # the loop's own bound for --steps
    pushes = pushes_fn(t_end) if pushes_fn else []
    fb = simulate(robot, scenario, planner, path, obstacles, opts.obstacle_speed, pushes, duration, opts.steps,
                  record_video=opts.video, progress=True)
    summary: dict[str, Any] = {"scenario": scenario, "planner": planner, "robot": getattr(robot, "name", str(opts.robot))}
    summary.update(fb.summary)
    summary["seed"] = opts.seed
    summary["fast_mode"] = config.fast_mode()
    summary["pushes"] = int(sum(p.t_start < fb.summary["duration_s"] for p in pushes))
    prm = fb.params
    summary["params"] = {
        "N": prm.N, "T_s": prm.model.T, "H_m": prm.model.H, "Q_bar": prm.Q_bar, "W_bar": prm.W_bar,
        "R": prm.R, "heading_weight": prm.heading_weight, "rho": prm.rho, "v_max": prm.v_max,
        "delta_min": prm.delta_min, "delta_max": prm.delta_max,
        "gamma": prm.gamma, "robot_radius": prm.robot_radius, "foot_radius": prm.foot_radius,
        "rectangle": {"forward": prm.rectangle.forward, "lateral": prm.rectangle.lateral, "heading": prm.rectangle.heading},
        "rate_hz": fb.source.rate_hz,
    }
    if fb.obstacles:
        summary["obstacle_speeds_mps"] = [
            float(ob.speed) if ob.path is not None else float(np.hypot(*ob.velocity)) for ob in fb.obstacles
        ]
    name = getattr(robot, "name", "full body")
    figs: dict[str, Any] = {}
    if scenario.startswith("circle"):
        figs[scenario] = plots.figure_circle_fullbody(fb.log, fb.path, f"{planner.upper()} on {name}, {scenario}")
    else:
        figs[scenario] = plots.figure_overtake(
            fb.log, fb.path, fb.obstacles, planner == "cartesian",
            title=("Cartesian MPC" if planner == "cartesian" else "MPCC") + f" on {name}: overtaking study",
        )
    files = _video(fb, opts)
    return RunResult(summary=summary, figures=figs, log=fb, files=files)
