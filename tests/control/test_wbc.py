"""lipmpcc.control.wbc: model construction, input validation, fallback on QP failure, contact switching,
and standing in MuJoCo (digit_like, 2 kHz simulation, 400 Hz controller)."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import mujoco
import numpy as np
import pytest

from lipmpcc.robots.wbc_model import wbc_model_data
from ..conftest import package_env

from lipmpcc.exceptions import (
    ConcurrentUseError,
    InvalidInputError,
    ModelFileError,
    ParameterError,
    RobotDescriptionError,
    StateError,
)
from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.control.wbc_types import PostureGains, TaskGains, WbcParams
from lipmpcc.robots import load_robot
from lipmpcc.sim.robot_sim import RobotSim

from ..conftest import SHARED_DIGIT

DATA = Path(__file__).resolve().parent / "data"
MINI = DATA / "mini_biped.xml"


def mini_description(**overrides):
    kw = dict(arm_joints=("left_shoulder_pitch", "right_shoulder_pitch"), foot_length=0.2, foot_width=0.1)
    kw.update(overrides)
    return load_robot(MINI, **kw)


@pytest.fixture(scope="module")
def mini():
    return WholeBodyController(mini_description())


@pytest.fixture(scope="module")
def digit():
    return WholeBodyController("digit_like")


def standing_state(wbc: WholeBodyController) -> tuple[np.ndarray, np.ndarray]:
    sim = RobotSim(wbc.description)
    sim.reset("stand")
    return sim.pinocchio_state()


# ------------------------------------------------------------------------------------------------
# Model
# ------------------------------------------------------------------------------------------------
def test_digit_like_model(digit):
    m = mujoco.MjModel.from_xml_path(str(digit.description.mjcf_path))
    assert (digit.nq, digit.nv, digit.nu, digit.n_arm) == (27, 26, 20, 8)
    assert digit.mass == pytest.approx(float(np.sum(m.body_mass)), rel=1e-9)
    B = digit.actuation
    # gear 1 motors, one per joint: B is a selection of the 20 joint velocities
    assert np.all(B[:6] == 0.0)
    np.testing.assert_array_equal(B[6:], np.eye(20))
    lo, hi = digit.u_limits
    np.testing.assert_allclose(lo, m.actuator_ctrlrange[:, 0])
    np.testing.assert_allclose(hi, m.actuator_ctrlrange[:, 1])
    # foot friction 1.0, pyramidal cone: the pyramid takes half of it
    assert digit.friction == pytest.approx(0.5)


def test_gear_enters_actuation(mini):
    """The mini biped's knees have gear 2: B holds the gear, u stays in ctrlrange."""
    m = mujoco.MjModel.from_xml_path(str(MINI))
    B = mini.actuation
    for a in range(m.nu):
        j = m.actuator_trnid[a, 0]
        assert B[m.jnt_dofadr[j], a] == pytest.approx(m.actuator_gear[a, 0])
    q, v = standing_state(mini)
    out = mini.solve(q, v, mini.hold_reference(q))
    assert out.status == "solved"
    np.testing.assert_allclose(out.tau_joint, B @ out.tau, atol=1e-12)


