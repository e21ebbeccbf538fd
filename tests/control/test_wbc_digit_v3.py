"""lipmpcc.control.wbc on the reference Digit v3 (../shared; skipped when absent): the controller reads the
slide+ball base, the six ``<equality connect>`` loops (Pinocchio's point-anchor constraints), the passive
springs and the geared motors; its QP sizes and a standing tick; its loop and drift terms agree with
MuJoCo and with finite differences; a file that lacks what the stack needs gets an error naming it."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from lipmpcc.exceptions import RobotDescriptionError
from lipmpcc.robots import load_robot
from lipmpcc.robots.layouts import DIGIT_V3_STANDING_QPOS


@pytest.fixture(scope="module")
def v3_wbc():
    from lipmpcc.control.wbc import WholeBodyController

    from ..conftest import SHARED_DIGIT

    if not SHARED_DIGIT.exists():
        pytest.skip(f"reference model not found at {SHARED_DIGIT}")
    return WholeBodyController(load_robot(SHARED_DIGIT))


def test_digit_v3_model_structure(v3_wbc) -> None:
    wbc = v3_wbc
    m = wbc.model
    mj = mujoco.MjModel.from_xml_path(str(wbc.description.mjcf_path))
    assert (wbc.nq, wbc.nv, wbc.nu) == (61, 54, 20)
    assert m.base_kind == "slide+ball" and m.base_quaternion_idx == 3 and m.base_idx_v == 0
    # six loops: the connect constraints' bodies carry the anchors' joints
    assert wbc.n_loops == 6 and m.n_loop_rows == 18
    for e, loop in enumerate(m.loops):
        for k in (1, 2):
            body = mj.eq_obj1id[e] if k == 1 else mj.eq_obj2id[e]
            assert mj.joint(mj.body_jntadr[body]).name == loop[f"joint{k}"]
        np.testing.assert_allclose(loop["anchor1"], mj.eq_data[e, :3], atol=1e-12)
    # passive springs (stiffness, no motor) are the rigid ones; motors act through their gear
    B = wbc.actuation
    springs = [mj.joint(j).name for j in range(mj.njnt) if mj.jnt_stiffness[j] > 0]
    assert sorted(springs) == sorted(f"{s}-leg/{j}" for s in ("left", "right") for j in ("shin", "heel-spring"))
    assert list(m.rigid_springs) == [0, 1, 2, 3]
    for a in range(mj.nu):
        dof = mj.jnt_dofadr[mj.actuator_trnid[a, 0]]
        assert B[dof, a] == pytest.approx(mj.actuator_gear[a, 0])
    lo, hi = wbc.u_limits
    np.testing.assert_allclose(hi, mj.actuator_ctrlrange[:, 1])  # torque limit = gear × ctrlrange
    # the dependent (eliminated) coordinates are unactuated and outside the base
    dep = np.asarray(m.dependent_idx_v)
    assert dep.size == 18 + 4 and np.all(dep >= 6) and not np.any(B[dep])
    assert m.qp_coordinates["n"] == 54 - 22


def test_digit_v3_qp_sizes_and_standing_tick(v3_wbc) -> None:
    from lipmpcc.sim.robot_sim import RobotSim

    wbc = v3_wbc
    wbc.reset()
    sim = RobotSim(wbc.description)
    q, v = sim.pinocchio_state()
    out = wbc.solve(q, v, wbc.hold_reference(q))
    assert out.status == "solved" and not out.used_fallback
    qp = wbc.last_qp()
    # 32 independent accelerations + 2 wrenches; 12 unactuated rows (base, rod spins) + 12 no-slip
    assert (qp["n_var"], qp["n_eq"], qp["n_in"]) == (44, 24, 42)
    # the feet carry the weight; the springs hold it (their known torque plus a small holding torque)
    assert np.sum(out.wrenches[:, 2]) == pytest.approx(wbc.mass * 9.80665, rel=0.02)
    assert out.loop_forces.shape == (18,) and out.spring_torques.shape == (4,)
    lo, hi = wbc.u_limits
    assert np.all(out.tau >= lo) and np.all(out.tau <= hi)


def test_digit_v3_loop_and_drift_terms_match_mujoco_and_finite_differences(v3_wbc) -> None:
    """J_loop v is MuJoCo's relative anchor velocity; γ_loop, the COM and the sole drifts equal
    d/dt (J) v by central differences (Pinocchio's dAg v misses the slide+ball base's bias)."""
    import pinocchio as pin

    from lipmpcc.sim.robot_sim import RobotSim

    wbc = v3_wbc
    sim = RobotSim(wbc.description)
    rng = np.random.default_rng(5)
    qvel = rng.normal(0.0, 0.3, sim.model.nv)
    sim.set_state(np.asarray(DIGIT_V3_STANDING_QPOS), qvel)
    q, v = sim.pinocchio_state()
    t = wbc.evaluate(q, v)
    model = pin.buildModelFromMJCF(str(wbc.description.mjcf_path))
    h = 1e-6

    def jac(key, qq):
        return np.asarray(wbc.evaluate(qq, np.zeros(wbc.nv))[key])

    qp, qm = pin.integrate(model, q, v * h), pin.integrate(model, q, -v * h)
    nl = wbc.n_loop_rows
    for key, drift, rows in (("J_loop", "gamma_loop", slice(0, nl)), ("J_com", "drift_com", slice(None))):
        fd = (jac(key, qp)[rows] - jac(key, qm)[rows]) / (2 * h) @ v
        np.testing.assert_allclose(np.asarray(t[drift])[rows], fd, atol=1e-5, err_msg=drift)
    for i in range(2):
        fd = (np.asarray(wbc.evaluate(qp)["J_sole"][i]) - np.asarray(wbc.evaluate(qm)["J_sole"][i])) / (2 * h) @ v
        # the classical acceleration of the sole adds ω × v to d/dt (J v)
        vel = np.asarray(t["vel_sole"][i])
        np.testing.assert_allclose(np.asarray(t["drift_sole"][i])[3:], fd[3:], atol=1e-5)
        np.testing.assert_allclose(np.asarray(t["drift_sole"][i])[:3], fd[:3], atol=1e-5 + 1e-9 * np.linalg.norm(vel))
    # MuJoCo: the anchors' relative velocity is J_loop v (the loops are closed at this pose)
    mujoco.mj_forward(sim.model, sim.data)
    rel = np.zeros((6, 3))
    for e in range(6):
        vel = []
        ends = ((sim.model.eq_obj1id[e], sim.model.eq_data[e, :3]), (sim.model.eq_obj2id[e], sim.model.eq_data[e, 3:6]))
        for body, anchor in ends:
            jacp = np.zeros((3, sim.model.nv))
            point = sim.data.xpos[body] + sim.data.xmat[body].reshape(3, 3) @ anchor
            mujoco.mj_jac(sim.model, sim.data, jacp, None, point, body)
            vel.append(jacp @ sim.data.qvel)
        rel[e] = vel[0] - vel[1]
    np.testing.assert_allclose(np.asarray(t["J_loop"])[:nl] @ v, rel.ravel(), atol=1e-9)
    np.testing.assert_allclose(np.asarray(t["loop_residual"]), 0.0, atol=1e-8)


def _v3_variant(tmp_path: Path, shared: Path, old: str, new: str) -> Path:
    """A temporary copy of the reference file (outside the project) with one edit; meshes from ../shared."""
    text = shared.read_text().replace("meshdir='stl'", f"meshdir='{shared.parent / 'stl'}'")
    assert old in text
    path = tmp_path / "digit_variant.xml"
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize(
    "old, new, expected",
    [
        ("<connect name='left-leg/toe-b-rod'", "<weld name='left-leg/toe-b-rod'", "weld"),
        ("<connect name='left-leg/toe-b-rod' body1", "<connect name='left-leg/toe-b-rod' active='false' body1",
         "active"),
        ("<joint type='ball' limited='false'/>", "", "floating base"),
        ("left-leg/achilles-rod' type='ball' axis='0 0 1'  stiffness='0'",
         "left-leg/achilles-rod' type='ball' axis='0 0 1'  stiffness='5'", "hinge or slide"),
    ],
    ids=["weld-equality", "inactive-loop", "slides-without-ball", "ball-spring"],
)
def test_a_file_that_lacks_what_the_stack_needs_is_named(
    shared_digit_xml: Path, tmp_path: Path, old: str, new: str, expected: str
) -> None:
    from lipmpcc.control.wbc import WholeBodyController

    path = _v3_variant(tmp_path, shared_digit_xml, old, new)
    desc = load_robot(path, layout="digit_v3", standing_qpos=None)  # (one variant has fewer coordinates)
    with pytest.raises(RobotDescriptionError) as err:
        WholeBodyController(desc)
    assert expected in str(err.value) and str(path) in str(err.value)
