"""lipmpcc.studies.stone_params: paper B on a full body — the whole-body QP's ALIP COM gains, the ALIP-MPC's
centre-of-pressure box from the robot's description, and the checked settings of a full-body stones run."""

from __future__ import annotations

import pytest

slow = pytest.mark.slow


@pytest.fixture(scope="module")
def robot():
    from lipmpcc.robots import load_robot

    return load_robot("digit_like")


@slow
def test_stones_runs_take_the_robots_alip_com_gains(robot) -> None:
    import dataclasses

    from lipmpcc.studies.stone_params import stones_wbc_params
    from lipmpcc.control.wbc_types import WbcParams

    p = stones_wbc_params(robot)
    base = WbcParams.for_robot(robot)
    assert p.com.kp == (16.0, 16.0, base.com.kp[2]) and p.com.kd == (8.0, 8.0, base.com.kd[2])
    assert p.com.weight == base.com.weight and p.torso == base.torso
    stiff = dataclasses.replace(robot, alip_com_gains=None)
    assert stones_wbc_params(stiff) == WbcParams.for_robot(stiff)


def test_stones_runs_apply_the_robots_alip_wbc_overrides_over_its_wbc_overrides(robot) -> None:
    """``alip_wbc_overrides`` (``robot init`` writes them for G1 and T1) change paper B's controller only."""
    import dataclasses

    from lipmpcc.studies.stone_params import stones_wbc_params
    from lipmpcc.control.wbc_types import PostureGains, WbcParams

    r = dataclasses.replace(robot, wbc_overrides=(("angular_momentum_weight", 0.5), ("cop_safety_factor", 0.6)),
                            alip_wbc_overrides=(("angular_momentum_weight", 1.0),
                                                ("arm_posture", {"weight": 0.01, "kp": 100.0, "kd": 20.0})))
    p = stones_wbc_params(r)
    assert p.angular_momentum_weight == 1.0 and p.arm_posture == PostureGains(weight=0.01, kp=100.0, kd=20.0)
    assert p.cop_safety_factor == 0.6  # the robot's own overrides stay under them
    everyday = WbcParams.for_robot(r)
    assert everyday.angular_momentum_weight == 0.5 and everyday.arm_posture == WbcParams().arm_posture


def test_the_cop_box_is_the_robots_or_a_point_foot(robot) -> None:
    import dataclasses

    from lipmpcc.studies.stone_params import robot_cop_range

    assert robot_cop_range(dataclasses.replace(robot, alip_cop_range=None)) == (0.0, 0.0)
    assert robot_cop_range(dataclasses.replace(robot, alip_cop_range=(0.03, 0.01))) == (0.03, 0.01)


@pytest.mark.parametrize("kw, name", [({"landing_depth": 0.1}, "landing_depth"), ({"n_exit": 11}, "n_exit"),
                                      ({"rate_hz": 0.0}, "rate_hz"), ({"stone_tolerance": -0.01}, "stone_tolerance"),
                                      ({"com_height": 3.0}, "com_height"), ({"approach_length": 0.7}, "approach_length"),
                                      ({"touchdown_contact": "sometimes"}, "touchdown_contact")])
def test_full_body_stones_params_refuse_bad_settings(kw, name) -> None:
    from lipmpcc.exceptions import ParameterError
    from lipmpcc.studies.stone_params import FullBodyStonesParams

    with pytest.raises(ParameterError, match=name):
        FullBodyStonesParams(**kw)
    assert FullBodyStonesParams().landing_depth == 0.015 and FullBodyStonesParams().n_exit == 2


def test_stones_runs_take_the_robots_cop_safety_factor(robot) -> None:
    """Paper B's controller uses the description's ``alip_cop_safety_factor`` (Digit v3: the lateral CoP room the
    whole-body controller keeps beyond the ALIP-MPC's box); without one (``digit_like``) its own, unchanged."""
    import dataclasses

    from lipmpcc.control.wbc_types import WbcParams
    from lipmpcc.studies.stone_params import stones_wbc_params

    assert robot.alip_cop_safety_factor is None
    own = stones_wbc_params(robot)
    assert own.cop_safety_factor == WbcParams.for_robot(robot).cop_safety_factor
    wide = stones_wbc_params(dataclasses.replace(robot, alip_cop_safety_factor=0.8))
    assert wide.cop_safety_factor == 0.8
    assert dataclasses.replace(wide, cop_safety_factor=own.cop_safety_factor) == own  # nothing else moves


def test_digit_v3s_controller_keeps_lateral_room_beyond_the_planners_ankle() -> None:
    """Digit v3's shipped layout (read as TOML: the model is not shipped): in paper B's runs the controller's
    lateral CoP limit (safety factor x half the sole's width) lies beyond the ALIP-MPC's lateral box, and that box
    is the 24 mm the push test needs (docs/design.md, "Digit v3's push test")."""
    import tomllib

    from lipmpcc.resources import data_path

    with open(data_path("layouts", "digit_v3.toml"), "rb") as f:
        lay = tomllib.load(f)
    half_w = 0.5 * lay["foot_width"]
    assert lay["alip_cop_range"][1] >= 0.024
    assert lay["alip_cop_safety_factor"] * half_w >= lay["alip_cop_range"][1] + 0.005
    assert lay["alip_cop_safety_factor"] > lay["wbc_overrides"]["cop_safety_factor"]  # paper B only: paper A keeps 0.6
