"""Paper A's studies on the 3D-LIP: ``circle``, ``circle-push`` and ``overtake``.

Defaults (documented in the README and notebook 03):

- circle: a counter-clockwise circle of radius 2 m starting at the origin heading +x; the
  robot starts at rest on it; 120 steps (48 s, a full lap with the paper's weights); errors
  judged after 2 s.
- circle-push: the same with paper A's random pushes, seeded by ``--seed``.
- overtake: a 40 m straight line; a cylinder of radius 0.25 m starts 1.5 m ahead and moves
  along the line at ``--obstacle-speed`` (0.6 m/s for the MPCC, 0.1 m/s for the Cartesian MPC,
  as in the paper); 70 steps (28 s).

``--planner mpcc`` uses the paper's MPCC weights for the scenario, ``--planner cartesian`` the
paper's Cartesian weights Q = W = 200 I, ρ = 50 (the same planner with Q̄ = αI).

``--robot lip`` (the default) runs the reduced model; ``--robot digit_like`` or ``--robot PATH.xml`` runs
the same study on the full-body robot (:mod:`lipmpcc.scenarios.fullbody_path_following`), with the same
summary fields plus the full-body ones.
"""

from __future__ import annotations

import numpy as np

from ..config import horizon
from ..exceptions import InvalidInputError
from ..obstacles import Obstacle, obstacles_from_json
from ..paths import ArcPath, LinePath, Path, load_path_csv
from ..planners.mpcc import MpccParams, MpccPlanner
from ..plots import path_following as plots
from ..loops import lip as lip_loop
from . import RunOptions, RunResult

CIRCLE_RADIUS = 2.0  # [m]
SETTLE_TIME = 2.0  # [s] start-up transient excluded from the error metrics
OBSTACLE_RADIUS = 0.25  # [m] paper A
OBSTACLE_START = 1.5  # [m] ahead of the robot along the path
PAPER_SPEED = {"mpcc": 0.6, "cartesian": 0.1}  # [m/s] paper A §IV-B


def _planner_name(opts: RunOptions) -> str:
    name = opts.planner or "mpcc"
    if name not in ("mpcc", "cartesian"):
        raise InvalidInputError("--planner", name, "'mpcc' or 'cartesian' for this scenario")
    return name


ROBOT_CHOICES = "'lip' (the reduced model, default), 'digit_like' or the path of a robot MJCF (.xml)"


def _check_robot(opts: RunOptions) -> str:
    robot = opts.robot or "lip"
    if robot != "lip":
        raise InvalidInputError("--robot", robot, ROBOT_CHOICES)
    return robot


def _full_body(opts: RunOptions) -> bool:
    """True when ``--robot`` names a full-body robot (``digit_like`` or ``PATH.xml``)."""
    robot = opts.robot or "lip"
    if robot == "lip":
        return False
    if robot == "digit_like" or robot.lower().endswith(".xml"):
        return True
    raise InvalidInputError("--robot", robot, ROBOT_CHOICES)


def _params(scenario: str, planner: str) -> MpccParams:
    if planner == "cartesian":
        return MpccParams.overtake_cartesian()
    return MpccParams.circle() if scenario.startswith("circle") else MpccParams.overtake_mpcc()


def _initial_state(path: Path) -> np.ndarray:
    p0 = path.position(0.0)
    return np.array([p0[0], 0.0, p0[1], 0.0, path.slope(0.0)])


def _common(opts: RunOptions, scenario: str, default_path: Path, default_obstacles, default_steps: tuple[int, int], pushes_fn=None) -> RunResult:
    planner_name = _planner_name(opts)
    if _full_body(opts):
        from . import fullbody_path_following

        return fullbody_path_following.run(opts, scenario, planner_name, pushes_fn)
    robot = _check_robot(opts)
    path = load_path_csv(opts.path) if opts.path else default_path
    obstacles = obstacles_from_json(opts.obstacles, path) if opts.obstacles else default_obstacles(path)
    steps = opts.steps or int(horizon(*default_steps))
    prm = _params(scenario, planner_name)
    planner = MpccPlanner(path, prm)
    pushes = pushes_fn(steps * prm.model.T) if pushes_fn else []
    log = lip_loop.simulate(planner, _initial_state(path), steps, obstacles, pushes)
    summary = {"scenario": scenario, "planner": planner_name, "robot": robot}
    summary.update(lip_loop.summarize(log, obstacles, settle_time=SETTLE_TIME))
    summary["pushes"] = len(pushes)
    summary["params"] = {
        "N": prm.N, "T_s": prm.model.T, "H_m": prm.model.H, "Q_bar": prm.Q_bar, "W_bar": prm.W_bar,
        "R": prm.R, "rho": prm.rho, "v_max": prm.v_max, "delta_min": prm.delta_min, "delta_max": prm.delta_max,
        "gamma": prm.gamma, "robot_radius": prm.robot_radius,
    }
    if obstacles:
        summary["obstacle_speeds_mps"] = [float(ob.speed) if ob.path is not None else float(np.hypot(*ob.velocity)) for ob in obstacles]
    figs = {}
    if scenario.startswith("circle"):
        figs[scenario] = plots.figure_circle(log, path, f"{planner_name.upper()} on the LIP, {scenario}")
    else:
        figs[scenario] = plots.figure_overtake(log, path, obstacles, planner_name == "cartesian")
    return RunResult(summary=summary, figures=figs, log=log)


def _circle_path() -> Path:
    return ArcPath.circle(CIRCLE_RADIUS, start=(0.0, 0.0), heading=0.0, turns=1.25)


def run_circle(opts: RunOptions) -> RunResult:
    """Paper A Fig. 5(a, b): follow a circle of radius 2 m."""
    return _common(opts, "circle", _circle_path(), lambda p: [], (120, 40))


def run_circle_push(opts: RunOptions) -> RunResult:
    """Paper A Fig. 5(c, d): the circle under random pushes (seeded by ``--seed``)."""
    rng = np.random.default_rng(opts.seed)
    return _common(
        opts, "circle-push", _circle_path(), lambda p: [], (120, 40),
        pushes_fn=lambda t_end: lip_loop.random_pushes(t_end, rng),
    )


def run_overtake(opts: RunOptions) -> RunResult:
    """Paper A Fig. 6: a moving obstacle on a straight path; MPCC overtakes, Cartesian trails."""
    planner = _planner_name(opts)
    speed = opts.obstacle_speed if opts.obstacle_speed is not None else PAPER_SPEED[planner]

    def obstacles(path: Path) -> list[Obstacle]:
        return [Obstacle.circle(OBSTACLE_RADIUS, path=path, s0=min(OBSTACLE_START, path.length), speed=speed)]

    return _common(opts, "overtake", LinePath((0.0, 0.0), (40.0, 0.0)), obstacles, (70, 60))
