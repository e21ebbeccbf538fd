"""Full-body studies without an MPC: ``lipmpcc run walk|stand --robot digit_like`` (or ``PATH.xml``).

- ``walk``: the capture-point footstep source (:mod:`lipmpcc.planners.capture_point`) tracks a commanded
  speed (``--speed``, default 0.6 m/s) and yaw rate (``--yaw-rate``, default 0; v/R walks a circle of
  radius R) through the full-body loop (:mod:`lipmpcc.loops.fullbody.loop`): MuJoCo at 2 kHz, the C++
  whole-body QP at 400 Hz. Runs for ``--steps`` touch-downs or ``--duration`` seconds (default 20 s,
  6 s in fast mode).
- ``stand``: double support for ``--duration`` seconds (default 5 s) with four 50 N, 0.1 s pushes on
  the torso, from the front, back, left and right, evenly spaced (at 1, 2, 3, 4 s for 5 s).

Both runs are deterministic: they take no ``--seed`` (the summary records the default, 0). ``--video``
renders the run to ``OUT/SCENARIO.mp4`` (``.gif`` when imageio-ffmpeg is not installed).

Every summary has the planner studies' fields (scenario, planner, robot, steps, fell, solver_failures)
and the full-body ones: ``wbc_ms`` {median, p90, max}, ``qp_failures``, ``real_time_factor`` (simulated
seconds per wall second), ``min_base_height_m``, ``distance_walked_m``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import config
from ..exceptions import InvalidInputError
from ..push import Push
from . import replay
from .viewer import live_viewer
from .options import RunOptions, RunResult
from .outcome import add_outcome

if TYPE_CHECKING:  # pragma: no cover
    from ..loops.fullbody.loop import FullBodyLoop, LoopResult
    from ..planners.capture_point import CapturePointParams
    from ..robots import RobotDescription

__all__ = ["PLANNER", "DEFAULT_ROBOT", "DEFAULT_SPEED", "stand_pushes", "capture_point_params", "run_stand", "run_walk"]

PLANNER = "capture-point"
DEFAULT_ROBOT = "digit_like"
DEFAULT_SPEED = 0.6  # [m/s]
STAND_PUSH_N = 50.0  # [N]
STAND_PUSH_S = 0.1  # [s]


def _robot(opts: RunOptions) -> RobotDescription:
    from ..robots import load_robot

    name = opts.robot or DEFAULT_ROBOT
    if name in ("lip", "alip"):
        raise InvalidInputError("--robot", name, "a full-body robot: digit_like or a PATH.xml", f"{opts.scenario} needs one")
    return load_robot(name)


def _check_planner(opts: RunOptions) -> None:
    if opts.planner not in (None, PLANNER):
        raise InvalidInputError("--planner", opts.planner, f"{PLANNER!r} (the only footstep source of {opts.scenario})")


def _common_summary(opts: RunOptions, robot: RobotDescription, result: LoopResult) -> dict[str, Any]:
    s: dict[str, Any] = {
        "scenario": opts.scenario,
        "planner": PLANNER if opts.scenario == "walk" else None,
        "robot": robot.name,
        "steps": result.n_steps,
        "fell": result.fell,
        "solver_failures": 0,
        "seed": opts.rng_seed,
        "fast_mode": config.fast_mode(),
    }
    s.update(result.summary())
    return s


def stand_pushes(t_first: float = 1.0, spacing: float = 1.0, scale: float = 1.0) -> list[Push]:
    """The four 50 N, 0.1 s torso pushes of the stand study: +x, −x, +y, −y, one per ``spacing`` [s] from
    ``t_first`` [s] (the full-body loop takes them as they are); ``scale``: factor of the force (the robot's
    :attr:`~lipmpcc.robots.RobotDescription.push_scale`: 1 on Digit-sized robots)."""
    dirs = [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)]
    f = STAND_PUSH_N * float(scale)
    return [
        Push(force=(f * dx, f * dy, 0.0), t_start=t_first + i * spacing, duration=STAND_PUSH_S)
        for i, (dx, dy) in enumerate(dirs)
    ]


def capture_point_params(robot: RobotDescription) -> "CapturePointParams":
    """The capture-point walker's parameters on ``robot``: its defaults (Digit's: 0.26 m step width, 0.55 m
    reach, 0.4 s steps) unless the robot's layout states ``step_width`` and ``max_step_length``; then the
    width bounds scale with the step width, the forward/backward reach with the reach, and the step
    duration (and its adaptation range) is the layout's ``step_duration``."""
    from ..planners.capture_point import CapturePointParams

    base = CapturePointParams()
    if robot.step_width is None or robot.max_step_length is None:
        return base
    w, L = robot.step_width / base.step_width, robot.max_step_length / base.max_step_forward
    T = robot.step_duration / base.step_duration
    return CapturePointParams(
        step_duration=robot.step_duration, step_width=robot.step_width, max_step_forward=robot.max_step_length,
        max_step_backward=base.max_step_backward * L, min_step_width=base.min_step_width * w,
        max_step_width=base.max_step_width * w, min_duration=base.min_duration * T, max_duration=base.max_duration * T,
    )


