"""lipmpcc.robots.state_map: MuJoCo <-> Pinocchio state mapping (quaternion order, free-joint
velocity frames, joint order).

A random state is put into MuJoCo, mapped, and frame placements and frame velocities are compared
between MuJoCo (mj_forward, mj_objectVelocity) and Pinocchio (forwardKinematics, getFrameVelocity).
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

pin = pytest.importorskip("pinocchio")

from lipmpcc.exceptions import StateError  # noqa: E402
from lipmpcc.robots import load_robot  # noqa: E402
from lipmpcc.robots.state_map import StateMap, mujoco_to_pinocchio, pinocchio_to_mujoco  # noqa: E402
from lipmpcc.sim.robot_sim import RobotSim  # noqa: E402

TOL = 1e-9


def _random_state(model: mujoco.MjModel, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    qpos = model.qpos0.copy()
    for j in range(model.njnt):
        a, t = model.jnt_qposadr[j], model.jnt_type[j]
        if t == mujoco.mjtJoint.mjJNT_FREE:
            qpos[a : a + 3] = rng.normal(size=3)
            quat = rng.normal(size=4)
            qpos[a + 3 : a + 7] = quat / np.linalg.norm(quat)
        elif t == mujoco.mjtJoint.mjJNT_BALL:
            quat = rng.normal(size=4)
            qpos[a : a + 4] = quat / np.linalg.norm(quat)
        else:
            lo, hi = model.jnt_range[j] if model.jnt_limited[j] else (-np.pi, np.pi)
            qpos[a] = rng.uniform(lo, hi)
    return qpos, rng.normal(size=model.nv)


def _compare(path: Path, bodies: list[str], sites: list[str], seeds: range) -> None:
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    pmodel = pin.buildModelFromMJCF(str(path))
    pdata = pmodel.createData()
    smap = StateMap(model)
    for seed in seeds:
        qpos, qvel = _random_state(model, np.random.default_rng(seed))
        data.qpos[:], data.qvel[:] = qpos, qvel
        mujoco.mj_forward(model, data)
        q, v = smap.to_pinocchio(qpos, qvel)
        pin.forwardKinematics(pmodel, pdata, q, v)
        pin.updateFramePlacements(pmodel, pdata)
        objects = [(b, mujoco.mjtObj.mjOBJ_XBODY, pin.BODY) for b in bodies] + [
            (s, mujoco.mjtObj.mjOBJ_SITE, pin.OP_FRAME) for s in sites
        ]
        for name, objtype, ftype in objects:
            fid = pmodel.getFrameId(name, ftype)
            assert fid < pmodel.nframes, name
            oid = mujoco.mj_name2id(model, objtype, name)
            if objtype == mujoco.mjtObj.mjOBJ_XBODY:
                pos, rot = data.xpos[oid], data.xmat[oid].reshape(3, 3)
            else:
                pos, rot = data.site_xpos[oid], data.site_xmat[oid].reshape(3, 3)
            placement = pdata.oMf[fid]
            np.testing.assert_allclose(placement.translation, pos, atol=TOL, err_msg=name)
            np.testing.assert_allclose(placement.rotation, rot, atol=TOL, err_msg=name)
            vel = np.zeros(6)  # [angular; linear] in the object's frame
            mujoco.mj_objectVelocity(model, data, objtype, oid, vel, 1)
            pv = pin.getFrameVelocity(pmodel, pdata, fid, pin.LOCAL)
            np.testing.assert_allclose(pv.angular, vel[:3], atol=TOL, err_msg=name)
            np.testing.assert_allclose(pv.linear, vel[3:], atol=TOL, err_msg=name)
        # and back
        qpos2, qvel2 = smap.to_mujoco(q, v)
        np.testing.assert_allclose(qpos2, qpos, atol=1e-12)
        np.testing.assert_allclose(qvel2, qvel, atol=1e-12)


@pytest.fixture(scope="module")
def digit_like_xml() -> Path:
    return load_robot("digit_like").mjcf_path


def test_pinocchio_keeps_mujocos_joint_order(digit_like_xml: Path) -> None:
    model = mujoco.MjModel.from_xml_path(str(digit_like_xml))
    pmodel = pin.buildModelFromMJCF(str(digit_like_xml))
    assert list(pmodel.names)[1:] == [model.joint(j).name for j in range(model.njnt)]
    for j in range(1, model.njnt):  # same coordinate and velocity slots
        jid = pmodel.getJointId(model.joint(j).name)
        assert pmodel.joints[jid].idx_q == model.jnt_qposadr[j]
        assert pmodel.joints[jid].idx_v == model.jnt_dofadr[j]


def test_frame_placements_and_velocities_agree_for_random_states(digit_like_xml: Path) -> None:
    _compare(
        digit_like_xml,
        bodies=["torso", "left_foot", "right_foot", "left_forearm"],
        sites=["left_sole", "right_sole"],
        seeds=range(5),
    )


def test_mass_matrix_agrees_after_the_velocity_change_of_coordinates(digit_like_xml: Path) -> None:
    model = mujoco.MjModel.from_xml_path(str(digit_like_xml))
    data = mujoco.MjData(model)
    pmodel = pin.buildModelFromMJCF(str(digit_like_xml))
    pdata = pmodel.createData()
    assert pin.computeTotalMass(pmodel) == pytest.approx(float(np.sum(model.body_mass)), rel=1e-12)
    qpos, qvel = _random_state(model, np.random.default_rng(7))
    data.qpos[:], data.qvel[:] = qpos, qvel
    mujoco.mj_forward(model, data)
    m_mj = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, m_mj)
    q, v = mujoco_to_pinocchio(qpos, qvel)
    m_pin = pin.crba(pmodel, pdata, q)
    m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
    # v_pin = T qvel_mj with T = diag(R^T, I): M_mj = T^T M_pin T
    R = data.xmat[1].reshape(3, 3)
    T = np.eye(model.nv)
    T[:3, :3] = R.T
    np.testing.assert_allclose(m_mj, T.T @ m_pin @ T, atol=1e-9)
    # kinetic energy is the same number in both conventions
    assert 0.5 * qvel @ m_mj @ qvel == pytest.approx(0.5 * v @ m_pin @ v, rel=1e-12)


def test_free_joint_quaternion_order_and_velocity_frame_explicitly() -> None:
    yaw = np.pi / 2  # base turned 90 deg about z
    qpos = np.r_[1.0, 2.0, 0.9, np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2), 0.3]
    qvel = np.r_[1.0, 0.0, 0.0, 0.0, 0.0, 0.5, -0.2]  # world +x, yaw rate 0.5 rad/s
    q, v = mujoco_to_pinocchio(qpos, qvel)
    np.testing.assert_allclose(q[3:7], [0.0, 0.0, np.sin(yaw / 2), np.cos(yaw / 2)])  # (x, y, z, w)
    np.testing.assert_allclose(v[:3], [0.0, -1.0, 0.0], atol=1e-15)  # world +x is body -y
    np.testing.assert_allclose(v[3:], qvel[3:])
    back = pinocchio_to_mujoco(q, v)
    np.testing.assert_allclose(back[0], qpos)
    np.testing.assert_allclose(back[1], qvel, atol=1e-15)
    with pytest.raises(StateError):
        mujoco_to_pinocchio(qpos[:-1], qvel)
    with pytest.raises(StateError):
        mujoco_to_pinocchio(np.r_[qpos[:-1], np.nan], qvel)


def test_robot_sim_reports_the_mapped_state() -> None:
    sim = RobotSim("digit_like")
    rng = np.random.default_rng(3)
    qpos, qvel = _random_state(sim.model, rng)
    sim.set_state(qpos, qvel)
    q, v = sim.pinocchio_state()
    q2, v2 = mujoco_to_pinocchio(qpos, qvel)
    np.testing.assert_array_equal(q, q2)
    np.testing.assert_array_equal(v, v2)
    sim.set_pinocchio_state(q, v)
    np.testing.assert_allclose(sim.qpos, qpos, atol=1e-12)
    np.testing.assert_allclose(sim.qvel, qvel, atol=1e-12)


def test_slide_ball_base_and_ball_joints_of_the_reference_map_too(shared_digit_xml: Path) -> None:
    """The Digit v3 layout: 3 slides + a ball base (a composite joint in Pinocchio) and ball-jointed rods."""
    _compare(
        shared_digit_xml,
        bodies=["torso/base", "left-leg/toe-roll", "right-leg/tarsus", "left-leg/achilles-rod"],
        sites=["left-foot-mid"],
        seeds=range(2),
    )


def test_configuration_map_is_the_state_maps_and_round_trips(shared_digit_xml: Path) -> None:
    """configuration_to_pinocchio (the WBC's loop reference) is to_pinocchio's q, for the free-joint
    digit_like and for the slide+ball base and ball-jointed rods of Digit v3; to_mujoco inverts it."""
    for path in (load_robot("digit_like").mjcf_path, shared_digit_xml):
        model = mujoco.MjModel.from_xml_path(str(path))
        smap = StateMap(model)
        qpos, qvel = _random_state(model, np.random.default_rng(11))
        q, v = smap.to_pinocchio(qpos, qvel)
        assert smap.configuration_to_pinocchio(qpos).tobytes() == q.tobytes()
        assert np.array_equal(qpos[smap.permutation], q)
        back, _ = smap.to_mujoco(q, v)
        np.testing.assert_array_equal(back, qpos)
        with pytest.raises(StateError, match="qpos"):
            smap.to_pinocchio(qpos[:-1], qvel)