def test_kinematics_match_mujoco(mini):
    """Pinocchio (q, v) from RobotSim gives MuJoCo's COM, sole poses and sole velocities."""
    sim = RobotSim(mini.description)
    sim.reset("stand")
    rng = np.random.default_rng(3)
    qpos = sim.qpos
    qpos[:3] += rng.normal(0, 0.1, 3)
    quat = rng.normal(size=4)
    qpos[3:7] = quat / np.linalg.norm(quat)
    qpos[7:] += rng.normal(0, 0.2, sim.model.nq - 7)
    sim.set_state(qpos, rng.normal(0, 1.0, sim.model.nv))
    q, v = sim.pinocchio_state()
    t = mini.evaluate(q, v)
    np.testing.assert_allclose(t["com"], sim.com(), atol=1e-10)
    np.testing.assert_allclose(t["vcom"], sim.com_velocity(), atol=1e-10)
    m, d = sim.model, sim.data
    for i, site in enumerate(("left_sole", "right_sole")):
        sid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, site)
        np.testing.assert_allclose(t["p_sole"][i], d.site_xpos[sid], atol=1e-10)
        np.testing.assert_allclose(t["R_sole"][i], d.site_xmat[sid].reshape(3, 3), atol=1e-10)
        vel = np.zeros(6)  # MuJoCo: [angular; linear], world axes with flg_local = 0
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_SITE, sid, vel, 0)
        np.testing.assert_allclose(t["vel_sole"][i], np.r_[vel[3:], vel[:3]], atol=1e-9)
    # joint-space inertia (armature included) and gravity torques on the joints: the joint rows do
    # not depend on the base velocity convention
    sim.set_state(sim.qpos, np.zeros(sim.model.nv))
    t = mini.evaluate(*sim.pinocchio_state())
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    np.testing.assert_allclose(t["M"][6:, 6:], M[6:, 6:], atol=1e-10)
    np.testing.assert_allclose(t["h"][6:], d.qfrc_bias[6:], atol=1e-9)


def test_sole_frame_from_offset(mini):
    """Without sole sites, the sole frame is added on the foot body at sole_offset."""
    desc = mini_description(left_sole_site=None, right_sole_site=None, sole_offset=(0.02, 0.0, -0.05))
    wbc = WholeBodyController(desc)
    q, _ = standing_state(mini)
    a, b = mini.evaluate(q), wbc.evaluate(q)
    for i in range(2):
        np.testing.assert_allclose(a["p_sole"][i], b["p_sole"][i], atol=1e-12)
        np.testing.assert_allclose(a["J_sole"][i], b["J_sole"][i], atol=1e-12)


# ------------------------------------------------------------------------------------------------
# Validation
# ------------------------------------------------------------------------------------------------
def test_bad_state_raises_state_error(mini):
    q, v = standing_state(mini)
    ref = mini.hold_reference(q)
    bad_q = {
        "shape": np.zeros(mini.nq + 1),
        "dtype": q.astype(np.float32),
        "list": list(q),
        "non-contiguous": np.repeat(q, 2)[::2],
        "nan": np.where(np.arange(mini.nq) == 9, np.nan, q),
        "quaternion": np.where(np.arange(mini.nq) == 6, 2.0, q),
    }
    for what, value in bad_q.items():
        with pytest.raises(StateError, match=r"q") as info:
            mini.solve(value, v, ref)
        assert isinstance(info.value, ValueError), what
    with pytest.raises(StateError, match=rf"v = .*shape \({mini.nv},\)"):
        mini.solve(q, np.zeros(3), ref)
    with pytest.raises(StateError, match=r"^v"):
        mini.solve(q, np.full(mini.nv, np.inf), ref)


@pytest.mark.parametrize(
    "field, value, match",
    [
        ("com_pos", np.zeros(2), r"ref\.com_pos .*shape \(3,\)"),
        ("com_vel", np.array([0.0, np.nan, 0.0]), r"ref\.com_vel"),
        ("torso_rot", 2.0 * np.eye(3), r"(?s)ref\.torso_rot.*rotation"),
        ("torso_angacc", "fast", r"ref\.torso_angacc"),
        ("arm_posture", np.zeros(5), r"ref\.arm_posture .*shape \(2,\)"),
        ("contact", (True, True, False), r"ref\.contact"),
        ("max_normal_force", np.array([-1.0, 10.0]), r"ref\.max_normal_force"),
        ("foot_rot", np.zeros((2, 3, 3)), r"(?s)ref\.foot_rot.*rotation"),
        ("foot_pos", np.zeros(3), r"ref\.foot_pos .*shape \(2, 3\)"),
    ],
)
def test_bad_reference_raises(mini, field, value, match):
    q, v = standing_state(mini)
    ref = mini.hold_reference(q, contact=(True, False))  # left foot swings: its fields count
    if field == "contact":  # the reference refuses it when it is set (issue 14)
        with pytest.raises(InvalidInputError, match=r"WbcReference\.contact"):
            setattr(ref, field, value)
        object.__setattr__(ref, field, value)  # forced past the check: the controller still names it
    else:
        setattr(ref, field, value)
    with pytest.raises(InvalidInputError, match=match):
        mini.solve(q, v, ref)
    with pytest.raises(InvalidInputError, match="WbcReference"):
        mini.solve(q, v, {"com_pos": np.zeros(3)})