def run_stand(opts: RunOptions) -> RunResult:
    """Stand in double support under four 50 N, 0.1 s pushes (front, back, left, right)."""
    from ..plots import walking as plots
    from ..loops.fullbody.loop import FullBodyLoop

    _check_planner(opts)
    robot = _robot(opts)
    duration = float(opts.duration) if opts.duration is not None else 5.0
    if not (math.isfinite(duration) and duration > 0.0):
        raise InvalidInputError("--duration", opts.duration, "a positive simulated time [s]")
    spacing = duration / 5.0
    pushes = stand_pushes(t_first=spacing, spacing=spacing, scale=robot.push_scale)
    loop = FullBodyLoop(robot, planner=None)
    result = _run_loop(opts, loop, pushes, duration=duration)
    summary = _common_summary(opts, robot, result)
    summary["planner"] = None
    c = result.log.com[:, :2]
    summary["max_com_excursion_m"] = float(np.max(np.linalg.norm(c - c[0], axis=1)))
    summary["pushes"] = [{"t_start": p.t_start, "force_n": list(p.force), "duration_s": p.duration} for p in pushes]
    figures = {
        "stand": plots.stand_view(result, pushes),
        "stand_tracking": plots.tracking(result, pushes),
        "wbc_timing": plots.timing(result),
    }
    add_outcome(summary, result=result)
    rep, files = replay.run_outputs(opts, robot, loop.sim.model, result, pushes=replay.push_windows(pushes),
                                    fps=loop.params.video_fps)
    return RunResult(summary=summary, figures=figures, log=result, files=files, replay=rep)


def _run_loop(opts: RunOptions, loop: FullBodyLoop, pushes: list[Push], **bounds: Any) -> LoopResult:
    """``loop.run`` with the frames recorded (the run's replay), shown live with ``--viewer``."""
    live = live_viewer(opts)
    if live is not None:
        live.set_scene(pushes=replay.push_windows(pushes))
    try:
        return loop.run(pushes=pushes, progress=True, record_video=True, on_tick=live, **bounds)
    finally:
        if live is not None:
            live.close()


def run_walk(opts: RunOptions) -> RunResult:
    """Walk with the capture-point footstep source at a commanded speed and yaw rate."""
    from ..planners.capture_point import CapturePointPlanner
    from ..plots import walking as plots
    from ..loops.fullbody.loop import FullBodyLoop

    _check_planner(opts)
    robot = _robot(opts)
    speed = DEFAULT_SPEED if opts.speed is None else float(opts.speed)
    yaw_rate = 0.0 if opts.yaw_rate is None else float(opts.yaw_rate)
    params = capture_point_params(robot)
    planner = CapturePointPlanner(params, speed=speed, yaw_rate=yaw_rate)
    duration = opts.duration
    if duration is not None and not (math.isfinite(duration) and duration > 0.0):
        raise InvalidInputError("--duration", duration, "a positive simulated time [s]")
    if opts.steps is None and duration is None:
        duration = float(config.horizon(20.0, 6.0))
    loop = FullBodyLoop(robot, planner=planner)
    result = _run_loop(opts, loop, [], duration=duration, n_steps=opts.steps)
    summary = _common_summary(opts, robot, result)
    log = result.log
    t_walk = log.t[-1] - log.t[0] if log.t.size > 1 else float("nan")
    summary.update(
        {
            "speed_cmd_mps": speed,
            "yaw_rate_cmd_radps": yaw_rate,
            "mean_speed_mps": result.distance_walked / t_walk if t_walk > 0 else float("nan"),
            "heading_change_rad": float(np.unwrap(log.torso_yaw)[-1] - log.torso_yaw[0]) if log.t.size else 0.0,
            "step_duration_s": params.step_duration,
            "foothold_error_m": {
                "rms": float(np.sqrt(np.mean([np.sum((td.pos[:2] - td.planned) ** 2) for td in result.touchdowns])))
                if result.touchdowns
                else float("nan"),
            },
        }
    )
    figures = {
        "walk_top": plots.top_view(result, title=f"walk: v = {speed} m/s, yaw rate = {yaw_rate} rad/s"),
        "walk_tracking": plots.tracking(result),
        "wbc_timing": plots.timing(result),
    }
    early = None
    if opts.steps is not None and not result.fell and result.n_steps < opts.steps and (
            duration is None or result.sim_time < float(duration) - 1e-6):
        early = f"{result.n_steps} of {opts.steps} steps in {result.sim_time:.2f} s (the loop's time bound)"
    add_outcome(summary, stopped_early=early, result=result)
    rep, files = replay.run_outputs(opts, robot, loop.sim.model, result, fps=loop.params.video_fps)
    return RunResult(summary=summary, figures=figures, log=result, files=files, replay=rep)
