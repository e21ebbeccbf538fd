"""lipmpcc.robots.wbc_model: what the whole-body controller reads from the MJCF; the old lipmpcc.wbc path."""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

from lipmpcc.exceptions import ParameterError, RobotDescriptionError
from lipmpcc.robots import load_robot
from lipmpcc.robots.state_map import StateMap
from lipmpcc.robots.wbc_model import WbcModelData, wbc_model_data


def test_digit_like_reading() -> None:
    robot = load_robot("digit_like")
    data = wbc_model_data(robot)
    mj = robot.model
    assert isinstance(data, WbcModelData) and data.mjcf_path == str(robot.mjcf_path)
    assert data.actuator_names == robot.motor_names and data.actuated_joints == robot.motor_joints
    np.testing.assert_array_equal(data.actuation_gains, np.ones(20))  # gear 1, gain 1
    np.testing.assert_array_equal(data.u_min, mj.actuator_ctrlrange[:, 0])
    np.testing.assert_array_equal(data.u_max, mj.actuator_ctrlrange[:, 1])
    assert data.gravity.tolist() == [0.0, 0.0, -9.80665] and data.spring_joints == ()
    mus = [mj.geom_friction[mj.geom(f"{s}_foot_box").id, 0] for s in ("left", "right")]
    cone = 2.0 if mj.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL else math.sqrt(2.0)
    assert data.friction == min(mus) / cone
    # the sole sites sit at the centres of the foot boxes' bottom faces
    np.testing.assert_allclose(np.asarray(data.sole_cop_centers), 0.0, atol=1e-9)
    # loops are checked at the standing keyframe, in Pinocchio's order
    key = mj.key_qpos[mj.key("stand").id]
    assert data.loop_reference_qpos.tobytes() == key.tobytes()
    assert data.loop_reference_configuration.tobytes() == StateMap(mj).configuration_to_pinocchio(key).tobytes()
    assert wbc_model_data(robot, friction=0.3).friction == 0.3
    with pytest.raises(ParameterError, match="friction"):
        wbc_model_data(robot, friction=-1.0)


def test_the_controller_reads_the_same(shared_digit_xml: Path) -> None:
    from lipmpcc.control.wbc import WholeBodyController

    robot = load_robot(shared_digit_xml)
    data = wbc_model_data(robot)
    wbc = WholeBodyController(robot)
    assert wbc.actuator_names == list(data.actuator_names) and wbc.friction == data.friction
    assert len(data.spring_joints) == 4 and np.all(data.spring_stiffness > 0)
    assert wbc.n_springs == len(data.spring_joints) and wbc.n_loops == robot.model.neq == 6
    # Digit v3's sole sites are 1.5 cm ahead of the foot boxes' centres
    np.testing.assert_allclose([c[0] for c in data.sole_cop_centers], -0.015, atol=1e-3)


def test_an_equality_other_than_connect_is_named(tmp_path: Path) -> None:
    robot = load_robot("digit_like")
    text = robot.mjcf_path.read_text()
    xml = tmp_path / "welded.xml"
    xml.write_text(text.replace("</mujoco>", '<equality><weld name="glue" body1="left_foot" body2="right_foot"/>'
                                               "</equality></mujoco>"))
    with pytest.raises(RobotDescriptionError, match="weld> 'glue'"):
        wbc_model_data(load_robot(xml))


def test_the_old_wbc_path_forwards_with_a_warning() -> None:
    import lipmpcc.wbc as old
    from lipmpcc.control import wbc, wbc_types

    for name, obj in (("WholeBodyController", wbc.WholeBodyController), ("WbcParams", wbc_types.WbcParams),
                      ("WbcReference", wbc_types.WbcReference), ("TaskGains", wbc_types.TaskGains)):
        with pytest.warns(DeprecationWarning, match=rf"lipmpcc\.wbc\.{name} moved"):
            assert getattr(old, name) is obj
