"""lipmpcc.studies.path_params: paper A's MPCC on a full body — the robot's minimum lateral step and step duration,
the Cartesian MPC's heading weight, the timed MPCC's heading and turn weights, the whole-body disk, the reach
rectangle scaled by the layout."""

from __future__ import annotations

import pytest


def test_full_body_parameters_take_the_robots_minimum_lateral_step() -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies.path_params import FULLBODY_OBSTACLE_MARGIN, fullbody_params

    p = fullbody_params("overtake", "mpcc", 0.95, min_lateral_step=0.16)
    assert p.rectangle.lateral == (0.16, 0.40) and p.obstacle_margin == FULLBODY_OBSTACLE_MARGIN
    for bad in (-0.01, 0.4, float("nan")):
        with pytest.raises(InvalidInputError, match="min_lateral_step"):
            fullbody_params("overtake", "mpcc", 0.95, min_lateral_step=bad)


def test_full_body_cartesian_mpc_steps_about_a_wide_minimum_lateral_step_through_its_cost() -> None:
    """A layout's min_lateral_step above the rectangle's 0.10 m (Digit v3's 0.16 m) becomes the Cartesian MPC's
    lateral_nominal, the rectangle's bound kept; at 0.10 m (digit_like) and for the MPCC nothing changes."""
    from lipmpcc.studies.path_params import fullbody_params

    p = fullbody_params("overtake", "cartesian", 0.95, min_lateral_step=0.16)
    assert p.rectangle.lateral == (0.10, 0.40) and p.lateral_nominal == 0.16
    p = fullbody_params("overtake", "cartesian", 0.95, min_lateral_step=0.10)
    assert p.rectangle.lateral == (0.10, 0.40) and p.lateral_nominal == 0.0
    p = fullbody_params("overtake", "mpcc", 0.95, min_lateral_step=0.16)
    assert p.rectangle.lateral == (0.16, 0.40) and p.lateral_nominal == 0.0


def test_full_body_cartesian_mpc_weighs_the_heading_error() -> None:
    from lipmpcc.studies.path_params import FULLBODY_CARTESIAN_HEADING_WEIGHT, fullbody_params

    assert fullbody_params("overtake", "cartesian", 0.95).heading_weight == FULLBODY_CARTESIAN_HEADING_WEIGHT > 0
    assert fullbody_params("overtake", "mpcc", 0.95).heading_weight == 0.0  # paper A's cost
    assert fullbody_params("circle", "mpcc", 0.95).heading_weight == 0.0


def test_timed_mpcc_on_a_full_body_weighs_the_heading_and_keeps_the_whole_body_clear() -> None:
    """The timed MPCC's full-body parameters (timed_fullbody_params): a heading weight of 0.2 max(Q̄) (twice the
    Cartesian MPC's ratio), a weight of at least 50 on the heading change, and the whole-body disk of
    body_clearance_params; fields given by --set are left alone, and fixed T's weights (fullbody_params) are paper
    A's."""
    from lipmpcc.planners.presets import PlannerSettings
    from lipmpcc.robots import load_robot
    from lipmpcc.studies.path_params import (FULLBODY_TIMED_HEADING_RATIO, FULLBODY_TIMED_TURN_WEIGHT, fullbody_params,
                                             timed_fullbody_params)

    robot = load_robot("digit_like")
    fixed = fullbody_params("overtake", "mpcc", 0.95)
    assert fixed.robot_radius == 0.2 and fixed.heading_weight == 0.0 and fixed.R[2] == 5.0
    r = body_clearance_radius(robot, fixed)
    timed = timed_fullbody_params(fixed, robot)
    assert timed.robot_radius == r and timed.heading_weight == pytest.approx(200.0) == FULLBODY_TIMED_HEADING_RATIO * 1000.0
    assert timed.R == (fixed.R[0], fixed.R[1], FULLBODY_TIMED_TURN_WEIGHT) == (100.0, 100.0, 50.0)
    assert timed.with_(robot_radius=0.2, heading_weight=0.0, R=fixed.R) == fixed  # nothing else changes
    assert timed_fullbody_params(fullbody_params("circle", "mpcc", 0.95), robot).heading_weight == pytest.approx(60.0)
    free = timed_fullbody_params(fullbody_params("circle", "mpcc", 0.95), robot, obstacles=False)  # no swerve to damp
    assert free.heading_weight == fullbody_params("circle", "mpcc", 0.95).heading_weight and free.R[2] == 5.0
    assert free.robot_radius == r
    cart = fullbody_params("overtake", "cartesian", 0.95)
    assert timed_fullbody_params(cart, robot).heading_weight == pytest.approx(2.0 * cart.heading_weight) == 40.0
    given = PlannerSettings(values={"heading_weight": 0.0, "robot_radius": 0.3, "r_theta": 1.0})
    kept = timed_fullbody_params(given.apply(fixed, "mpcc"), robot, given)
    assert kept.heading_weight == 0.0 and kept.robot_radius == 0.3 and kept.R[2] == 1.0


def body_clearance_radius(robot, prm) -> float:
    """The swept-body radius body_clearance_params gives ``prm`` on ``robot`` (checked against swept_body)."""
    from lipmpcc.studies.clearance import swept_body
    from lipmpcc.studies.path_params import body_clearance_params

    r = body_clearance_params(prm, robot).robot_radius
    assert r == swept_body(robot, 0.5 * prm.delta_max).radius
    return r