def test_bad_params():
    with pytest.raises(ParameterError, match="kp"):
        TaskGains(kp=-1.0)
    with pytest.raises(ParameterError, match="weight"):
        TaskGains(weight=(1.0, 2.0))
    with pytest.raises(ParameterError, match="qdd_regularization"):
        WbcParams(qdd_regularization=0.0)
    with pytest.raises(ParameterError, match="cop_safety_factor"):
        WbcParams(cop_safety_factor=1.5)
    with pytest.raises(ParameterError, match="qp_max_iter"):
        WbcParams(qp_max_iter=0)
    with pytest.raises(ParameterError, match="arm_posture.kd"):
        PostureGains(kd=float("nan"))
    with pytest.raises(ParameterError, match="params"):
        WholeBodyController(mini_description(), params={"com": 1})
    with pytest.raises(ParameterError, match="friction"):
        WholeBodyController(mini_description(), friction=-0.3)


def test_bad_models(tmp_path):
    with pytest.raises(ModelFileError):
        WholeBodyController(tmp_path / "missing.xml")
    desc = dataclasses.replace(mini_description(), torso_body="no_such_body")
    with pytest.raises(RobotDescriptionError, match="no_such_body"):
        WholeBodyController(desc)
    # a servo with activation dynamics is not a torque source
    text = MINI.read_text().replace(
        '<motor name="left_knee" joint="left_knee" gear="2" ctrlrange="-100 100"/>',
        '<general name="left_knee" joint="left_knee" dyntype="filter" gainprm="100" biastype="affine" '
        'biasprm="0 -100 0" ctrlrange="-1 1"/>',
    )
    servo = tmp_path / "servo.xml"
    servo.write_text(text)
    with pytest.raises(RobotDescriptionError, match="motor actuator.*left_knee"):
        WholeBodyController(mini_description().__class__(**{**dataclasses.asdict(mini_description()),
                                                             "mjcf_path": servo, "scene_path": servo}))


def test_position_servo_is_driven_as_a_torque_source(tmp_path):
    """A <position> servo with a force range becomes a motor: gain 1, no bias, ctrl bounded by the
    force range, and the controller's efforts for it are bounded the same way."""
    text = MINI.read_text().replace(
        '<motor name="left_knee" joint="left_knee" gear="2" ctrlrange="-100 100"/>',
        '<position name="left_knee" joint="left_knee" kp="100" ctrlrange="-1 1" forcerange="-70 70"/>',
    )
    servo = tmp_path / "servo.xml"
    servo.write_text(text)
    desc = load_robot(servo, arm_joints=("left_shoulder_pitch", "right_shoulder_pitch"), foot_length=0.2,
                      foot_width=0.1)
    assert any("position servo" in n and "forcerange" in n for n in desc.actuator_notes)
    k = desc.motor_names.index("left_knee")
    assert desc.torque_limits[k] == pytest.approx(70.0)
    data = wbc_model_data(desc)
    assert data.u_max[k] == pytest.approx(70.0) and data.u_min[k] == pytest.approx(-70.0)
    assert data.actuation_gains[k] == pytest.approx(1.0)
    WholeBodyController(desc)  # accepted


