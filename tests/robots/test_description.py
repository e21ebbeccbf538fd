"""lipmpcc.robots.description and .loading: the robot resolved once (compiled models, standing pose),
the shipped layouts as files, and the old lipmpcc.robot path."""

from __future__ import annotations

import contextlib
import math
import pickle
from collections import Counter
from pathlib import Path
from typing import Iterator

import mujoco
import numpy as np
import pytest

from lipmpcc.conventions import LEFT, RIGHT
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.robots import RobotDescription, StandingPose, load_robot
from lipmpcc.robots.description import DIGIT_PUBLISHED_MASS
from lipmpcc.robots.layouts import SHIPPED_LAYOUTS, read_layout_file, shipped_layout
from lipmpcc.robots.mjcf import connect_residuals, loop_closure_errors
from lipmpcc.resources import data_path


@contextlib.contextmanager
def counting_compiles() -> Iterator[Counter]:
    """Counts MjModel.from_xml_path and MjSpec.compile calls inside the block."""
    counts: Counter = Counter()
    from_xml, compile_spec = mujoco.MjModel.from_xml_path, mujoco.MjSpec.compile

    def from_xml_path(path: str, *a: object, **k: object) -> mujoco.MjModel:
        counts["from_xml_path"] += 1
        return from_xml(path, *a, **k)

    def compile(spec: mujoco.MjSpec, *a: object, **k: object) -> mujoco.MjModel:
        counts["compile"] += 1
        return compile_spec(spec, *a, **k)

    mujoco.MjModel.from_xml_path = staticmethod(from_xml_path)
    mujoco.MjSpec.compile = compile
    try:
        yield counts
    finally:
        mujoco.MjModel.from_xml_path = from_xml
        mujoco.MjSpec.compile = compile_spec


def _measured_standing(robot: RobotDescription) -> tuple[np.ndarray, ...]:
    from lipmpcc.sim.robot_sim import RobotSim

    sim = RobotSim(robot)
    sim.reset(robot.standing_reset)
    (pl, _), (pr, _) = sim.foot_poses()
    R = sim.torso_pose().rotation
    return sim.qpos, pl, pr, sim.com(), np.array([math.atan2(R[1, 0], R[0, 0])])


def test_digit_like_compiles_each_file_once_and_nothing_compiles_it_again() -> None:
    from lipmpcc.control.wbc import WholeBodyController
    from lipmpcc.sim.robot_sim import RobotSim
    from lipmpcc.sim.stones_scene import StonesRobotSim
    from lipmpcc.terrain import make_profile

    with counting_compiles() as load:
        robot = load_robot("digit_like")
    assert load == {"from_xml_path": 1, "compile": 1}  # the robot file and the scene
    assert robot.model is robot.model and robot.scene_model is robot.scene_model
    with counting_compiles() as later:
        robot.standing
        WholeBodyController(robot)
        RobotSim(robot)
        RobotSim(robot, timestep=0.001)
    assert sum(later.values()) == 0
    with counting_compiles() as stones:
        StonesRobotSim(robot, make_profile("I", L=0.4, W=0.15))
    assert stones == {"compile": 1}  # its own edited scene only


def test_a_path_robot_compiles_its_file_once_for_the_controller_and_once_as_the_simulators_scene() -> None:
    from lipmpcc.control.wbc import WholeBodyController
    from lipmpcc.sim.robot_sim import RobotSim

    xml = load_robot("digit_like").mjcf_path  # the robot file alone (no floor: the scene gets one)
    with counting_compiles() as counts:
        robot = load_robot(xml)
        WholeBodyController(robot)
        RobotSim(robot)
        RobotSim(robot)
        robot.standing
    assert counts == {"from_xml_path": 1, "compile": 2}  # the scene: compiled, floor added, compiled


def test_standing_pose_is_what_a_simulator_reset_to_it_measures_to_the_bit(shared_digit_xml: Path) -> None:
    for robot in (load_robot("digit_like"), load_robot(shared_digit_xml)):
        st = robot.standing
        assert isinstance(st, StandingPose) and robot.standing is st
        qpos, pl, pr, com, yaw = _measured_standing(robot)
        assert st.qpos.tobytes() == qpos.tobytes()
        assert st.left_sole.tobytes() == pl.tobytes() and st.right_sole.tobytes() == pr.tobytes()
        assert st.com.tobytes() == com.tobytes() and st.com_height == float(com[2])
        assert st.torso_yaw == float(yaw[0])
        np.testing.assert_array_equal(st.feet_xy, [pl[:2], pr[:2]])
        assert st.sole(LEFT) is st.left_sole and st.sole("right") is st.right_sole
        with pytest.raises(ValueError):
            st.com[0] = 1.0  # read-only


