"""Paper A's MPCC on a full body: the reachability from the robot's layout, the presets with the loop's COM height,
the whole-body disk, and the timed MPCC's parameters (:mod:`lipmpcc.studies.path_following`).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Sequence

from ..exceptions import InvalidInputError
from ..models.lip3d import Lip3dModel, ReachabilityRectangle
from ..paths import Path
from ..planners.mpcc import MpccParams
from ..planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner
from ..planners.presets import PlannerSettings
from .options import check_step_duration_range
from .path_scenarios import STEP_DURATION, study_preset

if TYPE_CHECKING:  # pragma: no cover
    from ..robots import RobotDescription

__all__ = [
    "FULLBODY_RECTANGLE", "FULLBODY_OBSTACLE_MARGIN", "FULLBODY_CARTESIAN_HEADING_WEIGHT",
    "FULLBODY_TIMED_HEADING_RATIO", "FULLBODY_TIMED_TURN_WEIGHT", "robot_rectangle", "robot_step_scale", "robot_sized",
    "fullbody_params",
    "timed_fullbody_params", "steady_heading_params", "body_clearance_params", "timed_params", "timed_lip_planner",
]


FULLBODY_RECTANGLE = ReachabilityRectangle(forward=(-0.35, 0.35), lateral=(0.10, 0.40), heading=(-0.3, 0.3))
FULLBODY_OBSTACLE_MARGIN = 0.10  # [m] barrier margin (0.05 on the LIP): the body sways between the steps
FULLBODY_CARTESIAN_HEADING_WEIGHT = 20.0  # the Cartesian MPC's weight on the heading error to the path
# the timed MPCC's heading weight on a full body per unit of its largest running tracking weight max(Q̄), twice the
# Cartesian MPC's ratio (20 against Q = 200), and its least weight on the heading change u^θ [1/rad²], ten times
# paper A's R_θ = 5; see timed_fullbody_params
FULLBODY_TIMED_HEADING_RATIO = 2.0 * FULLBODY_CARTESIAN_HEADING_WEIGHT / 200.0
FULLBODY_TIMED_TURN_WEIGHT = 50.0


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


def robot_rectangle(robot: RobotDescription) -> ReachabilityRectangle:
    """The MPCC's reachability on ``robot``: :data:`FULLBODY_RECTANGLE` (Digit's) unless the robot's layout
    states ``max_step_length`` and ``step_width``; then the forward range scales with the reach (Digit:
    0.55 m), the lateral upper bound with the step width (Digit: 0.26 m) and the heading change per step with
    the step duration (:func:`robot_step_scale`)."""
    if not robot_sized(robot):
        return FULLBODY_RECTANGLE
    r = FULLBODY_RECTANGLE
    fwd, lat, turn = robot.max_step_length / 0.55, robot.step_width / 0.26, robot_step_scale(robot)
    return ReachabilityRectangle(forward=(r.forward[0] * fwd, r.forward[1] * fwd), lateral=(r.lateral[0], r.lateral[1] * lat),
                                 heading=(r.heading[0] * turn, r.heading[1] * turn))


def robot_step_scale(robot: RobotDescription) -> float:
    """The factor on the MPCC's per-step bounds on ``robot`` (its progress ``v_max`` [m] and heading change
    [rad] per step): 1 unless the layout states the robot's sizes (``max_step_length`` and ``step_width``, as
    ``lipmpcc robot init`` writes them; Digit's layouts do not); then ``step_duration`` / 0.4 s, so that paper
    A's bounds for Digit's 0.4 s step (0.3 m and ±0.3 rad) hold as a speed (0.75 m/s) and a turn rate
    (0.75 rad/s). Booster T1 (0.303 s steps, 0.76) was asked 1.0 m/s of progress in the overtake and fell
    (docs/add_a_robot.md, Appendix B)."""
    if not robot_sized(robot):
        return 1.0
    return float(robot.step_duration) / STEP_DURATION


def robot_sized(robot: RobotDescription) -> bool:
    """True when ``robot``'s layout states its sizes (``max_step_length`` and ``step_width``, as ``lipmpcc robot
    init`` writes them): paper A's MPCC then gets the robot's reach (:func:`robot_rectangle`), per-step bounds
    (:func:`robot_step_scale`) and, on paper A's scenes with obstacles (``overtake``), the steady heading every
    robot gets on a user's scene with obstacles (:func:`steady_heading_params`). Digit's layouts state none:
    paper A's own parameters."""
    return robot.max_step_length is not None and robot.step_width is not None


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

    The Cartesian MPC on a robot whose ``min_lateral_step`` is above the rectangle's own lower bound (Digit v3:
    0.16 m against 0.10 m) keeps the rectangle's bound and steps about ``min_lateral_step`` through its cost
    instead (``lateral_nominal``, :class:`~lipmpcc.planners.mpcc.MpccParams`): on the bound every step sat at
    0.16 m, a correction cost first order (a dead band) and only every other step could make it, and Digit v3's
    trailing run missed its 0.06 m Cartesian error (0.08-0.17 m; with this 0.012-0.045 m, docs/design.md).

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
    nominal = 0.0  # the Cartesian MPC's lateral_nominal (0: paper A's ‖u‖²_R)
    if min_lateral_step is not None:
        if not (math.isfinite(min_lateral_step) and 0.0 <= min_lateral_step < rect.lateral[1]):
            raise InvalidInputError("min_lateral_step", min_lateral_step, f"a lateral offset in [0, {rect.lateral[1]}) [m]")
        if planner == "cartesian" and min_lateral_step > rect.lateral[0]:
            nominal = float(min_lateral_step)  # stepped about through the cost, the rectangle's bound kept
        else:
            rect = ReachabilityRectangle(forward=rect.forward, lateral=(float(min_lateral_step), rect.lateral[1]),
                                         heading=rect.heading)
    kw = {"model": Lip3dModel(T=float(T), H=float(com_height)), "rectangle": rect,
          "obstacle_margin": FULLBODY_OBSTACLE_MARGIN}
    if planner == "cartesian":
        return MpccParams.overtake_cartesian(heading_weight=FULLBODY_CARTESIAN_HEADING_WEIGHT, lateral_nominal=nominal, **kw)
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
    - ``robot_radius``: the whole-body disk of :func:`body_clearance_params`, for any planner
      (:func:`simulate_full_body` has already applied it, and again it changes nothing).

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

    Fixed T on a full body gets them on a user's scene with obstacles
    (:func:`~lipmpcc.studies.path_following.simulate_full_body`): with paper A's near-free heading, on issue 31's
    random scenes on ``digit_like`` the planned heading change sat at its ±0.3 rad bound and flipped sign between
    the re-plans of one swing (seed 9), and in the detour the robot turned round to face backwards (seed 1,
    heading from −0.1 to ±π in 9 steps), then fell."""
    given = set(settings.values) if settings is not None else set()
    kw: dict[str, Any] = {}
    if "heading_weight" not in given:
        kw["heading_weight"] = max(prm.heading_weight, FULLBODY_TIMED_HEADING_RATIO * float(max(prm.Q_bar)))
    if "r_theta" not in given:
        kw["R"] = (prm.R[0], prm.R[1], max(float(prm.R[2]), FULLBODY_TIMED_TURN_WEIGHT))
    return prm.with_(**kw)


def body_clearance_params(prm: MpccParams, robot: RobotDescription, settings: PlannerSettings | None = None) -> MpccParams:
    """The MPCC's body disk on a full body (fixed T and timed, the MPCC and the Cartesian MPC; applied by
    :func:`simulate_full_body`): ``robot_radius`` at least the radius of what
    the robot's geometry covers about its COM during a step (:func:`~lipmpcc.studies.clearance.swept_body`
    with the legs swept by half the largest COM distance per step, ``delta_max`` / 2), unless ``--set``
    gives ``robot_radius``.

    The default 0.2 m disk (this library's: paper A's barrier (17) keeps the COM outside the obstacle's own
    radius, with no robot radius) holds the torso, not the arms and legs: on ``digit_like`` the 0.6 m/s obstacle
    caught the trailing right thigh from behind (6.7 cm deep) while the COM disk kept 0.098 m. The swept
    disk is ``digit_like``'s 0.432 m (its right thigh swept back; standing, its forearms reach 0.415 m),
    Digit v3's 0.531 m (its elbows). The MPCC's barriers (COM disk grown by ``robot_radius`` +
    ``obstacle_margin``, footholds by ``foot_radius`` + ``obstacle_margin``) are unchanged in form.

    The Cartesian MPC trails the obstacle at the distance this disk sets: with the default 0.2 m disk Digit v3
    trailed 0.52 m behind the obstacle's centre and its right elbow, swung forward by a 0.28 rad yaw, met the
    obstacle (−0.009 m); with its 0.531 m disk it trails 0.87 m behind, 0.31 m clear (docs/design.md).
    """
    given = set(settings.values) if settings is not None else set()
    if "robot_radius" in given:
        return prm
    from .clearance import arm_reach, swept_body

    radius = max(prm.robot_radius, swept_body(robot, 0.5 * prm.delta_max).radius)
    if float(dict(robot.wbc_overrides).get("angular_momentum_weight", 0.0)) > 0.0:  # the arms swing (robot init's)
        radius = max(radius, arm_reach(robot))
    return prm.with_(robot_radius=radius)