# ------------------------------------------------------------------------------------------------
# Fallback
# ------------------------------------------------------------------------------------------------
def test_infeasible_tick_falls_back_to_damped_last_efforts():
    wbc = WholeBodyController(mini_description(), WbcParams(fallback_damping=0.5))
    q, v = standing_state(wbc)
    ref = wbc.hold_reference(q)
    good = wbc.solve(q, v, ref)
    assert good.status == "solved" and not good.used_fallback and wbc.qp_failures == 0
    v_fast = v.copy()
    v_fast[6:] = 30.0  # Coriolis torques beyond the motor bounds: no feasible point
    bad = wbc.solve(q, v_fast, ref)
    assert bad.used_fallback and bad.status != "solved"
    assert wbc.qp_failures == 1
    lo, hi = wbc.u_limits
    expected = np.clip(good.tau - 0.5 * wbc.actuation.T @ v_fast, lo, hi)
    np.testing.assert_allclose(bad.tau, expected, atol=1e-12)
    assert np.all(bad.qdd == 0.0) and np.all(bad.wrenches == 0.0)
    # the loop goes on: the next feasible tick is solved again
    again = wbc.solve(q, v, ref)
    assert again.status == "solved" and not again.used_fallback
    np.testing.assert_allclose(again.tau, good.tau, atol=1e-6 * np.max(np.abs(good.tau)))
    assert wbc.qp_failures == 1
    wbc.reset()
    assert wbc.qp_failures == 0


def test_iteration_limit_counts_failures_without_raising():
    # proxsuite's limit (DAQP's, 20 x qp_max_iter active-set changes: tests/control/test_wbc_daqp.py)
    wbc = WholeBodyController(mini_description(), WbcParams(qp_max_iter=1, qp_solver="proxsuite"))
    q, v = standing_state(wbc)
    ref = wbc.hold_reference(q)
    for k in range(3):
        out = wbc.solve(q, v, ref)
        assert out.used_fallback and out.status == "max_iter_reached"
        assert np.all(np.isfinite(out.tau))
        assert wbc.qp_failures == k + 1


def broken_solver_controller(monkeypatch):
    """A mini controller, its standing state and hold reference, its good output, and then its C++ solver
    replaced by one whose every call raises (the fallback's case)."""
    wbc = WholeBodyController(mini_description())
    q, v = standing_state(wbc)
    ref = wbc.hold_reference(q)
    good = wbc.solve(q, v, ref)

    class Broken:
        qp_failures = 0

        def solve_packed(self, *args):
            raise RuntimeError("boom")

    monkeypatch.setattr(wbc, "_solver", Broken())
    return wbc, q, v, ref, good


def test_solver_exception_falls_back(mini, monkeypatch):
    """Even an unexpected exception from the extension does not escape solve()."""
    wbc, q, v, ref, good = broken_solver_controller(monkeypatch)
    out = wbc.solve(q, v, ref)
    assert out.used_fallback and out.status == "exception"
    np.testing.assert_allclose(out.tau, good.tau - wbc.params.fallback_damping * wbc.actuation.T @ v)
    assert wbc.qp_failures == 1


# ------------------------------------------------------------------------------------------------
# Closed loop in MuJoCo (digit_like)
# ------------------------------------------------------------------------------------------------
def _quintic(s: float) -> tuple[float, float, float]:
    s = min(max(s, 0.0), 1.0)
    return 10 * s**3 - 15 * s**4 + 6 * s**5, 30 * s**2 - 60 * s**3 + 30 * s**4, 60 * s - 180 * s**2 + 120 * s**3


def test_stands(digit):
    """2 s at 2 kHz with the WBC at 400 Hz holding the 'stand' keyframe: no fall, COM drift < 2 cm."""
    digit.reset()
    sim = RobotSim(digit.description)
    sim.reset("stand")
    q, v = sim.pinocchio_state()
    ref = digit.hold_reference(q)
    com0 = sim.com()
    for _ in range(800):  # 2 s: 800 ticks of 5 simulation steps
        q, v = sim.pinocchio_state()
        out = digit.solve(q, v, ref)
        sim.step(out.tau, 5)
        assert not sim.fallen(), sim.fall_reason()
    assert sim.time == pytest.approx(2.0)
    assert np.linalg.norm(sim.com() - com0) < 0.02
    assert digit.qp_failures == 0
    fl, fr = sim.normal_forces()
    assert fl + fr == pytest.approx(digit.mass * 9.80665, rel=0.02)


