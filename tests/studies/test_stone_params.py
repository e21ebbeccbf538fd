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