def test_the_mpcc_on_a_full_body_keeps_the_swept_body_clear_fixed_t_and_timed() -> None:
    """body_clearance_params: the default 0.2 m disk grows to what digit_like's geometry covers during a step (the
    thigh swept back by half of delta_max: 0.43 m), whatever the preset; a robot_radius given by --set is kept,
    and a larger preset radius is not shrunk."""
    from lipmpcc.planners.presets import PlannerSettings
    from lipmpcc.robots import load_robot
    from lipmpcc.studies.path_params import body_clearance_params, fullbody_params

    robot = load_robot("digit_like")
    for scenario, planner in (("overtake", "mpcc"), ("circle", "mpcc"), ("overtake", "cartesian")):
        prm = fullbody_params(scenario, planner, 0.95)
        grown = body_clearance_params(prm, robot)
        assert 0.42 < grown.robot_radius < 0.45 and grown.with_(robot_radius=prm.robot_radius) == prm
    prm = fullbody_params("overtake", "mpcc", 0.95)
    assert body_clearance_radius(robot, prm.with_(delta_max=0.6)) > body_clearance_radius(robot, prm)  # longer steps
    given = PlannerSettings(values={"robot_radius": 0.25})
    assert body_clearance_params(given.apply(prm, "mpcc"), robot, given).robot_radius == 0.25
    assert body_clearance_params(prm.with_(robot_radius=0.9), robot).robot_radius == 0.9


def test_full_body_parameters_take_the_robots_step_duration() -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.robots import load_robot
    from lipmpcc.studies.path_scenarios import STEP_DURATION
    from lipmpcc.studies.path_params import fullbody_params

    assert fullbody_params("overtake", "mpcc", 0.95).model.T == STEP_DURATION == load_robot("digit_like").step_duration
    assert fullbody_params("overtake", "mpcc", 0.95, step_duration=0.35).model.T == pytest.approx(0.35)
    for bad in (0.1, 1.5, float("nan"), True):
        with pytest.raises(InvalidInputError, match="step_duration"):
            fullbody_params("overtake", "mpcc", 0.95, step_duration=bad)


def test_the_mpcc_reach_rectangle_scales_with_the_layout_sizes() -> None:
    import dataclasses

    from lipmpcc.robots import load_robot
    from lipmpcc.studies.path_params import FULLBODY_RECTANGLE, fullbody_params, robot_rectangle

    digit = load_robot("digit_like")
    assert robot_rectangle(digit) == FULLBODY_RECTANGLE
    small = dataclasses.replace(digit, step_width=0.13, max_step_length=0.275)
    rect = robot_rectangle(small)
    assert rect.forward == pytest.approx((-0.175, 0.175)) and rect.lateral == pytest.approx((0.10, 0.20))
    p = fullbody_params("circle", "mpcc", 0.6, min_lateral_step=0.08, step_duration=0.3, rectangle=rect)
    assert p.rectangle.lateral == pytest.approx((0.08, 0.20)) and p.rectangle.forward == rect.forward


def test_per_step_bounds_scale_with_the_step_duration_on_a_sized_layout() -> None:
    """Paper A's per-step bounds (0.3 m of progress, ±0.3 rad of heading change per 0.4 s step) hold as a speed and
    a turn rate on a robot whose layout states its sizes; Digit's layouts keep paper A's numbers."""
    import dataclasses

    from lipmpcc.robots import load_robot
    from lipmpcc.studies.path_params import FULLBODY_RECTANGLE, robot_rectangle, robot_sized, robot_step_scale

    digit = load_robot("digit_like")
    assert not robot_sized(digit) and robot_step_scale(digit) == 1.0
    assert robot_rectangle(digit).heading == FULLBODY_RECTANGLE.heading
    small = dataclasses.replace(digit, step_width=0.2, max_step_length=0.27, step_duration=0.3)
    assert robot_sized(small) and robot_step_scale(small) == pytest.approx(0.75)
    assert robot_rectangle(small).heading == pytest.approx((-0.225, 0.225))


def test_the_body_disk_covers_free_arms_only_when_the_upper_body_yields() -> None:
    """A layout whose upper body takes the swing leg's momentum (``angular_momentum_weight`` > 0, as ``robot init``
    writes it) gets a body disk out to the arms' reach about their joints; Digit's layouts keep the swept body."""
    import dataclasses

    from lipmpcc.planners.mpcc import MpccParams
    from lipmpcc.robots import load_robot
    from lipmpcc.studies.clearance import arm_reach, swept_body
    from lipmpcc.studies.path_params import body_clearance_params

    digit = load_robot("digit_like")
    prm = MpccParams.overtake_mpcc()
    swept = swept_body(digit, 0.5 * prm.delta_max).radius
    assert body_clearance_params(prm, digit).robot_radius == pytest.approx(max(prm.robot_radius, swept))
    reach = arm_reach(digit)
    assert reach > swept  # an arm held out sideways reaches past the standing arms
    free = dataclasses.replace(digit, wbc_overrides=(("angular_momentum_weight", 1.0),))
    assert body_clearance_params(prm, free).robot_radius == pytest.approx(reach)
    assert arm_reach(dataclasses.replace(digit, arm_joints=())) == 0.0
