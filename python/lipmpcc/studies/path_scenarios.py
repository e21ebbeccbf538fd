"""Paper A's scenarios (``circle``, ``circle-push``, ``overtake``, ``follow-path``): the paths, the obstacles, the
pushes, the presets and the run lengths of :mod:`lipmpcc.studies.path_following`, on the LIP and on a full body, and
the checks of a user's path and obstacles against the robot's start.
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np

from .. import config
from ..exceptions import InvalidInputError
from ..loops import lip as lip_loop
from ..obstacles import Obstacle
from ..paths import ArcPath, LinePath, Path
from ..planners.mpcc import MpccParams
from ..push import Push

__all__ = [
    "SCENARIOS", "PLANNERS", "ROBOT_CHOICES", "CIRCLE_RADIUS", "CIRCLE_TURNS", "LINE_LENGTH", "OBSTACLE_RADIUS",
    "PAPER_SPEED", "SETTLE_TIME", "OBSTACLE_START", "LIP_STEPS", "FULLBODY_SETTLE_TIME",
    "FULLBODY_OBSTACLE_START", "STEP_DURATION", "PATH_START_TOLERANCE", "PATH_HEADING_TOLERANCE",
    "DEFAULT_DURATION", "FOLLOW_PATH_M_PER_STEP", "FOLLOW_PATH_EXTRA_STEPS", "FOLLOW_PATH_SPEED",
    "FOLLOW_PATH_EXTRA_TIME", "FOLLOW_PATH_MAX_STEPS", "FOLLOW_PATH_MAX_DURATION", "ObstacleSpec", "circle_path",
    "line_path", "study_path", "study_line_length", "study_obstacles", "paper_a_pushes", "study_preset", "lip_params",
    "follow_path_steps", "follow_path_duration", "check_obstacles_clear", "check_path_start", "run_goal",
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


def study_path(scenario: str, start: Sequence[float] = (0.0, 0.0), heading: float = 0.0,
               length: float = LINE_LENGTH) -> Path:
    """The study's path from the robot's start (x, y) [m] and heading [rad]: the circle or the line of
    ``length`` [m] (:func:`study_line_length`)."""
    return circle_path(start, heading) if scenario.startswith("circle") else line_path(start, heading, length)


def study_line_length(v_max: float, step_time: float, reach: float, duration: float | None = None,
                      n_steps: int | None = None) -> float:
    """The length [m] of the study's line for a run of ``duration`` [s] or ``n_steps`` steps: :data:`LINE_LENGTH`,
    or longer when the run could reach its end: the most the MPCC can progress, ``v_max`` [m] per step of at least
    ``step_time`` [s] (the shortest step), plus its plan's ``reach`` [m] (N v_max). Paper A's line studies run on a
    path longer than the run (:func:`run_goal`), so that how the robot stops at a path's end is not part of them:
    the timed MPCC's 0.8 m/s overtaking on ``digit_like`` covers 0.93 m/s, and in a 60 s run it reached the 40 m
    line's end at 44 s, with the obstacle coming up behind it to stop on the same end."""
    if n_steps:
        most = n_steps * v_max
    elif duration is not None:
        most = duration / step_time * v_max
    else:
        return LINE_LENGTH
    return max(LINE_LENGTH, float(most + reach))


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


def _lip_steps(scenario: str, n_steps: int | None, path: Path | None = None) -> int:
    if n_steps:
        return n_steps
    if scenario == "follow-path":
        return follow_path_steps(path.length if path is not None else 0.0)
    return int(config.horizon(*LIP_STEPS[scenario]))


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


def run_goal(scenario: str) -> str:
    """A run's goal (:data:`lipmpcc.studies.outcome.GOALS`): ``"end"`` for ``follow-path`` (it walks to the
    path's end), ``"length"`` for paper A's studies (their set number of steps or seconds, on a path longer
    than that: the circle's 1.25 turns, the 40 m line; also with ``--path``)."""
    return "end" if scenario == "follow-path" else "length"
