"""Paper A's studies: ``circle``, ``circle-push`` and ``overtake``, and ``follow-path`` (a path of the user's),
on the 3D-LIP or on a full-body robot.

The MPCC (:mod:`lipmpcc.planners.mpcc`; ``--planner cartesian``: the Cartesian MPC, the same planner with
Q̄ = αI and paper A's Q = W = 200 I, ρ = 50) follows a path, with paper A's weights for the study:

- ``--robot lip`` (default): the reduced model (:mod:`lipmpcc.loops.lip`), re-solving at every support
  exchange, for ``--steps`` steps (:func:`simulate_lip`). With ``--step-duration-range TMIN TMAX`` the
  planner is the timed MPCC (:mod:`lipmpcc.planners.mpcc_timed`, the study's preset with each step's
  duration in [TMIN, TMAX] s); without it, paper A's fixed T (0.4 s) as before.
- ``--robot digit_like`` or ``--robot PATH.xml``: the full-body loop (:mod:`lipmpcc.loops.fullbody.loop`:
  MuJoCo at 2 kHz, the whole-body QP at 400 Hz) through
  :class:`~lipmpcc.planners.sources.mpcc.MpccFootstepSource`, re-planning at 15 Hz within each swing, for
  ``--duration`` seconds or ``--steps`` touch-downs, whichever comes first (:func:`simulate_full_body`;
  the MPCC's model and limits on a full body: :func:`fullbody_params`). With ``--step-duration-range``
  the source is the timed MPCC's (:class:`lipmpcc.planners.sources.mpcc.TimedMpccFootstepSource`), re-planned at 25 Hz
  within each step from the measured state, the swing re-timed to each plan's duration.

One set-up for both (the constants name what differs between the two):

- ``circle``: a counter-clockwise circle of radius 2 m (1.25 turns of path) through the robot's start,
  along its heading (the LIP starts at rest at the origin heading +x; a full body at its standing COM,
  heading along its torso). 120 steps on the LIP (40 in fast mode); 45 s on a full body (10 s).
- ``circle-push``: the same under paper A's random pushes (:func:`paper_a_pushes`, seeded by ``--seed``).
- ``overtake``: a 40 m straight line; a cylinder of radius 0.25 m starts :data:`OBSTACLE_START` (LIP) or
  :data:`FULLBODY_OBSTACLE_START` ahead and moves along it at ``--obstacle-speed`` (paper A: 0.6 m/s for
  the MPCC, 0.1 m/s for the Cartesian MPC). 70 steps (60) on the LIP; on a full body 30 s (25 s) for the
  MPCC, 25 s (15 s) for the Cartesian MPC.
- ``--path FILE.csv`` and ``--obstacles FILE.json`` replace the path and the obstacles.
- ``follow-path``: the path of ``--path FILE.csv`` (required), with the obstacles of ``--obstacles`` (none
  without), and paper A's contouring-accurate weights (the ``circle`` preset, not the overtaking one: with
  its contouring weight 1 the robot cuts bends). It walks to the end of the path: on the LIP at most
  :func:`follow_path_steps` steps, on a full body :func:`follow_path_duration` seconds.
- ``--preset NAME`` and ``--set KEY=VALUE`` (:mod:`lipmpcc.planners.presets`) change the MPCC's weights and
  bounds (:class:`~lipmpcc.planners.presets.PlannerSettings`, applied over the study's parameters); the
  summary records ``preset`` (the one in effect), ``planner_set`` and ``planner_params``.

Errors are judged after :data:`SETTLE_TIME` (LIP) or :data:`FULLBODY_SETTLE_TIME` (a full body starts
from rest with a weight shift). At each support exchange: the contouring error at the closest point
(eq. 19), the lag error against the path parameter the MPCC committed to for that exchange, and the
Cartesian error to that point. On a full body these are the measured COM's at the touch-downs; the
summary adds the contouring error at every WBC tick (``contouring_error_continuous_max_m``), and the
clearance is the COM disk's (0.2 m) and the stance-foot disks' (0.1 m) at every tick; with obstacles,
``min_body_clearance_m`` is the whole robot's, from its MuJoCo geometry on the configurations recorded at
the video's rate (:mod:`lipmpcc.studies.clearance`), and ``collided`` reads it
(:mod:`lipmpcc.studies.outcome`). A full-body ``--path`` must start where the robot stands, facing along
it (:func:`check_path_start`); the LIP starts on the path's first point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np

from .. import config
from ..contouring import errors as contouring_errors
from ..exceptions import InvalidInputError
from ..loops import lip as lip_loop
from ..metrics import max_abs, rms, timing_stats_ms
from ..models.lip3d import Lip3dModel, ReachabilityRectangle
from ..obstacles import Obstacle, obstacles_from_json
from ..paths import ArcPath, LinePath, Path, load_path_csv
from ..planners.mpcc import MpccParams, MpccPlanner, MpccResult
from ..planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner
from ..planners.presets import PlannerSettings, params_dict
from ..plots import path_following as plots
from ..plots.logs import PathFollowingLog
from ..push import Push
from . import replay, video
from .viewer import LiveViewer, live_viewer
from .options import RunOptions, RunResult, check_step_duration_range
from .outcome import PathAssessment, ProgressTrace, add_outcome, assess_progress

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ..loops.fullbody.loop import FullBodyLoop, LoopResult
    from ..planners.sources.mpcc import MpccFootstepSource
    from ..robots import RobotDescription
    from ..sim.render import VideoSettings

__all__ = [
    "SCENARIOS",
    "PLANNERS",
    "CIRCLE_RADIUS",
    "OBSTACLE_RADIUS",
    "PAPER_SPEED",
    "SETTLE_TIME",
    "OBSTACLE_START",
    "FULLBODY_SETTLE_TIME",
    "FULLBODY_OBSTACLE_START",
    "STEP_DURATION",
    "FULLBODY_RECTANGLE",
    "robot_rectangle",
    "FULLBODY_OBSTACLE_MARGIN",
    "FULLBODY_CARTESIAN_HEADING_WEIGHT",
    "FULLBODY_TIMED_HEADING_RATIO",
    "FULLBODY_TIMED_TURN_WEIGHT",
    "PATH_START_TOLERANCE",
    "PATH_HEADING_TOLERANCE",
    "check_path_start",
    "check_obstacles_clear",
    "PathFollowingLog",
    "PathRun",
    "LipPathRun",
    "FullBodyPathRun",
    "circle_path",
    "line_path",
    "study_path",
    "study_obstacles",
    "paper_a_pushes",
    "lip_params",
    "lip_path_log",
    "timed_lip_planner",
    "simulate_lip",
    "lip_stopped_early",
    "fullbody_params",
    "timed_fullbody_params",
    "steady_heading_params",
    "body_clearance_params",
    "standing_state",
    "full_body_path_log",
    "summarize_full_body",
    "body_clearance_summary",
    "push_recovery_times",
    "timed_params",
    "simulate_full_body",
    "render_frames",
    "write_video",
    "run_circle",
    "run_circle_push",
    "run_overtake",
    "run_follow_path",
    "study_preset",
    "planner_fields",
    "follow_path_steps",
    "follow_path_duration",
    "run_goal",
    "progress_trace",
    "assess_run",
    "run_events",
]

SCENARIOS = ("circle", "circle-push", "overtake", "follow-path")
PLANNERS = ("mpcc", "cartesian")
ROBOT_CHOICES = "'lip' (the reduced model, default), 'digit_like' or the path of a robot MJCF (.xml)"
CIRCLE_RADIUS = 2.0  # [m]
CIRCLE_TURNS = 1.25  # path length in turns (the runs stop before its end)
LINE_LENGTH = 40.0  # [m]
OBSTACLE_RADIUS = 0.25  # [m] paper A
PAPER_SPEED = {"mpcc": 0.6, "cartesian": 0.1}  # [m/s] paper A §IV-B
# on the LIP
SETTLE_TIME = 2.0  # [s] start-up transient excluded from the error metrics
OBSTACLE_START = 1.5  # [m] ahead of the robot along the path
LIP_STEPS = {"circle": (120, 40), "circle-push": (120, 40), "overtake": (70, 60)}  # (full, fast)
# on a full body
FULLBODY_SETTLE_TIME = 3.0  # [s]
FULLBODY_OBSTACLE_START = 1.0  # [m]
STEP_DURATION = 0.4  # [s] the MPCC's T when the robot description does not give one
FULLBODY_RECTANGLE = ReachabilityRectangle(forward=(-0.35, 0.35), lateral=(0.10, 0.40), heading=(-0.3, 0.3))
FULLBODY_OBSTACLE_MARGIN = 0.10  # [m] barrier margin (0.05 on the LIP): the body sways between the steps
FULLBODY_CARTESIAN_HEADING_WEIGHT = 20.0  # the Cartesian MPC's weight on the heading error to the path
# the timed MPCC's heading weight on a full body per unit of its largest running tracking weight max(Q̄), twice the
# Cartesian MPC's ratio (20 against Q = 200), and its least weight on the heading change u^θ [1/rad²], ten times
# paper A's R_θ = 5; see timed_fullbody_params
FULLBODY_TIMED_HEADING_RATIO = 2.0 * FULLBODY_CARTESIAN_HEADING_WEIGHT / 200.0
FULLBODY_TIMED_TURN_WEIGHT = 50.0
PATH_START_TOLERANCE = 0.25  # [m] a full-body path starts this near the standing COM (check_path_start)
PATH_HEADING_TOLERANCE = 1.6  # [rad] and at most about a quarter turn from the torso heading (it turns on the spot)
DEFAULT_DURATION = {  # [s] (full, fast)
    "circle": (45.0, 10.0),
    "circle-push": (45.0, 10.0),
    "overtake-mpcc": (30.0, 25.0),
    "overtake-cartesian": (25.0, 15.0),
}
FOLLOW_PATH_M_PER_STEP = 0.08  # [m] follow-path's LIP step bound: path length / this (+ FOLLOW_PATH_EXTRA_STEPS)
FOLLOW_PATH_EXTRA_STEPS = 20
# [m/s] follow-path's full-body time bound: path length / this (+ FOLLOW_PATH_EXTRA_TIME + FULLBODY_SETTLE_TIME): the
# LIP's bound in time at T = STEP_DURATION (0.2 m/s, 8 s). A full body walks a free path at about 0.25 m/s, so the
# former bound of length / 0.25 m/s + 3 s left it no slack: any slowing down for an obstacle or a detour ended the
# run short of the end (issue 31's random scenes on digit_like: 17.5 and 17.8 m of 19 m in 79 s)
FOLLOW_PATH_SPEED = FOLLOW_PATH_M_PER_STEP / STEP_DURATION
FOLLOW_PATH_EXTRA_TIME = FOLLOW_PATH_EXTRA_STEPS * STEP_DURATION  # [s]
FOLLOW_PATH_MAX_STEPS = 2000  # the bounds' caps (a longer path: --steps, --duration)
FOLLOW_PATH_MAX_DURATION = 600.0  # [s]

ObstacleSpec = Sequence[Obstacle] | Callable[[Path], Sequence[Obstacle]] | None


# --------------------------------------------------------------------------------------------
# The set-up, common to both robots
# --------------------------------------------------------------------------------------------
def _check_study(scenario: str, planner: str) -> None:
    if scenario not in SCENARIOS:
        raise InvalidInputError("scenario", scenario, "'circle', 'circle-push', 'overtake' or 'follow-path'")
    if planner not in PLANNERS:
        raise InvalidInputError("--planner", planner, "'mpcc' or 'cartesian' for this scenario")


def circle_path(start: Sequence[float], heading: float, radius: float = CIRCLE_RADIUS) -> Path:
    """Counter-clockwise circle of ``radius`` [m] through ``start`` with tangent ``heading`` [rad]."""
    return ArcPath.circle(radius, start=(float(start[0]), float(start[1])), heading=float(heading), turns=CIRCLE_TURNS)


def line_path(start: Sequence[float], heading: float, length: float = LINE_LENGTH) -> Path:
    """Straight line of ``length`` [m] from ``start`` along ``heading`` [rad]."""
    s = np.asarray(start[:2], dtype=float)
    return LinePath(tuple(s), tuple(s + length * np.array([math.cos(heading), math.sin(heading)])))


def study_path(scenario: str, start: Sequence[float] = (0.0, 0.0), heading: float = 0.0) -> Path:
    """The study's path from the robot's start (x, y) [m] and heading [rad]: the circle or the line."""
    return circle_path(start, heading) if scenario.startswith("circle") else line_path(start, heading)


def study_obstacles(scenario: str, planner: str, path: Path, start: float, speed: float | None = None) -> list[Obstacle]:
    """The study's obstacles: none, or for ``overtake`` one cylinder ``start`` [m] ahead along ``path``
    moving at ``speed`` [m/s] (None: paper A's for ``planner``)."""
    if scenario != "overtake":
        return []
    v = PAPER_SPEED[planner] if speed is None else float(speed)
    return [Obstacle.circle(OBSTACLE_RADIUS, path=path, s0=min(start, path.length), speed=v)]


def _resolve_obstacles(spec: ObstacleSpec, scenario: str, planner: str, path: Path, start: float,
                       speed: float | None) -> list[Obstacle]:
    if spec is None:
        return study_obstacles(scenario, planner, path, start, speed)
    return list(spec(path) if callable(spec) else spec)


def paper_a_pushes(t_end: float, seed: int) -> list[Push]:
    """Paper A's random pushes up to ``t_end`` [s]: U[−50, 50] N in a uniform horizontal direction for
    0.1 s, at random instants at most 2 s apart (:func:`lipmpcc.loops.lip.random_pushes`, seeded)."""
    rng = np.random.default_rng(seed)
    return list(lip_loop.random_pushes(t_end, rng))


@dataclass
class PathRun:
    """One path-following run.

    Attributes:
        log: what the figures draw (:class:`~lipmpcc.plots.logs.PathFollowingLog`).
        summary: the run's metrics (summary.json fields).
        path, obstacles, params: the reference path, the obstacles and the MPCC parameters.
        pushes: the pushes (planar, world frame).
        settle_time: errors are judged after this time [s].
    """

    log: PathFollowingLog
    summary: dict[str, Any]
    path: Path
    obstacles: list[Obstacle]
    params: MpccParams
    pushes: list[Push]
    settle_time: float


# --------------------------------------------------------------------------------------------
# The LIP
# --------------------------------------------------------------------------------------------
@dataclass
class LipPathRun(PathRun):
    """A LIP run; ``lip_log`` is the loop's own :class:`~lipmpcc.loops.lip.LipLog`."""

    lip_log: lip_loop.LipLog


def study_preset(scenario: str, planner: str) -> str:
    """The name of the study's preset (:data:`lipmpcc.planners.presets.PRESETS`): ``cartesian`` for the
    Cartesian MPC, ``circle`` (contouring-accurate) for circle, circle-push and follow-path, else ``overtake``."""
    if planner == "cartesian":
        return "cartesian"
    return "circle" if scenario.startswith("circle") or scenario == "follow-path" else "overtake"


def lip_params(scenario: str, planner: str) -> MpccParams:
    """Paper A's preset of ``scenario`` for ``planner`` on the LIP (:func:`study_preset`)."""
    if planner == "cartesian":
        return MpccParams.overtake_cartesian()
    return MpccParams.circle() if study_preset(scenario, planner) == "circle" else MpccParams.overtake_mpcc()


def follow_path_steps(length: float) -> int:
    """follow-path's step bound on the LIP for a path of ``length`` [m] (the run ends at the path's end)."""
    return min(FOLLOW_PATH_MAX_STEPS, int(math.ceil(length / FOLLOW_PATH_M_PER_STEP)) + FOLLOW_PATH_EXTRA_STEPS)


def follow_path_duration(length: float) -> float:
    """follow-path's simulated time [s] on a full body for a path of ``length`` [m]: the LIP's step bound
    (:func:`follow_path_steps`) in time at T = :data:`STEP_DURATION`, after :data:`FULLBODY_SETTLE_TIME`."""
    return min(FOLLOW_PATH_MAX_DURATION, FULLBODY_SETTLE_TIME + FOLLOW_PATH_EXTRA_TIME + length / FOLLOW_PATH_SPEED)


def _initial_state(path: Path) -> np.ndarray:
    p0 = path.position(0.0)
    return np.array([p0[0], 0.0, p0[1], 0.0, path.slope(0.0)])


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


def _lip_steps(scenario: str, n_steps: int | None, path: Path | None = None) -> int:
    if n_steps:
        return n_steps
    if scenario == "follow-path":
        return follow_path_steps(path.length if path is not None else 0.0)
    return int(config.horizon(*LIP_STEPS[scenario]))


def timed_lip_planner(path: Path, prm: MpccParams, step_duration_range: Sequence[float],
                      within_step: bool = False) -> TimedMpccPlanner:
    """The timed MPCC (:class:`~lipmpcc.planners.mpcc_timed.TimedMpccPlanner`) of the preset ``prm``, each
    step's duration in ``step_duration_range`` = (TMIN, TMAX) [s] (checked by
    :func:`~lipmpcc.studies.options.check_step_duration_range` against the preset's T), called at each
    support exchange or, with ``within_step``, within steps (the loop's ``replan_hz``)."""
    return TimedMpccPlanner(path, timed_params(prm, step_duration_range), within_step=within_step)


def timed_params(prm: MpccParams, step_duration_range: Sequence[float]) -> TimedMpccParams:
    """The timed MPCC's parameters: ``prm`` with each step's duration in ``step_duration_range`` = (TMIN, TMAX)
    [s] (checked by :func:`~lipmpcc.studies.options.check_step_duration_range` against the preset's T). A fixed
    duration TMIN = TMAX other than the preset's T becomes the model's T (paper A's MPCC at that T: its
    per-step bounds v_max and delta_max then hold per shorter or longer step)."""
    lo, hi = check_step_duration_range(step_duration_range, prm.model.T)
    if lo == hi and lo != prm.model.T:
        prm = replace(prm, model=replace(prm.model, T=lo))
    return TimedMpccParams(mpcc=prm, T_min=lo, T_max=hi)


def _run_lip_timed(planner: TimedMpccPlanner, x0: np.ndarray, n_steps: int, obstacles: list[Obstacle],
                   pushes: list[Push], replan_hz: float | None = None) -> lip_loop.LipLog:
    """:func:`lipmpcc.loops.lip.simulate`'s call of the loop, with the timed MPCC (re-planned within steps at
    ``replan_hz`` [Hz]; None: at the exchanges)."""
    prm = planner.params.mpcc
    return lip_loop.run_lip_loop(planner, x0, n_steps, planner.path, obstacles, pushes, 1, prm.model.H, prm.model.g,
                                 robot_radius=prm.robot_radius, foot_radius=prm.foot_radius, replan_hz=replan_hz)


def simulate_lip(
    scenario: str,
    planner: str = "mpcc",
    path: Path | None = None,
    obstacles: ObstacleSpec = None,
    obstacle_speed: float | None = None,
    pushes: Sequence[Push] = (),
    n_steps: int | None = None,
    step_duration_range: Sequence[float] | None = None,
    settings: PlannerSettings | None = None,
    replan_hz: float | None = None,
) -> LipPathRun:
    """Run one of paper A's studies on the LIP.

    Args:
        scenario: ``"circle"``, ``"circle-push"`` or ``"overtake"`` (the weights, path and obstacle).
        planner: ``"mpcc"`` or ``"cartesian"``.
        path: reference path; None: the study's, from the origin heading +x.
        obstacles: obstacles, or a function of the path that makes them; None: the study's.
        obstacle_speed: speed of the study's obstacle [m/s] (None: paper A's for the planner).
        pushes: pushes on the point mass (e.g. :func:`paper_a_pushes`).
        n_steps: number of steps (None: the study's).
        step_duration_range: (TMIN, TMAX) [s]: the timed MPCC chooses each step's duration in it
            (:func:`timed_lip_planner`); None: paper A's fixed T.
        settings: ``--preset`` / ``--set`` applied over the study's parameters (None: the study's).
        replan_hz: with ``step_duration_range``, re-plan within each step at this rate [Hz] (paper B: 25;
            :func:`lipmpcc.loops.lip.run_lip_loop`); None: once per step, at the support exchange.
    """
    _check_study(scenario, planner)
    if replan_hz is not None and step_duration_range is None:
        raise InvalidInputError("replan_hz", replan_hz, "None without step_duration_range (only the timed MPCC "
                                "re-plans within steps)")
    if path is None:
        if scenario == "follow-path":
            raise InvalidInputError("path", None, "a path for follow-path (--path FILE.csv)")
        path = study_path(scenario)
    obs = _resolve_obstacles(obstacles, scenario, planner, path, OBSTACLE_START, obstacle_speed)
    prm = lip_params(scenario, planner)
    if settings is not None:
        prm = settings.apply(prm, planner)
    check_obstacles_clear(obs, path.position(0.0), prm.robot_radius)
    steps = _lip_steps(scenario, n_steps, path)
    if step_duration_range is None:
        log = lip_loop.simulate(MpccPlanner(path, prm), _initial_state(path), steps, obs, list(pushes))
    else:
        timed = timed_lip_planner(path, prm, step_duration_range, within_step=replan_hz is not None)
        prm = timed.params.mpcc  # a fixed TMIN = TMAX is its model's T
        log = _run_lip_timed(timed, _initial_state(path), steps, obs, list(pushes), replan_hz)
    summary = lip_loop.summarize(log, obs, settle_time=SETTLE_TIME)
    return LipPathRun(lip_path_log(log), summary, path, obs, prm, list(pushes), SETTLE_TIME, log)


# --------------------------------------------------------------------------------------------
# A full body
# --------------------------------------------------------------------------------------------
@dataclass
class FullBodyPathRun(PathRun):
    """A full-body run.

    Attributes:
        result: the loop's :class:`~lipmpcc.loops.fullbody.loop.LoopResult`.
        source: the MPCC footstep source (its records hold every solve).
        loop: the :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop` (its ``sim.model`` renders the video).
    """

    result: LoopResult
    source: MpccFootstepSource
    loop: FullBodyLoop


def robot_rectangle(robot: RobotDescription) -> ReachabilityRectangle:
    """The MPCC's reachability on ``robot``: :data:`FULLBODY_RECTANGLE` (Digit's) unless the robot's layout
    states ``max_step_length`` and ``step_width``; then the forward range scales with the reach (Digit:
    0.55 m) and the lateral upper bound with the step width (Digit: 0.26 m)."""
    if robot.max_step_length is None or robot.step_width is None:
        return FULLBODY_RECTANGLE
    r = FULLBODY_RECTANGLE
    fwd, lat = robot.max_step_length / 0.55, robot.step_width / 0.26
    return ReachabilityRectangle(forward=(r.forward[0] * fwd, r.forward[1] * fwd), lateral=(r.lateral[0], r.lateral[1] * lat),
                                 heading=r.heading)


def fullbody_params(
    scenario: str,
    planner: str,
    com_height: float,
    min_lateral_step: float | None = None,
    step_duration: float | None = None,
    rectangle: ReachabilityRectangle | None = None,
) -> MpccParams:
    """Paper A's MPCC preset of ``scenario`` / ``planner`` for a full body.

    The LIP's H is the loop's COM height (one ω for the MPCC, the loop's COM reference and the
    exchange-state prediction); the reachability's lateral range starts at the robot's
    ``min_lateral_step`` (:data:`FULLBODY_RECTANGLE`: 0.10 m); obstacles get a wider margin
    (:data:`FULLBODY_OBSTACLE_MARGIN`); the Cartesian MPC also weighs the heading error
    (:data:`FULLBODY_CARTESIAN_HEADING_WEIGHT`).

    Args:
        scenario: ``"circle"``, ``"circle-push"`` or ``"overtake"``.
        planner: ``"mpcc"`` or ``"cartesian"``.
        com_height: the loop's constant COM height [m] (the LIP's H).
        min_lateral_step: lower bound of the lateral reachability [m]; None: 0.10 m.
        step_duration: the LIP's step duration T [s] (the robot description's); None: :data:`STEP_DURATION`.
        rectangle: the reachability before ``min_lateral_step`` applies (:func:`robot_rectangle`); None:
            :data:`FULLBODY_RECTANGLE`.
    """
    if not (math.isfinite(com_height) and com_height > 0.0):
        raise InvalidInputError("com_height", com_height, "a positive COM height [m]")
    T = STEP_DURATION if step_duration is None else step_duration
    if isinstance(T, bool) or not isinstance(T, (int, float)) or not (math.isfinite(T) and 0.2 <= T <= 1.0):
        raise InvalidInputError("step_duration", step_duration, "a step duration in [0.2, 1.0] [s]")
    rect = FULLBODY_RECTANGLE if rectangle is None else rectangle
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
    return MpccParams.circle(**kw) if study_preset(scenario, planner) == "circle" else MpccParams.overtake_mpcc(**kw)


def timed_fullbody_params(prm: MpccParams, robot: RobotDescription, settings: PlannerSettings | None = None,
                          obstacles: bool = True) -> MpccParams:
    """The timed MPCC's parameters on a full body: ``prm`` (:func:`fullbody_params`, with ``--preset`` /
    ``--set`` applied) with three changes, each left alone when ``--set`` gives that field (the first two only
    with ``obstacles``, a run that has some):

    - ``heading_weight`` at least :data:`FULLBODY_TIMED_HEADING_RATIO` × max(Q̄) (overtake: 200; circle: 60;
      Cartesian: 40) and the weight on the heading change, ``R[2]`` (``r_theta``), at least
      :data:`FULLBODY_TIMED_TURN_WEIGHT` (50 [1/rad²], paper A's 5). The full body turns its torso and feet to
      the planned heading; paper A's MPCC presets leave the heading almost free, and the reachability
      rectangle turns with it, so the timed MPCC turned the planned heading by up to 0.3 rad a step (the
      bound) to cheapen its foot offsets while it swerved. The LIP follows such plans; ``digit_like``'s yaw
      swung by up to ±0.9 rad from one re-plan to the next, its lateral COM velocity reached 1.8 m/s, and it
      fell (docs/design.md, the timed MPCC: with half the heading weight alone it passed 0.8 m/s and fell
      at 0.79 m/s; with both it passes 0.70-0.82 m/s). Without obstacles they are not set: on the circle
      any heading weight took away the longer step after paper B's backward push (Fig. 7; 0.39 against
      0.40 s unpushed, 0.46 s without), and a path without obstacles calls for no swerve.
    - ``robot_radius``: the whole-body disk of :func:`body_clearance_params`, for any planner (the Cartesian
      MPC's too; :func:`simulate_full_body` has already applied it to the MPC's, and again it changes nothing).

    Fixed T (:func:`fullbody_params` and :func:`body_clearance_params`) keeps paper A's weights in paper A's
    studies; on a scene of the user's (``follow-path``, or a ``--path``) it gets the same heading weights
    (:func:`steady_heading_params`).
    """
    if obstacles:
        prm = steady_heading_params(prm, settings)
    return body_clearance_params(prm, robot, settings)


def steady_heading_params(prm: MpccParams, settings: PlannerSettings | None = None) -> MpccParams:
    """``prm`` with ``heading_weight`` at least :data:`FULLBODY_TIMED_HEADING_RATIO` × max(Q̄) and ``R[2]``
    at least :data:`FULLBODY_TIMED_TURN_WEIGHT`, each left alone when ``--set`` gives it: a full body's
    heading held to the path while it swerves (:func:`timed_fullbody_params` says why).

    Fixed T on a full body gets them on a user's scene with obstacles (:func:`simulate_full_body`): with paper
    A's near-free heading, on issue 31's random scenes on ``digit_like`` the planned heading change sat at
    its ±0.3 rad bound and flipped sign between the re-plans of one swing (seed 9), and in the detour the robot
    turned round to face backwards (seed 1, heading from −0.1 to ±π in 9 steps), then fell."""
    given = set(settings.values) if settings is not None else set()
    kw: dict[str, Any] = {}
    if "heading_weight" not in given:
        kw["heading_weight"] = max(prm.heading_weight, FULLBODY_TIMED_HEADING_RATIO * float(max(prm.Q_bar)))
    if "r_theta" not in given:
        kw["R"] = (prm.R[0], prm.R[1], max(float(prm.R[2]), FULLBODY_TIMED_TURN_WEIGHT))
    return prm.with_(**kw)


def body_clearance_params(prm: MpccParams, robot: RobotDescription, settings: PlannerSettings | None = None) -> MpccParams:
    """The MPCC's body disk on a full body (fixed T and timed; :func:`simulate_full_body` applies it to the MPCC,
    not to the Cartesian MPC at fixed T): ``robot_radius`` at least the radius of what
    the robot's geometry covers about its COM during a step (:func:`~lipmpcc.studies.clearance.swept_body`
    with the legs swept by half the largest COM distance per step, ``delta_max`` / 2), unless ``--set``
    gives ``robot_radius``.

    Paper A's 0.2 m disk holds the torso, not the arms and legs: on ``digit_like`` the 0.6 m/s obstacle
    caught the trailing right thigh from behind (6.7 cm deep) while the COM disk kept 0.098 m. The swept
    disk is ``digit_like``'s 0.432 m (its right thigh swept back; standing, its forearms reach 0.415 m),
    Digit v3's 0.531 m (its elbows). The MPCC's barriers (COM disk grown by ``robot_radius`` +
    ``obstacle_margin``, footholds by ``foot_radius`` + ``obstacle_margin``) are unchanged in form.

    The Cartesian MPC at fixed T keeps paper A's 0.2 m disk: it trails the obstacle, which starts 1 m ahead,
    and with Digit v3's 0.531 m disk the robot stood 0.12 m outside the grown barrier at the start and fell
    at 2.7 s (``digit_like`` trailed with its 0.432 m disk, 0.334 m clear).
    """
    given = set(settings.values) if settings is not None else set()
    if "robot_radius" in given:
        return prm
    from .clearance import swept_body

    return prm.with_(robot_radius=max(prm.robot_radius, swept_body(robot, 0.5 * prm.delta_max).radius))


def standing_state(loop: FullBodyLoop) -> tuple[np.ndarray, float]:
    """The robot's standing COM (3,) [m] and torso yaw [rad] (resets the loop's simulator)."""
    sim = loop.sim
    sim.reset(loop.robot.standing_reset)  # keyframe or standing qpos (Digit v3 has no keyframe)
    com = np.asarray(sim.com(), dtype=float)
    R = np.asarray(sim.torso_pose().rotation, dtype=float)
    return com, math.atan2(R[1, 0], R[0, 0])


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
    tds = result.touchdowns
    n = len(tds)
    tc = np.asarray(log.t, dtype=float)
    com = np.column_stack([log.com[:, 0], log.com_vel[:, 0], log.com[:, 1], log.com_vel[:, 1]]) if len(tc) else np.zeros((0, 4))
    theta_c = _closest_dense(path, np.asarray(log.com[:, :2], dtype=float))
    e_c = contouring_errors(log.com[:, :2], path.position(theta_c), path.slope(theta_c))[:, 0] if len(tc) else np.zeros(0)
    t_td = np.array([td.t for td in tds], dtype=float)
    feet = np.array([[td.pos[0], td.pos[1], td.yaw] for td in tds], dtype=float).reshape(n, 3)
    idx = np.clip(np.searchsorted(tc, t_td), 0, max(len(tc) - 1, 0))
    pos_td = (com[idx] if n else np.zeros((0, 4)))[:, [0, 2]]
    e_td, e_lag, e_cart = _touchdown_errors(pos_td, path, _committed_theta(source, n))
    obs_c, clearance = _clearance(result, obstacles, source.params)
    recs = [r for r in source.records if r.result is not None]
    return PathFollowingLog(
        t=t_td, e_contouring=e_td, e_lag=e_lag, e_cartesian=e_cart,
        footholds=feet, sides=np.array([1 if td.side == "left" else -1 for td in tds], dtype=int),
        step_offsets=feet[:, :2] - pos_td,
        v_avg_t=np.array([r.t for r in recs], dtype=float), v_avg=np.array([r.result.v_avg for r in recs], dtype=float),
        v_max=source.params.v_max, tc=tc, com=com, obstacles=obs_c, clearance=clearance, pushes=tuple(pushes),
        progress=float(theta_c[-1]) if len(theta_c) else 0.0, theta_c=theta_c, e_contouring_c=e_c,
    )


def push_recovery_times(log: PathFollowingLog, bound: float = 0.05) -> list[float]:
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


def _overtook(log: PathFollowingLog, obstacles: Sequence[Obstacle]) -> bool:
    """At the end, the robot's footprint is entirely ahead of every obstacle along the path."""
    if not len(obstacles):
        return False
    t_end = float(log.tc[-1]) if len(log.tc) else 0.0
    return all(ob.path is not None and log.progress > ob.s0 + ob.speed * t_end + max(ob.axes) + 0.2 for ob in obstacles)


def summarize_full_body(log: PathFollowingLog, result: LoopResult, source: MpccFootstepSource,
                        obstacles: Sequence[Obstacle] = (), settle_time: float = FULLBODY_SETTLE_TIME) -> dict[str, Any]:
    """The LIP runs' summary fields (:func:`lipmpcc.loops.lip.summarize`) of a full-body run, plus
    ``contouring_error_continuous_max_m`` and the loop's full-body fields."""
    t0 = float(log.tc[0]) if len(log.tc) else 0.0
    after = log.t - t0 >= settle_time
    ec = log.e_contouring[after]
    el = log.e_lag[after]
    eca = log.e_cartesian[after]
    s: dict[str, Any] = {
        "steps": int(log.steps),
        "fell": bool(result.fell),
        "fall_step": int(log.steps) if result.fell else None,
        "solver_failures": int(source.solver_failures),
        "solve_ms": timing_stats_ms(source.solve_times),
        "contouring_error_max_m": max_abs(ec),
        "contouring_error_rms_m": rms(ec),
        "contouring_error_continuous_max_m": max_abs(log.e_contouring_c[log.tc - t0 >= settle_time]),
        "lag_error_rms_m": rms(el[np.isfinite(el)]),
        "cartesian_error_max_m": max_abs(eca[np.isfinite(eca)]),
        "min_clearance_m": float(np.min(log.clearance)) if len(obstacles) and len(log.clearance) else None,
        "overtook": bool(_overtook(log, obstacles)),
        "progress_m": float(log.progress),
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


def check_obstacles_clear(obstacles: Sequence[Obstacle], start: Sequence[float], robot_radius: float) -> None:
    """Refuse an obstacle that starts on the robot: its clearance at t = 0 to the robot's body disk of
    ``robot_radius`` [m] at ``start`` (x, y) [m] is negative (the MPCC's barrier cannot hold from the first
    step; the run would start in a collision).

    Raises:
        InvalidInputError: naming the first such obstacle (its index in the file), its clearance and how far to
            move it.
    """
    here = np.asarray(start[:2], dtype=float).reshape(1, 2)
    for j, ob in enumerate(obstacles):
        c = float(ob.clearance(here, 0.0, robot_radius)[0])
        if c < 0.0:
            x, y = np.asarray(ob.center(0.0), dtype=float)
            raise InvalidInputError(
                "--obstacles", f"obstacle {j} at ({x:.2f}, {y:.2f}) m",
                f"obstacles clear of the robot at its start ({here[0, 0]:.2f}, {here[0, 1]:.2f}) m",
                f"obstacle {j} starts on the robot: its clearance to the robot's {robot_radius:g} m body disk at t = 0 "
                f"is {c:.3f} m; move it at least {-c:.3f} m away")


def check_path_start(path: Path, com_xy: Sequence[float], yaw: float, robot: str = "the robot") -> None:
    """Refuse a full-body path that does not start where the robot stands, facing along it: its start
    within :data:`PATH_START_TOLERANCE` [m] of the standing COM (x, y) ``com_xy`` and its initial tangent
    within :data:`PATH_HEADING_TOLERANCE` [rad] of the torso heading ``yaw``. (The robot is not moved: it
    would walk towards a far start with no path under it and fall; the LIP starts on the path.)

    Raises:
        InvalidInputError: naming the path's start, the robot's and how to move the path.
    """
    p0 = np.asarray(path.position(0.0), dtype=float)
    c = np.asarray(com_xy[:2], dtype=float)
    h0 = float(path.slope(0.0))
    gap = float(np.linalg.norm(p0 - c))
    turn = abs(math.remainder(h0 - float(yaw), 2.0 * math.pi))
    if gap <= PATH_START_TOLERANCE and turn <= PATH_HEADING_TOLERANCE:
        return
    where = f"({p0[0]:.3f}, {p0[1]:.3f}) m heading {h0:.2f} rad"
    raise InvalidInputError(
        "--path", f"a path starting at {where}",
        f"a full-body path that starts where {robot} stands, ({c[0]:.3f}, {c[1]:.3f}) m facing {float(yaw):.2f} rad "
        f"(within {PATH_START_TOLERANCE:g} m and {PATH_HEADING_TOLERANCE:g} rad)",
        f"the robot is not moved to the path; shift its waypoints by ({c[0] - p0[0]:+.3f}, {c[1] - p0[1]:+.3f}) m"
        + (" and turn them to start along the robot's heading" if turn > PATH_HEADING_TOLERANCE else ""),
    )


def _default_duration(scenario: str, planner: str, path: Path | None = None) -> float:
    if scenario == "follow-path":
        return follow_path_duration(path.length if path is not None else 0.0)
    key = scenario if scenario.startswith("circle") else f"overtake-{planner}"
    return float(config.horizon(*DEFAULT_DURATION[key]))


def simulate_full_body(
    robot: RobotDescription,
    scenario: str,
    planner: str = "mpcc",
    path: Path | None = None,
    obstacles: ObstacleSpec = None,
    obstacle_speed: float | None = None,
    pushes: Sequence[Push] = (),
    duration: float | None = None,
    n_steps: int | None = None,
    record_video: bool = False,
    progress: bool = False,
    settle_time: float = FULLBODY_SETTLE_TIME,
    loop: FullBodyLoop | None = None,
    settings: PlannerSettings | None = None,
    step_duration_range: Sequence[float] | None = None,
    viewer: LiveViewer | None = None,
) -> FullBodyPathRun:
    """Run one of paper A's studies on a full-body robot.

    Args:
        robot: a :class:`~lipmpcc.robots.RobotDescription` (``load_robot("digit_like")``).
        scenario: ``"circle"``, ``"circle-push"`` or ``"overtake"`` (the weights, path and obstacle).
        planner: ``"mpcc"`` or ``"cartesian"``.
        path: reference path (world frame); None: the study's, from the standing COM along the torso.
        obstacles: obstacles, or a function of the path that makes them; None: the study's.
        obstacle_speed: speed of the study's obstacle [m/s] (None: paper A's for the planner).
        pushes: planar torso pushes (e.g. :func:`paper_a_pushes`), at absolute times or timed from a footstep's
            touch-down (``Push.step``, armed by the loop).
        duration: simulated time [s] (None with ``n_steps`` None: the study's default).
        n_steps: stop after this many touch-downs.
        record_video: record configurations for a video.
        progress: progress bar.
        settle_time: errors are judged after this time [s].
        loop: an existing :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop` whose simulator and whole-body
            controller are reused (its planner is replaced).
        settings: ``--preset`` / ``--set`` applied over the study's parameters (None: the study's).
        step_duration_range: (TMIN, TMAX) [s]: the timed MPCC re-planned at 25 Hz within each step
            (:class:`~lipmpcc.planners.sources.mpcc.TimedMpccFootstepSource`); None: paper A's fixed T.
        viewer: a :class:`~lipmpcc.studies.viewer.LiveViewer` that shows the run live (None: none).
    """
    from ..loops.base import Course
    from ..loops.fullbody.loop import FullBodyLoop, LoopParams

    _check_study(scenario, planner)
    if duration is not None and not (math.isfinite(duration) and duration > 0.0):
        raise InvalidInputError("--duration", duration, "a positive simulated time [s]")
    user_scene = scenario == "follow-path" or path is not None  # a scene of the user's, not paper A's study
    com0, yaw0 = robot.standing.com, robot.standing.torso_yaw
    H = float(com0[2]) if robot.lip_height is None else float(robot.lip_height)
    prm = fullbody_params(scenario, planner, H, min_lateral_step=robot.min_lateral_step, step_duration=robot.step_duration,
                          rectangle=robot_rectangle(robot))
    if settings is not None:
        prm = settings.apply(prm, planner)
    if path is None:
        if scenario == "follow-path":
            raise InvalidInputError("path", None, "a path for follow-path (--path FILE.csv)")
        path = study_path(scenario, com0[:2], yaw0)
    else:
        check_path_start(path, com0[:2], yaw0, robot.name)
    obs = _resolve_obstacles(obstacles, scenario, planner, path, FULLBODY_OBSTACLE_START, obstacle_speed)
    if planner == "mpcc":  # the MPCC (fixed T here, timed below); the Cartesian MPC trails with paper A's disk
        prm = body_clearance_params(prm, robot, settings)
    if step_duration_range is not None:
        prm = timed_fullbody_params(prm, robot, settings, obstacles=bool(obs))
    elif planner == "mpcc" and obs and user_scene:  # paper A's own studies keep paper A's weights
        prm = steady_heading_params(prm, settings)
    check_obstacles_clear(obs, com0[:2], prm.robot_radius)
    if duration is None and n_steps is None:
        duration = _default_duration(scenario, planner, path)
    source = _full_body_source(path, prm, obs, planner, step_duration_range)
    if step_duration_range is not None:  # the timed source's MPCC: a fixed TMIN = TMAX is its model's T
        prm = source.timed_params.mpcc  # type: ignore[attr-defined]
    source.warm_up()  # build/JIT the solvers before the timed run
    run_loop = FullBodyLoop(robot, planner=source, params=LoopParams(com_height=H),
                           sim=loop.sim if loop is not None else None, wbc=loop.wbc if loop is not None else None)
    if viewer is not None:  # the footstep-timed pushes are drawn as the loop arms them
        fixed = replay.push_windows(pushes)
        viewer.set_scene(path, obs, lambda: fixed + replay.push_windows(run_loop.armed_pushes))
    # with obstacles, the configurations are recorded (at the video's rate) for the whole body's clearance
    result = run_loop.run(duration=duration, n_steps=n_steps, pushes=pushes, course=Course(path, tuple(obs)),
                          progress=progress, record_video=record_video or bool(obs), on_tick=viewer)
    pushes = list(result.pushes)  # as applied: absolute times
    log = full_body_path_log(result, source, path, obs, pushes)
    summary = summarize_full_body(log, result, source, obs, settle_time)
    summary.update(body_clearance_summary(robot, obs, result))
    summary["footholds_clipped"] = int(source.clipped_steps)  # steps brought within the robot's reach
    summary["stopped_reason"] = (
        "fell" if result.fell else ("steps" if n_steps is not None and result.n_steps >= n_steps else "duration")
    )
    return FullBodyPathRun(log, summary, path, obs, prm, list(pushes), settle_time, result, source, run_loop)


def _full_body_source(path: Path, prm: MpccParams, obs: list[Obstacle], planner: str,
                      step_duration_range: Sequence[float] | None) -> MpccFootstepSource:
    """Paper A's MPCC source (fixed T, 15 Hz), or the timed MPCC's (25 Hz within steps) for a duration range
    (each hands the full body only footholds within the robot's reachability rectangle: their ``guard``)."""
    from ..planners.sources.mpcc import MpccFootstepSource
    from ..planners.sources.mpcc import TimedMpccFootstepSource

    if step_duration_range is None:
        return MpccFootstepSource(path, prm, obs, name=planner)
    return TimedMpccFootstepSource(path, timed_params(prm, step_duration_range), obs, name=planner)


def render_frames(run: FullBodyPathRun, times: Sequence[float] | None = None, settings: VideoSettings | None = None,
                  size: tuple[int, int] = (640, 480)) -> tuple[list[np.ndarray], np.ndarray]:
    """Frames of a full-body run recorded with ``record_video=True``, its path and obstacles drawn in
    (:func:`lipmpcc.studies.video.render_path_frames`)."""
    return video.render_path_frames(run.loop, run.result, run.path, run.obstacles, times, settings, size)


def write_video(run: FullBodyPathRun, path: str | FsPath, size: tuple[int, int] | None = None,
                every: int | None = None) -> FsPath:
    """The video of a full-body run with its path and obstacles drawn in
    (:func:`lipmpcc.studies.video.write_path_video`)."""
    return video.write_path_video(run.loop, run.result, run.path, run.obstacles, path, size, every)


# --------------------------------------------------------------------------------------------
# How a run ended along its path (the outcome: lipmpcc.studies.outcome)
# --------------------------------------------------------------------------------------------
def run_goal(scenario: str) -> str:
    """A run's goal (:data:`lipmpcc.studies.outcome.GOALS`): ``"end"`` for ``follow-path`` (it walks to the
    path's end), ``"length"`` for paper A's studies (their set number of steps or seconds, on a path longer
    than that: the circle's 1.25 turns, the 40 m line; also with ``--path``)."""
    return "end" if scenario == "follow-path" else "length"


def progress_trace(run: PathRun, goal: str = "end") -> ProgressTrace:
    """The progress of a path-following run (:class:`~lipmpcc.studies.outcome.ProgressTrace`): on the LIP the
    closest path parameter of the state at each support exchange, on a full body of the measured COM at every
    WBC tick; each obstacle's clearance to the robot's body disk (the MPCC's ``robot_radius``) at those times
    and, for one moving along the path, its path parameter."""
    if isinstance(run, LipPathRun):
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


def _run_plans(run: PathRun) -> tuple[np.ndarray, list[MpccResult]]:
    """The times [s] the run's MPCC plans were made and the plans (the LIP: one per step, the last of each
    step when re-planned within it; a full body: every solve of the source)."""
    if isinstance(run, LipPathRun):
        plans = [pl for pl in run.lip_log.plans if isinstance(pl, MpccResult)]
        return np.asarray(run.lip_log.t[: len(plans)], dtype=float), plans
    recs = [r for r in getattr(run, "source").records if r.result is not None]
    return np.array([r.t for r in recs], dtype=float), [r.result for r in recs]


def _planned_clearance(run: PathRun, t: np.ndarray) -> np.ndarray | None:
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


def _held(run: PathRun, t: np.ndarray) -> np.ndarray | None:
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


def assess_run(run: PathRun, scenario: str) -> PathAssessment:
    """How ``run`` of ``scenario`` ended along its path (:func:`~lipmpcc.studies.outcome.assess_progress` of
    :func:`progress_trace`, the goal :func:`run_goal`), its ``progress_m`` the summary's."""
    return assess_progress(progress_trace(run, run_goal(scenario)), run.summary.get("progress_m"))


# --------------------------------------------------------------------------------------------
# The study from the CLI options: one set-up, one summary, one figure choice
# --------------------------------------------------------------------------------------------
def lip_stopped_early(reason: str) -> str | None:
    """The LIP loop's ``stopped_reason`` as the summary's ``stopped_early``: None when the run took its
    steps, reached the end of the path or fell (``fell`` says so), else the reason."""
    return None if reason in ("steps", "end of path", "fell", "") else reason


def _planner_name(opts: RunOptions) -> str:
    name = opts.planner or "mpcc"
    if name not in PLANNERS:
        raise InvalidInputError("--planner", name, "'mpcc' or 'cartesian' for this scenario")
    return name


def _robot(opts: RunOptions) -> RobotDescription | None:
    """None for ``--robot lip`` (the default), else the full-body robot (``digit_like`` or ``PATH.xml``)."""
    robot = opts.robot or "lip"
    if robot == "lip":
        return None
    if robot == "digit_like" or robot.lower().endswith(".xml"):
        from ..robots import load_robot

        return load_robot(robot)
    raise InvalidInputError("--robot", robot, ROBOT_CHOICES)


def _params_summary(prm: MpccParams, rate_hz: float | None = None) -> dict[str, Any]:
    """The MPCC parameters in the summary (a full-body run, with its planner rate, adds its own)."""
    full = rate_hz is not None
    s: dict[str, Any] = {"N": prm.N, "T_s": prm.model.T, "H_m": prm.model.H, "Q_bar": prm.Q_bar, "W_bar": prm.W_bar,
                         "R": prm.R}
    if full:
        s["heading_weight"] = prm.heading_weight
    s.update({"rho": prm.rho, "v_max": prm.v_max, "delta_min": prm.delta_min, "delta_max": prm.delta_max,
              "gamma": prm.gamma, "robot_radius": prm.robot_radius})
    if full:
        s["foot_radius"] = prm.foot_radius
        s["rectangle"] = {"forward": prm.rectangle.forward, "lateral": prm.rectangle.lateral, "heading": prm.rectangle.heading}
        s["rate_hz"] = rate_hz
    return s


def _summary(scenario: str, planner: str, robot: str, run: PathRun, extra: dict[str, Any], rate_hz: float | None,
             settings: PlannerSettings | None = None) -> dict[str, Any]:
    s: dict[str, Any] = {"scenario": scenario, "planner": planner, "robot": robot}
    s.update(run.summary)
    s.update(extra)
    s["params"] = _params_summary(run.params, rate_hz)
    if run.obstacles:
        s["obstacle_speeds_mps"] = [
            float(ob.speed) if ob.path is not None else float(np.hypot(*ob.velocity)) for ob in run.obstacles
        ]
    s.update(planner_fields(scenario, planner, run.params, settings))
    return s


def planner_fields(scenario: str, planner: str, params: MpccParams, settings: PlannerSettings | None) -> dict[str, Any]:
    """The summary's ``preset`` (``--preset``, else the study's, :func:`study_preset`), ``planner_set``
    (the ``--set`` values) and ``planner_params`` (every field of the effective MPCC parameters)."""
    given = settings if settings is not None else PlannerSettings()
    return {"preset": given.preset or study_preset(scenario, planner), "planner_set": dict(given.values),
            "planner_params": params_dict(params)}


def run_events(run: PathRun, summary: dict[str, Any]) -> list[tuple[str, tuple[float, float]]]:
    """Where the run's figure marks how it ended, (label, (x, y) [m]): the stall's start (``stall``), the
    least clearance when it collided, the COM at the end when it fell or did not reach the end."""
    out: list[tuple[str, tuple[float, float]]] = []
    com = run.log.com
    if not len(com):
        return out
    stall = summary.get("stall")
    if isinstance(stall, dict):
        x, y = stall["position"]
        out.append((f"stalled from {stall['t_s']:.0f} s", (float(x), float(y))))
    if summary.get("collided") and len(run.log.clearance):
        i = int(np.argmin(run.log.clearance))
        out.append((f"collided ({run.log.tc[i]:.1f} s)", (float(com[i, 0]), float(com[i, 2]))))
    if summary.get("fell"):
        out.append(("fell", (float(com[-1, 0]), float(com[-1, 2]))))
    elif summary.get("outcome") in ("stalled", "incomplete", "stopped_early"):
        out.append((f"end of run ({summary.get('progress_m', 0.0):.1f} of {summary.get('path_length_m', 0.0):.1f} m)",
                    (float(com[-1, 0]), float(com[-1, 2]))))
    return out


def _figures(scenario: str, planner: str, robot_label: str, run: PathRun, preset: str = "",
             path_file: str | None = None, summary: dict[str, Any] | None = None) -> dict[str, Figure]:
    who = "Cartesian MPC" if planner == "cartesian" else "MPCC"
    with_obstacles = ", with obstacles" if run.obstacles else ""
    events = run_events(run, summary or {})
    ending = f" ({summary['outcome']})" if summary and summary.get("outcome") not in (None, "completed") else ""
    if scenario == "follow-path":
        title = f"Path following: {who} ({preset} preset) on {robot_label}" + with_obstacles + ending
        return {scenario: plots.figure_follow_path(run.log, run.path, run.obstacles, title, run.settle_time, events)}
    if scenario.startswith("circle"):  # paper A's study; on --path FILE it says whose path it drew
        on = f" on {FsPath(path_file).name}" if path_file else ""
        title = f"{planner.upper()} on {robot_label}, {scenario}{on}{with_obstacles}{ending}"
        return {scenario: plots.figure_circle(run.log, run.path, title, run.settle_time, run.obstacles, events)}
    return {scenario: plots.figure_overtake(run.log, run.path, run.obstacles, planner == "cartesian",
                                            title=f"{who} on {robot_label}: overtaking study{ending}", events=events)}


def _study_pushes(opts: RunOptions, scenario: str, t_end: float) -> list[Push]:
    """``circle-push``'s pushes up to ``t_end`` [s]: paper A's (seeded), their forces times
    ``opts.extra["push_scale"]`` (default 1), or ``opts.extra["pushes"]`` instead (``lipmpcc sweep``'s hook)."""
    if scenario != "circle-push":
        return []
    if opts.extra.get("pushes") is not None:
        return list(opts.extra["pushes"])
    scale = float(opts.extra.get("push_scale", 1.0))
    pushes = paper_a_pushes(t_end, opts.rng_seed)
    return pushes if scale == 1.0 else [Push(tuple(scale * f for f in p.force), p.t_start, p.duration) for p in pushes]


def _run(opts: RunOptions, scenario: str) -> RunResult:
    planner = _planner_name(opts)
    robot = _robot(opts)
    path = load_path_csv(opts.path) if opts.path else None
    obstacles = (lambda p: obstacles_from_json(opts.obstacles, p)) if opts.obstacles else None
    settings = opts.planner_settings
    preset = settings.preset or study_preset(scenario, planner)
    if robot is None:
        steps = _lip_steps(scenario, opts.steps, path)
        timed = opts.step_duration_range
        t_end = steps * (lip_params(scenario, planner).model.T if timed is None else timed[1])  # the longest run
        pushes = _study_pushes(opts, scenario, t_end)
        run: PathRun = simulate_lip(scenario, planner, path, obstacles, opts.obstacle_speed, pushes, steps, timed, settings,
                                    opts.replan_hz)
        n_pushes = len(pushes) if timed is None else int(sum(p.t_start < run.lip_log.t[-1] for p in pushes))
        extra = {"pushes": n_pushes, "step_duration_range": None if timed is None else list(timed),
                 "replan_hz": opts.replan_hz}
        summary = _summary(scenario, planner, "lip", run, extra, None, settings)
        add_outcome(summary, stopped_early=lip_stopped_early(run.lip_log.stopped_reason), path=assess_run(run, scenario))
        return RunResult(summary=summary, figures=_figures(scenario, planner, "the LIP", run, preset, opts.path, summary),
                         log=run)
    duration = opts.duration
    if duration is None and opts.steps is None:
        duration = _default_duration(scenario, planner, path)
    t_end = duration if duration is not None else 5.0 + float(opts.steps)  # the loop's own bound for --steps
    pushes = _study_pushes(opts, scenario, t_end)
    timed = opts.step_duration_range
    live = live_viewer(opts)
    try:  # the frames are always recorded: the run's replay (studies.replay)
        fb = simulate_full_body(robot, scenario, planner, path, obstacles, opts.obstacle_speed, pushes, duration,
                                opts.steps, record_video=True, progress=True, settings=settings,
                                step_duration_range=timed, viewer=live)
    finally:
        if live is not None:
            live.close()
    extra = {"seed": opts.rng_seed, "fast_mode": config.fast_mode(),
             "pushes": int(sum(p.t_start < fb.summary["duration_s"] for p in fb.pushes))}
    if timed is not None:  # new fields only with the option: the fixed-T summaries are unchanged
        extra.update(_full_body_durations(fb, timed))
    summary = _summary(scenario, planner, robot.name, fb, extra, fb.source.rate_hz, settings)
    early = None
    if opts.steps is not None and duration is None and not fb.result.fell and fb.result.n_steps < opts.steps:
        early = f"{fb.result.n_steps} of {opts.steps} steps in {fb.result.sim_time:.2f} s (the loop's time bound)"
    add_outcome(summary, stopped_early=early, result=fb.result, path=assess_run(fb, scenario))
    rep, files = replay.run_outputs(opts, robot, fb.loop.sim.model, fb.result, fb.path, fb.obstacles,
                                    replay.push_windows(fb.pushes), fb.loop.params.video_fps)
    return RunResult(summary=summary, figures=_figures(scenario, planner, robot.name, fb, preset, opts.path, summary),
                     log=fb, files=files, replay=rep)


def _full_body_durations(run: FullBodyPathRun, timed: Sequence[float]) -> dict[str, Any]:
    """The timed MPCC's summary fields on a full body: the range, the durations its plans asked for (the
    last plan of each step) and the executed ones (between touch-downs) [s]."""
    last: dict[int, float] = {}
    for rec in run.source.records:
        last[rec.step_index] = rec.duration
    t_td = np.array([td.t for td in run.result.touchdowns], dtype=float)  # duration of the first: from the start
    return {"step_duration_range": list(timed), "replan_hz": float(run.source.rate_hz),
            "planned_durations_s": lip_loop.duration_stats(np.array(list(last.values()), dtype=float)),
            "executed_durations_s": lip_loop.duration_stats(np.diff(t_td), values=True)}


def run_circle(opts: RunOptions) -> RunResult:
    """Paper A Fig. 5(a, b): follow a circle of radius 2 m."""
    return _run(opts, "circle")


def run_circle_push(opts: RunOptions) -> RunResult:
    """Paper A Fig. 5(c, d): the circle under random pushes (seeded by ``--seed``)."""
    return _run(opts, "circle-push")


def run_overtake(opts: RunOptions) -> RunResult:
    """Paper A Fig. 6: a moving obstacle on a straight path; the MPCC overtakes, the Cartesian MPC trails."""
    return _run(opts, "overtake")


def run_follow_path(opts: RunOptions) -> RunResult:
    """Follow the path of ``--path`` (with ``--obstacles``, if any) with the contouring-accurate weights."""
    return _run(opts, "follow-path")
