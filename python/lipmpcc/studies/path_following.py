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

The study's parts live in modules named for them: the scenarios (paths, obstacles, pushes, presets, run
lengths, start checks: :mod:`lipmpcc.studies.path_scenarios`), the MPCC's parameters on a full body
(:mod:`lipmpcc.studies.path_params`) and paper A's metrics, once for both robots
(:mod:`lipmpcc.studies.path_metrics`). Their names, read from this module, still work with a
DeprecationWarning until lipmpcc 0.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from .. import config
from .._deprecated import moved_names
from ..exceptions import InvalidInputError
from ..loops import lip as lip_loop
from ..obstacles import Obstacle, obstacles_from_json
from ..paths import Path, load_path_csv
from ..planners.mpcc import MpccParams, MpccPlanner
from ..planners.mpcc_timed import TimedMpccPlanner
from ..planners.presets import PlannerSettings, params_dict
from ..plots import path_following as plots
from ..plots.logs import PathFollowingLog
from ..push import Push
from . import path_metrics, path_params, path_scenarios, replay, video
from .viewer import LiveViewer, live_viewer
from .options import RunOptions, RunResult
from .outcome import add_outcome
from .path_scenarios import (
    SCENARIOS, PLANNERS, ROBOT_CHOICES, CIRCLE_RADIUS, CIRCLE_TURNS, LINE_LENGTH, OBSTACLE_RADIUS, PAPER_SPEED,
    SETTLE_TIME, OBSTACLE_START, LIP_STEPS, FULLBODY_SETTLE_TIME, FULLBODY_OBSTACLE_START, STEP_DURATION,
    PATH_START_TOLERANCE, PATH_HEADING_TOLERANCE, DEFAULT_DURATION, FOLLOW_PATH_M_PER_STEP,
    FOLLOW_PATH_EXTRA_STEPS, FOLLOW_PATH_SPEED, FOLLOW_PATH_EXTRA_TIME, FOLLOW_PATH_MAX_STEPS,
    FOLLOW_PATH_MAX_DURATION, ObstacleSpec, _check_study, circle_path, line_path, study_path, study_obstacles,
    _resolve_obstacles, paper_a_pushes, study_preset, study_line_length, lip_params, follow_path_steps, follow_path_duration,
    _initial_state, _lip_steps, check_obstacles_clear, check_path_start, _default_duration, run_goal,
)
from .path_params import (
    FULLBODY_RECTANGLE, FULLBODY_OBSTACLE_MARGIN, FULLBODY_CARTESIAN_HEADING_WEIGHT, FULLBODY_TIMED_HEADING_RATIO,
    FULLBODY_TIMED_TURN_WEIGHT, robot_rectangle, robot_step_scale, robot_sized, fullbody_params, timed_fullbody_params,
    steady_heading_params, body_clearance_params, timed_params, timed_lip_planner,
)
from .path_metrics import (
    lip_path_log, full_body_path_log, push_recovery_times, paper_a_fields, summarize_lip, summarize_full_body,
    body_clearance_summary, progress_trace, assess_run,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ..loops.fullbody.loop import FullBodyLoop, LoopResult
    from ..planners.sources.mpcc import MpccFootstepSource
    from ..robots import RobotDescription
    from ..sim.render import VideoSettings

__all__ = [
    "PLANNERS", "PathFollowingLog", "PathRun", "LipPathRun", "FullBodyPathRun", "simulate_lip", "lip_stopped_early",
    "standing_state", "simulate_full_body", "render_frames", "write_video", "run_circle", "run_circle_push",
    "run_overtake", "run_follow_path", "planner_fields", "run_events",
]

# the names that moved to their own modules: read from here, they warn (removed in lipmpcc 0.3)
moved_names(__name__, {n: m.__name__ for m in (path_scenarios, path_params, path_metrics) for n in m.__all__
                        if n != "PLANNERS"})  # every study module names its planners (lipmpcc sweep reads them)


# --------------------------------------------------------------------------------------------
# A run, on either robot
# --------------------------------------------------------------------------------------------
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
    prm = lip_params(scenario, planner)
    if settings is not None:
        prm = settings.apply(prm, planner)
    if path is None:
        if scenario == "follow-path":
            raise InvalidInputError("path", None, "a path for follow-path (--path FILE.csv)")
        path = study_path(scenario, length=study_line_length(prm.v_max, prm.model.T, prm.N * prm.v_max,
                                                             n_steps=_lip_steps(scenario, n_steps)))
    obs = _resolve_obstacles(obstacles, scenario, planner, path, OBSTACLE_START, obstacle_speed)
    check_obstacles_clear(obs, path.position(0.0), prm.robot_radius)
    steps = _lip_steps(scenario, n_steps, path)
    if step_duration_range is None:
        log = lip_loop.simulate(MpccPlanner(path, prm), _initial_state(path), steps, obs, list(pushes))
    else:
        timed = timed_lip_planner(path, prm, step_duration_range, within_step=replan_hz is not None)
        prm = timed.params.mpcc  # a fixed TMIN = TMAX is its model's T
        log = _run_lip_timed(timed, _initial_state(path), steps, obs, list(pushes), replan_hz)
    summary = summarize_lip(log, obs, settle_time=SETTLE_TIME)
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


def standing_state(loop: FullBodyLoop) -> tuple[np.ndarray, float]:
    """The robot's standing COM (3,) [m] and torso yaw [rad] (resets the loop's simulator)."""
    sim = loop.sim
    sim.reset(loop.robot.standing_reset)  # keyframe or standing qpos (Digit v3 has no keyframe)
    com = np.asarray(sim.com(), dtype=float)
    R = np.asarray(sim.torso_pose().rotation, dtype=float)
    return com, math.atan2(R[1, 0], R[0, 0])


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
    prm = prm.with_(v_max=prm.v_max * robot_step_scale(robot))  # paper A's progress per 0.4 s step as a speed
    if settings is not None:
        prm = settings.apply(prm, planner)
    if path is None:
        if scenario == "follow-path":
            raise InvalidInputError("path", None, "a path for follow-path (--path FILE.csv)")
        t_run = duration if duration is not None or n_steps else _default_duration(scenario, planner)
        t_min = prm.model.T if step_duration_range is None else min(float(step_duration_range[0]), prm.model.T)
        path = study_path(scenario, com0[:2], yaw0,
                          study_line_length(prm.v_max, t_min, prm.N * prm.v_max, t_run, n_steps))
    else:
        check_path_start(path, com0[:2], yaw0, robot.name)
    obs = _resolve_obstacles(obstacles, scenario, planner, path, FULLBODY_OBSTACLE_START, obstacle_speed)
    # the whole-body disk for both planners (fixed T here, timed below): the Cartesian MPC trails the obstacle at the
    # distance that keeps the swept body clear (with the default 0.2 m disk Digit v3's elbow met the obstacle)
    prm = body_clearance_params(prm, robot, settings)
    if step_duration_range is not None:
        prm = timed_fullbody_params(prm, robot, settings, obstacles=bool(obs))
    elif planner == "mpcc" and ((obs and (user_scene or robot_sized(robot))) or robot.steady_heading):  # else paper A's
        prm = steady_heading_params(prm, settings)
    check_obstacles_clear(obs, com0[:2], prm.robot_radius)
    if duration is None and n_steps is None:
        duration = _default_duration(scenario, planner, path)
    source = _full_body_source(path, prm, obs, planner, step_duration_range)
    if step_duration_range is not None:  # the timed source's MPCC: a fixed TMIN = TMAX is its model's T
        prm = source.timed_params.mpcc  # type: ignore[attr-defined]
    source.warm_up()  # build/JIT the solvers before the timed run
    # the layout's landing depth (0 without one): a T1 foot that lags its reference is on the ground at the planned time
    run_loop = FullBodyLoop(robot, planner=source, params=LoopParams(com_height=H, landing_depth=robot.landing_depth),
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