def test_contact_switching_lifts_a_foot(digit):
    """Double support -> COM over the right foot -> unload the left foot (normal-force ramp) ->
    single support with a 5 cm swing of the left foot -> touch-down -> back to double support."""
    digit.reset()
    sim = RobotSim(digit.description)
    sim.reset("stand")
    q, _ = sim.pinocchio_state()
    ref = digit.hold_reference(q)
    com_c = ref.com_pos.copy()
    p_left = ref.foot_pos[0].copy()
    com_r = com_c.copy()
    com_r[1] = ref.foot_pos[1][1]  # over the right sole
    shift, t_unload, t_lift, t_swing, height = 1.5, 1.5, 1.7, 1.2, 0.05
    max_lift, max_swing_err, max_com_err, n_single = 0.0, 0.0, 0.0, 0
    for _ in range(int(4.7 * 400)):
        t = sim.time
        if t < 3.0:
            s, ds, dds = _quintic(t / shift)
            a, b = com_c, com_r
        else:
            s, ds, dds = _quintic((t - 3.0) / shift)
            a, b = com_r, com_c
        ref.com_pos, ref.com_vel, ref.com_acc = a + s * (b - a), ds / shift * (b - a), dds / shift**2 * (b - a)
        swing = t_lift <= t < t_lift + t_swing
        ref.contact = (not swing, True)
        ramp = (t - t_unload) / (t_lift - t_unload)
        ref.max_normal_force = (400.0 * (1.0 - ramp) + 1.0 if 0.0 <= ramp < 1.0 else np.inf, np.inf)
        z = dz = ddz = 0.0
        if swing:
            w = 2 * np.pi / t_swing
            ph = (t - t_lift) * w
            z, dz, ddz = height * np.sin(ph / 2) ** 2, height * w / 2 * np.sin(ph), height * w**2 / 2 * np.cos(ph)
        ref.foot_pos = np.stack([p_left + [0.0, 0.0, z], ref.foot_pos[1]])
        ref.foot_vel = np.array([[0.0, 0.0, dz], [0.0, 0.0, 0.0]])
        ref.foot_acc = np.array([[0.0, 0.0, ddz], [0.0, 0.0, 0.0]])
        q, v = sim.pinocchio_state()
        out = digit.solve(q, v, ref)
        assert out.status == "solved"
        sim.step(out.tau, 5)
        assert not sim.fallen(), sim.fall_reason()
        max_com_err = max(max_com_err, float(np.linalg.norm(out.errors.com_pos)))
        if swing:
            n_single += 1
            assert np.all(out.wrenches[0] == 0.0)
            assert out.wrenches[1][2] == pytest.approx(digit.mass * 9.80665, rel=0.1)
            max_swing_err = max(max_swing_err, float(np.linalg.norm(out.errors.foot_pos[0])))
            max_lift = max(max_lift, float(sim.foot_poses()[0].position[2]))
    assert abs(n_single - t_swing * 400) <= 1
    assert max_lift > 0.045
    assert max_swing_err < 0.005
    assert max_com_err < 0.01
    assert digit.qp_failures == 0
    fl, fr = sim.normal_forces()
    assert fl > 100.0 and fr > 100.0  # both feet loaded again
    assert np.linalg.norm(sim.foot_poses()[0].position - p_left) < 0.005


# ------------------------------------------------------------------------------------------------
# prepare(): the dynamics stage ahead of solve (on a worker thread when threaded)
# ------------------------------------------------------------------------------------------------