def test_digit_like_standing_pose_values() -> None:
    st = load_robot("digit_like").standing
    assert 0.9 < st.com_height < 1.0 and st.torso_yaw == 0.0
    assert st.left_sole[1] > 0.1 and st.right_sole[1] < -0.1 and abs(st.left_sole[2]) < 1e-3
    assert np.linalg.norm(st.com[:2] - 0.5 * (st.left_sole + st.right_sole)[:2]) < 5e-3


def test_overrides_keep_the_compiled_models_and_recompute_the_standing_pose() -> None:
    robot = load_robot("digit_like")
    st = robot.standing
    by_offset = load_robot(robot, left_sole_site=None, right_sole_site=None)  # soles from sole_offset
    assert by_offset.model is robot.model and by_offset.scene_model is robot.scene_model
    assert by_offset.standing is not st and by_offset.standing.com.tobytes() == st.com.tobytes()
    np.testing.assert_allclose(by_offset.standing.feet_xy, st.feet_xy, atol=1e-6)  # the offset is the site's
    assert load_robot(robot) is robot
    assert by_offset != robot and load_robot(robot, name="x").name == "x"


def test_a_pickled_description_carries_no_compiled_model_and_compiles_again() -> None:
    robot = load_robot("digit_like")
    robot.standing
    copy = pickle.loads(pickle.dumps(robot))
    assert copy == robot and copy._cache == {}
    assert copy.standing.com.tobytes() == robot.standing.com.tobytes()


def test_shipped_layouts_are_layout_files() -> None:
    for name in SHIPPED_LAYOUTS:
        path = data_path("layouts", f"{name}.toml")
        assert read_layout_file(path) == shipped_layout(name) and shipped_layout(name)["name"] == name
    a = shipped_layout("digit_like")
    a["torso_body"] = "changed"  # a copy
    assert shipped_layout("digit_like")["torso_body"] == "torso"
    v3 = shipped_layout("digit_v3")
    assert len(v3["standing_qpos"]) == 61 and v3["base_joint"] is None and v3["wbc_overrides"] == {"cop_safety_factor": 0.6}
    with pytest.raises(InvalidInputError, match="cassie"):
        shipped_layout("cassie")


def test_sides_come_from_the_conventions() -> None:
    robot = load_robot("digit_like")
    assert robot.foot_body(LEFT) == robot.foot_body("l") == "left_foot"
    assert robot.sole_site(RIGHT) == robot.sole_site(-1) == "right_sole"
    with pytest.raises(InvalidInputError, match="side"):
        robot.foot_body("middle")


def test_loop_closure_errors_are_the_norms_of_the_connect_residuals() -> None:
    xml = """<mujoco><worldbody>
      <body name="a"><freejoint/><geom size=".1"/></body>
      <body name="b" pos="0.3 0 0"><freejoint/><geom size=".1"/></body>
    </worldbody><equality>
      <connect body1="a" body2="b" anchor="0.1 0 0"/>
      <weld body1="a" body2="b"/>
    </equality></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    np.testing.assert_allclose(connect_residuals(model, data)[0], 0.0, atol=1e-12)  # MuJoCo closes it at qpos0
    data.qpos[7] += 0.05  # body b 5 cm further along x
    mujoco.mj_forward(model, data)
    res = connect_residuals(model, data)
    np.testing.assert_allclose(res[0], [-0.05, 0.0, 0.0], atol=1e-12)  # anchor 1 minus anchor 2
    assert np.all(np.isnan(res[1]))  # a weld
    err = loop_closure_errors(model, data)
    assert err[0] == float(np.linalg.norm(res[0])) and np.isnan(err[1])


def test_the_old_robot_path_forwards_with_a_warning() -> None:
    import lipmpcc.conventions
    import lipmpcc.robot as old
    import lipmpcc.robots.layouts as layouts

    for name, obj in (("load_robot", load_robot), ("RobotDescription", RobotDescription),
                      ("DIGIT_MASS", DIGIT_PUBLISHED_MASS), ("LEFT", lipmpcc.conventions.LEFT),
                      ("read_layout_file", read_layout_file), ("loop_closure_errors", loop_closure_errors),
                      ("DIGIT_V3_STANDING_QPOS", layouts.DIGIT_V3_STANDING_QPOS)):
        with pytest.warns(DeprecationWarning, match=rf"lipmpcc\.robot\.{name} moved"):
            assert getattr(old, name) == obj
    assert DIGIT_PUBLISHED_MASS == 47.9
