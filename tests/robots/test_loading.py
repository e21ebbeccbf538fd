"""lipmpcc.robots.loading: the embedded digit_like model and robot descriptions (load_robot).

Figures are checked against the published Digit mass and, when ../shared is present, against the
reference Digit v3 MJCF (osudrl/roadrunner) read at its standing configuration.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, RobotDescriptionError
from lipmpcc.robots import DIGIT_PUBLISHED_MASS as DIGIT_MASS
from lipmpcc.robots import RobotDescription, digit_like_paths, load_robot

LEGS = ("hip_roll", "hip_yaw", "hip_pitch", "knee", "ankle_pitch", "ankle_roll")
ARMS = ("shoulder_roll", "shoulder_pitch", "shoulder_yaw", "elbow")
MOTORS = tuple(f"{s}_{j}" for s in ("left", "right") for j in LEGS) + tuple(
    f"{s}_{j}" for s in ("left", "right") for j in ARMS
)
# digit_like motor -> the reference motor whose torque limit and joint range it carries
REF_MOTOR = {
    "hip_roll": "leg/hip-roll", "hip_yaw": "leg/hip-yaw", "hip_pitch": "leg/hip-pitch", "knee": "leg/knee",
    "ankle_pitch": "leg/toe-a", "ankle_roll": "leg/toe-b", "shoulder_roll": "arm/shoulder-roll",
    "shoulder_pitch": "arm/shoulder-pitch", "shoulder_yaw": "arm/shoulder-yaw", "elbow": "arm/elbow",
}
REF_JOINT = dict(REF_MOTOR, ankle_pitch="leg/toe-pitch", ankle_roll="leg/toe-roll")


def _ref_name(table: dict[str, str], motor: str) -> str:
    side, joint = motor.split("_", 1)
    return f"{side}-{table[joint]}"


@pytest.fixture(scope="module")
def desc() -> RobotDescription:
    return load_robot("digit_like")


@pytest.fixture(scope="module")
def model(desc: RobotDescription) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(desc.scene_path))


def _standing(model: mujoco.MjModel, desc: RobotDescription) -> mujoco.MjData:
    data = mujoco.MjData(model)
    if desc.standing_keyframe:
        mujoco.mj_resetDataKeyframe(model, data, model.key(desc.standing_keyframe).id)
    else:
        data.qpos[:] = desc.standing_qpos
    mujoco.mj_forward(model, data)
    return data


# ------------------------------------------------------------------------------------------------
# structure
# ------------------------------------------------------------------------------------------------
def test_digit_like_has_free_base_and_20_motors_in_joint_order(desc: RobotDescription, model: mujoco.MjModel) -> None:
    assert model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE and model.joint(0).name == "base"
    assert model.nq == 7 + 20 and model.nv == 6 + 20
    joint_names = tuple(model.joint(j).name for j in range(1, model.njnt))
    assert joint_names == MOTORS  # tree order = actuator order
    assert desc.motor_names == MOTORS and desc.motor_joints == MOTORS
    assert desc.leg_joints == MOTORS[:12] and desc.arm_joints == MOTORS[12:]
    for a in range(model.nu):
        assert model.actuator_ctrllimited[a]
        assert model.actuator_gear[a, 0] == 1.0  # ctrl is the joint torque
        lo, hi = model.actuator_ctrlrange[a]
        assert lo == -hi and hi > 0
    assert desc.name == "digit_like" and desc.base_joint == "base" and not desc.closed_loops
    assert desc.mjcf_path.name == "digit_like.xml" and desc.scene_path.name == "scene.xml"


def test_total_mass_within_2_percent_of_published_digit_mass(desc: RobotDescription, model: mujoco.MjModel) -> None:
    mass = float(np.sum(model.body_mass))
    assert abs(mass - DIGIT_MASS) / DIGIT_MASS < 0.02
    assert desc.total_mass == pytest.approx(mass)


def test_only_the_feet_collide_and_the_scene_has_a_floor(model: mujoco.MjModel) -> None:
    colliding = [model.geom(g).name for g in range(model.ngeom)
                 if model.geom_contype[g] or model.geom_conaffinity[g]]
    assert sorted(colliding) == ["floor", "left_foot_box", "right_foot_box"]
    assert model.opt.timestep == pytest.approx(0.0005)


def test_feet_are_digit_sized_boxes_with_sole_sites_on_the_bottom(
    desc: RobotDescription, model: mujoco.MjModel
) -> None:
    assert 0.2 <= desc.foot_length <= 0.25 and 0.07 <= desc.foot_width <= 0.11
    for side in ("left", "right"):
        g = model.geom(f"{side}_foot_box")
        assert g.type[0] == mujoco.mjtGeom.mjGEOM_BOX
        np.testing.assert_allclose(2 * g.size[:2], [desc.foot_length, desc.foot_width])
        s = model.site(f"{side}_sole")
        # the site sits at the centre of the box's bottom face
        np.testing.assert_allclose(s.pos, g.pos - [0.0, 0.0, g.size[2]], atol=1e-9)
        assert model.geom_bodyid[g.id] == model.site_bodyid[s.id] == model.body(f"{side}_foot").id


def test_standing_keyframe_is_flat_footed_balanced_and_inside_joint_ranges(
    desc: RobotDescription, model: mujoco.MjModel
) -> None:
    data = _standing(model, desc)
    soles = [data.site(f"{s}_sole") for s in ("left", "right")]
    for s in soles:
        assert abs(s.xpos[2]) < 1e-4  # on the floor
        assert s.xmat.reshape(3, 3)[2, 2] > 1 - 1e-9  # flat
    centre = 0.5 * (soles[0].xpos + soles[1].xpos)
    com = data.subtree_com[model.body("torso").id]
    assert np.linalg.norm(com[:2] - centre[:2]) < 5e-3  # COM above the middle of the feet
    q = data.qpos[7:]
    lo, hi = model.jnt_range[1:, 0], model.jnt_range[1:, 1]
    assert np.all(q > lo + 0.05) and np.all(q < hi - 0.05)
    knee = model.joint("left_knee").qposadr[0]
    assert data.qpos[knee] < -0.5  # knees bent


def test_pinocchio_loads_the_robot_with_the_same_dofs_mass_and_armature(desc: RobotDescription) -> None:
    pin = pytest.importorskip("pinocchio")
    pm = pin.buildModelFromMJCF(str(desc.mjcf_path))
    mm = mujoco.MjModel.from_xml_path(str(desc.mjcf_path))
    assert (pm.nq, pm.nv) == (mm.nq, mm.nv)
    assert pin.computeTotalMass(pm) == pytest.approx(float(np.sum(mm.body_mass)), rel=1e-12)
    np.testing.assert_allclose(pm.armature[6:], mm.dof_armature[6:], rtol=1e-12)
    np.testing.assert_allclose(pm.lowerPositionLimit[7:], mm.jnt_range[1:, 0])
    np.testing.assert_allclose(pm.upperPositionLimit[7:], mm.jnt_range[1:, 1])


def test_joint_pd_with_static_feedforward_holds_the_standing_pose(
    desc: RobotDescription, model: mujoco.MjModel
) -> None:
    """The model stands for 2 s under a joint PD plus the torques that balance gravity at the keyframe."""
    data = _standing(model, desc)
    jac = []
    for s in ("left_sole", "right_sole"):
        jp, jr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, jp, jr, model.site(s).id)
        jac += [jp, jr]
    J = np.vstack(jac)
    bias = data.qfrc_bias.copy()
    wrench = np.linalg.lstsq(J[:, :6].T, bias[:6], rcond=None)[0]  # feet wrenches carrying the weight
    tau_ff = bias[6:] - J[:, 6:].T @ wrench
    q0 = data.qpos[7:].copy()
    kp = np.array([1000, 600, 1000, 1000, 200, 200] * 2 + [200] * 8, dtype=float)
    kd = 0.6 * np.sqrt(kp)
    com0 = data.subtree_com[1].copy()
    for _ in range(4000):
        data.ctrl[:] = tau_ff + kp * (q0 - data.qpos[7:]) - kd * data.qvel[6:]
        mujoco.mj_step(model, data)
    mujoco.mj_forward(model, data)
    assert np.linalg.norm(data.subtree_com[1] - com0) < 0.01
    assert np.abs(q0 - data.qpos[7:]).max() < 0.01
    assert data.xmat[1].reshape(3, 3)[2, 2] > np.cos(0.02)


# ------------------------------------------------------------------------------------------------
# against the reference Digit v3
# ------------------------------------------------------------------------------------------------
def _reference_standing_figures(path: Path) -> dict[str, float]:
    ref = load_robot(path)
    model = mujoco.MjModel.from_xml_path(str(path))
    data = _standing(model, ref)
    soles, legs = [], []
    for side in ("left", "right"):
        g = model.geom(f"{side}-foot")  # the reference foot collision box
        R = data.geom_xmat[g.id].reshape(3, 3)
        sole = data.geom_xpos[g.id] - R[:, 2] * g.size[2]  # centre of its bottom face
        hip = data.xanchor[model.joint(f"{side}-leg/hip-roll").id]
        soles.append(sole)
        legs.append(np.linalg.norm(hip - sole))
    com = data.subtree_com[model.body(ref.torso_body).id]
    return {
        "mass": float(np.sum(model.body_mass)),
        "com_height": float(com[2] - np.mean([s[2] for s in soles])),
        "leg_length": float(np.mean(legs)),
        "loop_residual": float(np.max(np.abs(data.efc_pos[: data.ne]))) if data.ne else 0.0,
    }


def _digit_like_standing_figures(desc: RobotDescription, model: mujoco.MjModel) -> dict[str, float]:
    data = _standing(model, desc)
    soles, legs = [], []
    for side in ("left", "right"):
        sole = data.site(f"{side}_sole").xpos
        hip = data.xanchor[model.joint(f"{side}_hip_roll").id]
        soles.append(sole.copy())
        legs.append(np.linalg.norm(hip - sole))
    com = data.subtree_com[model.body("torso").id]
    return {
        "com_height": float(com[2] - np.mean([s[2] for s in soles])),
        "leg_length": float(np.mean(legs)),
    }


def test_mass_com_height_and_leg_length_match_the_reference(
    shared_digit_xml: Path, desc: RobotDescription, model: mujoco.MjModel
) -> None:
    ref = _reference_standing_figures(shared_digit_xml)
    assert ref["loop_residual"] < 1e-4  # the reference standing configuration is consistent
    assert abs(ref["mass"] - DIGIT_MASS) / DIGIT_MASS < 0.01
    assert abs(desc.total_mass - ref["mass"]) / ref["mass"] < 0.02
    ours = _digit_like_standing_figures(desc, model)
    assert 0.8 < ref["com_height"] < 1.1 and 0.9 < ref["leg_length"] < 1.1  # sanity of the reading
    assert abs(ours["com_height"] - ref["com_height"]) / ref["com_height"] < 0.05
    assert abs(ours["leg_length"] - ref["leg_length"]) / ref["leg_length"] < 0.05


def test_torque_limits_and_joint_range_spans_match_the_reference(
    shared_digit_xml: Path, desc: RobotDescription, model: mujoco.MjModel
) -> None:
    ref_model = mujoco.MjModel.from_xml_path(str(shared_digit_xml))
    for a, motor in enumerate(MOTORS):
        ra = ref_model.actuator(_ref_name(REF_MOTOR, motor))
        ref_limit = ra.gear[0] * ra.ctrlrange[1]
        assert desc.torque_limits[a] == pytest.approx(ref_limit, abs=1e-3), motor
        assert model.actuator_ctrlrange[a, 1] == pytest.approx(ref_limit, abs=1e-3), motor
        span = np.diff(model.joint(motor).range)[0]
        ref_span = np.diff(ref_model.joint(_ref_name(REF_JOINT, motor)).range)[0]
        assert span == pytest.approx(ref_span, abs=np.radians(0.01)), motor
        # armature: the reference's reflected rotor inertia (the ankles take the toe-A/B motors')
        ref_dof = ref_model.joint(_ref_name(REF_MOTOR, motor)).dofadr[0]
        assert model.dof_armature[model.joint(motor).dofadr[0]] == pytest.approx(
            ref_model.dof_armature[ref_dof], rel=1e-5
        ), motor


def test_the_reference_file_gets_the_digit_v3_description(shared_digit_xml: Path) -> None:
    ref = load_robot(shared_digit_xml)
    assert ref.name == "digit_v3" and ref.closed_loops and ref.base_joint is None
    assert ref.torso_body == "torso/base" and ref.left_foot_body == "left-leg/toe-roll"
    assert ref.standing_keyframe is None and ref.standing_qpos is not None and len(ref.standing_qpos) == 61
    assert len(ref.motor_names) == 20 and max(ref.torque_limits) == pytest.approx(231.317, abs=1e-3)
    assert ref.foot_length == pytest.approx(0.235) and ref.foot_width == pytest.approx(0.08)


# ------------------------------------------------------------------------------------------------
# bad input
# ------------------------------------------------------------------------------------------------


def test_model_lacking_a_foot_body_names_it(tmp_path: Path) -> None:
    robot_xml, _ = digit_like_paths()
    text = robot_xml.read_text().replace('name="left_foot"', 'name="left_paw"')
    path = tmp_path / "pawed.xml"
    path.write_text(text)
    with pytest.raises(RobotDescriptionError) as err:
        load_robot(path)
    assert "left_foot" in str(err.value) and str(path) in str(err.value)
    assert any("left_foot" in m for m in err.value.missing)
    # naming the part makes it loadable
    assert load_robot(path, left_foot_body="left_paw").left_foot_body == "left_paw"


def test_model_without_actuators_or_with_a_bad_override_is_rejected(tmp_path: Path) -> None:
    robot_xml, _ = digit_like_paths()
    text = robot_xml.read_text()
    start = text.index("\n  <actuator>")
    end = text.index("</actuator>") + len("</actuator>")
    path = tmp_path / "unactuated.xml"
    path.write_text(text[:start] + text[end:])
    with pytest.raises(RobotDescriptionError, match="actuators"):
        load_robot(path)
    with pytest.raises(RobotDescriptionError, match="keyframe 'crouch'"):
        load_robot("digit_like", standing_keyframe="crouch")
    with pytest.raises(InvalidInputError, match="overrides"):
        load_robot("digit_like", left_hoof="x")


def test_unknown_robot_name_is_rejected() -> None:
    with pytest.raises(InvalidInputError, match="digit_like"):
        load_robot("cassie")