def _same_output(a, b) -> None:
    for name in ("tau", "tau_joint", "qdd", "wrenches", "loop_forces", "spring_torques"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert (a.status, a.iterations, a.used_fallback) == (b.status, b.iterations, b.used_fallback)


@pytest.mark.parametrize("model", ["digit_like", "digit_v3"])
def test_prepare_gives_the_ticks_of_plain_solves(model):
    """Three controllers see the same 40 pushed-and-jittered states: one only solves, one prepares
    each state on its worker thread, one prepares another state first (so its solve must recompute).
    Their outputs are equal to the bit, and so are the terms the last QP was built from."""
    if model == "digit_v3":
        if not SHARED_DIGIT.exists():
            pytest.skip(f"reference model not found at {SHARED_DIGIT}")
        robot = load_robot(SHARED_DIGIT)
    else:
        robot = load_robot(model)
    plain = WholeBodyController(robot, threaded=False)
    ahead = WholeBodyController(robot, threaded=True)
    other = WholeBodyController(robot, threaded=True)
    assert (plain.threaded, ahead.threaded) == (False, True)
    sim = RobotSim(robot)
    sim.reset("stand")
    q, v = sim.pinocchio_state()
    ref = plain.hold_reference(q)
    rng = np.random.default_rng(3)
    sim.add_push(np.array([60.0, -40.0, 0.0]), t_start=0.0, duration=0.1)
    for _ in range(40):
        q, v = sim.pinocchio_state()
        v = v + 0.05 * rng.standard_normal(v.size)  # states the QP has not seen
        ahead.prepare(q, v)
        other.prepare(q, np.zeros_like(v))
        out_plain = plain.solve(q, v, ref)
        out_ahead = ahead.solve(q, v, ref)
        out_other = other.solve(q, v, ref)
        _same_output(out_plain, out_ahead)
        _same_output(out_plain, out_other)
        assert out_ahead.tick_time_us > 0.0
        sim.step(out_plain.tau, 5)
    assert plain.qp_failures == 0
    # the terms the last QP was built from (in the independent accelerations when loops are eliminated)
    terms = (lambda w: w.last_reduced_terms()) if plain.n_loops else (lambda w: w.last_terms())
    for wbc in (ahead, other):
        for key, val in terms(plain).items():
            np.testing.assert_array_equal(np.asarray(val), np.asarray(terms(wbc)[key]), err_msg=key)


def test_prepare_leaves_bad_states_to_solve(digit):
    """prepare() of a bad state does not raise from the worker; solve() names the bad value."""
    wbc = WholeBodyController(digit.description, threaded=True)
    q, v = standing_state(wbc)
    ref = wbc.hold_reference(q)
    bad_v = v.copy()
    bad_v[7] = np.nan
    wbc.prepare(q, bad_v)
    with pytest.raises(StateError, match="v"):
        wbc.solve(q, bad_v, ref)
    zero_quat = q.copy()
    zero_quat[3:7] = 0.0
    wbc.prepare(zero_quat, v)
    with pytest.raises(StateError, match=r"q\[3:7\]"):
        wbc.solve(zero_quat, v, ref)
    with pytest.raises(StateError, match="shape"):
        wbc.prepare(q[:-1], v)
    wbc.prepare(q, v)
    assert wbc.solve(q, v, ref).status == "solved"  # the worker is usable after bad states


def test_threaded_must_be_a_flag(digit):
    with pytest.raises(ParameterError, match="threaded"):
        WholeBodyController(digit.description, threaded="yes")


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork")
def test_threaded_controller_works_in_a_forked_child(digit):
    """A process forked after the worker thread started (multiprocessing's default on Linux) has no
    such thread: the controller there makes a new one instead of waiting forever, and its ticks
    equal the parent's."""
    wbc = WholeBodyController(digit.description, threaded=True)
    q, v = standing_state(wbc)
    ref = wbc.hold_reference(q)
    wbc.prepare(q, v)
    tau = wbc.solve(q, v, ref).tau.copy()
    wbc.prepare(q, v)  # the child starts with a prepared stage of the parent's worker
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # child: never return into pytest
        code = 1
        try:
            os.close(read)
            out = [wbc.solve(q, v, ref).tau]
            wbc.prepare(q, v)
            out.append(wbc.solve(q, v, ref).tau)
            os.write(write, np.concatenate(out).tobytes())
            code = 0
        finally:
            os._exit(code)
    os.close(write)
    deadline = time.monotonic() + 60.0
    while (done := os.waitpid(pid, os.WNOHANG))[0] == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    if done[0] == 0:
        os.kill(pid, 9)
        os.waitpid(pid, 0)
        pytest.fail("the forked child hung in the controller")
    data = b""
    while chunk := os.read(read, 1 << 16):
        data += chunk
    os.close(read)
    assert os.waitstatus_to_exitcode(done[1]) == 0
    got = np.frombuffer(data, dtype=np.float64).reshape(2, -1)
    np.testing.assert_array_equal(got[0], tau)
    np.testing.assert_array_equal(got[1], tau)


# ------------------------------------------------------------------------------------------------
# Threads: one controller per thread
# ------------------------------------------------------------------------------------------------
def test_a_call_while_another_thread_is_inside_raises_concurrent_use(digit):
    """While a call holds the controller (its lock taken, as by another thread), every call into C++
    refuses at once with a ConcurrentUseError that names the controller and the remedy; after it the
    controller works again."""
    q, v = standing_state(digit)
    ref = digit.hold_reference(q)
    digit._busy.acquire()
    try:
        calls = {"solve": lambda: digit.solve(q, v, ref), "prepare": lambda: digit.prepare(q, v),
                 "evaluate": lambda: digit.evaluate(q), "reset": digit.reset, "last_qp": digit.last_qp,
                 "last_terms": digit.last_terms, "last_reduced_terms": digit.last_reduced_terms}
        for method, call in calls.items():
            with pytest.raises(ConcurrentUseError, match="one controller per thread") as info:
                call()
            assert info.value.method == method and "WholeBodyController" in info.value.obj
            assert isinstance(info.value, RuntimeError)
    finally:
        digit._busy.release()
    assert not digit.solve(q, v, ref).used_fallback


_THREADS = textwrap.dedent("""
    import sys, threading
    from lipmpcc.control.wbc import WholeBodyController
    from lipmpcc.exceptions import ConcurrentUseError
    from lipmpcc.robots import load_robot
    from lipmpcc.sim.robot_sim import RobotSim
    desc = load_robot("digit_like")
    q, v = RobotSim(desc).pinocchio_state()
    shared = sys.argv[1] == "shared"
    one = WholeBodyController(desc)
    errors, done = [], []
    def work(c):
        try:
            ref = c.hold_reference(q)
            for _ in range(1500):
                c.prepare(q, v)
                c.solve(q, v, ref)
            done.append(1)
        except ConcurrentUseError as err:
            errors.append(str(err))
    go = threading.Barrier(2)
    def start(c):
        go.wait()
        work(c)
    ctrls = [one, one] if shared else [one, WholeBodyController(desc)]
    ts = [threading.Thread(target=start, args=(c,)) for c in ctrls]
    [t.start() for t in ts]
    [t.join() for t in ts]
    print(len(errors), len(done))
    print(errors[0] if errors else "")
""")


@pytest.mark.parametrize("mode", ["shared", "separate"])
def test_two_threads(mode):
    """One controller in two threads (a segfault before the guard): no crash, one thread gets the
    ConcurrentUseError and the other finishes; two controllers in two threads: both finish."""
    env = package_env()
    r = subprocess.run([sys.executable, "-c", _THREADS, mode], capture_output=True, text=True, timeout=300, env=env)
    assert r.returncode == 0, r.stderr[-2000:]
    n_err, n_done = map(int, r.stdout.split("\n")[0].split())
    if mode == "shared":
        assert (n_err, n_done) == (1, 1), r.stdout
        assert "use one controller per thread" in r.stdout
    else:
        assert (n_err, n_done) == (0, 2), r.stdout
def test_controller_options_of_the_wrong_type_are_named() -> None:
    import pytest

    from lipmpcc.control.wbc import WholeBodyController
    from lipmpcc.exceptions import ParameterError

    with pytest.raises(ParameterError, match=r"loop_formulation = \['a'\]"):
        WholeBodyController(loop_formulation=["a"])
    with pytest.raises(ParameterError, match=r"spring_model = \{\}"):
        WholeBodyController(spring_model={})


def test_a_swing_field_of_the_wrong_shape_is_named_in_double_support_too(digit):
    """In double support the swing fields are ignored by the QP, but a wrong one is still refused (it was
    accepted silently)."""
    q, v = standing_state(digit)
    ref = digit.hold_reference(q)
    ref.foot_pos = np.zeros(3)
    with pytest.raises(InvalidInputError, match=r"ref.foot_pos = 'array of shape \(3,\)': expected an array of shape \(2, 3\)"):
        digit.solve(q, v, ref)
