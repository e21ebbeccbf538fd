"""lipmpcc.sim.robot_sim: RobotSim, the MuJoCo plant (loading, contacts, pushes, falls, logs, measurements,
stepping) on both paths of its tick. (The tick itself: test_tick.py; rendering: test_render.py.)"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, ModelFileError, ParameterError, StateError
from lipmpcc.push import Push
from lipmpcc.robots import digit_like_paths, load_robot
from lipmpcc.sim import _tick
from lipmpcc.sim.robot_sim import RobotSim
from lipmpcc.sim.types import FallCriterion

from .tick_paths import measurement_bytes, python_path_sim

G = 9.80665


@pytest.fixture
def sim() -> RobotSim:
    return RobotSim("digit_like")


def _standing_controller(sim: RobotSim):
    """Joint PD about the keyframe plus the torques that balance gravity there (a stand-in for the WBC)."""
    m, d = sim.model, sim.data
    sim.forward()
    jac = []
    for s in ("left_sole", "right_sole"):
        jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        mujoco.mj_jacSite(m, d, jp, jr, m.site(s).id)
        jac += [jp, jr]
    J = np.vstack(jac)
    bias = d.qfrc_bias.copy()
    wrench = np.linalg.lstsq(J[:, :6].T, bias[:6], rcond=None)[0]
    tau_ff = bias[6:] - J[:, 6:].T @ wrench
    q0 = d.qpos[7:].copy()
    kp = np.array([1000, 600, 1000, 1000, 200, 200] * 2 + [200] * 8, dtype=float)
    kd = 0.6 * np.sqrt(kp)

    def control(s: RobotSim) -> np.ndarray:
        return tau_ff + kp * (q0 - s.data.qpos[7:]) - kd * s.data.qvel[6:]

    return control


# ------------------------------------------------------------------------------------------------
# loading and reset
# ------------------------------------------------------------------------------------------------
def test_loads_digit_like_at_2khz_standing_on_both_feet(sim: RobotSim) -> None:
    assert sim.timestep == pytest.approx(0.0005) and sim.nu == 20
    assert mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_GEOM, "lipmpcc_floor") < 0  # the scene's floor is used
    key = sim.model.key("stand")
    np.testing.assert_array_equal(sim.qpos, key.qpos)
    assert sim.contact_state() == (True, True)
    assert not sim.fallen() and sim.fall_reason() is None
    (pl, Rl), (pr, Rr) = sim.foot_poses()
    assert pl[1] > 0.1 and pr[1] < -0.1 and abs(pl[2]) < 1e-3 and abs(pr[2]) < 1e-3
    np.testing.assert_allclose(Rl, np.eye(3), atol=1e-6)
    com = sim.com()
    assert 0.9 < com[2] < 1.0 and np.linalg.norm(com[:2] - 0.5 * (pl + pr)[:2]) < 5e-3


def test_user_mjcf_without_floor_gets_one_and_custom_timestep(tmp_path: Path) -> None:
    robot_xml, _ = digit_like_paths()
    sim = RobotSim(robot_xml, timestep=0.001)  # the robot file alone has no floor
    assert sim.timestep == pytest.approx(0.001)
    assert mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_GEOM, "lipmpcc_floor") >= 0
    sim.step(np.zeros(sim.nu), 5)
    assert sim.contact_state() == (True, True)


def test_simulators_share_the_descriptions_compiled_scene_as_their_own_copies() -> None:
    """RobotSim starts from a copy of the description's compiled scene (no compile of its own): equal
    to the model MuJoCo compiles from the file, and changing one simulator's model changes neither
    the description's nor another simulator's."""
    robot = load_robot("digit_like")
    compiled = []
    original = mujoco.MjSpec.compile

    def counting(spec: mujoco.MjSpec) -> mujoco.MjModel:
        compiled.append(spec)
        return original(spec)

    mujoco.MjSpec.compile = counting
    try:
        a, b = RobotSim(robot), RobotSim(robot, timestep=0.001)
    finally:
        mujoco.MjSpec.compile = original
    assert compiled == []  # both from the description's scene_model
    assert a.model is not robot.scene_model and b.model is not a.model
    fresh = mujoco.MjSpec.from_file(str(robot.scene_path)).compile()
    for name in ("body_mass", "geom_size", "qpos0", "dof_damping", "actuator_ctrlrange", "key_qpos"):
        assert getattr(a.model, name).tobytes() == getattr(fresh, name).tobytes(), name
    a.model.opt.gravity[:] = 0.0
    assert robot.scene_model.opt.gravity[2] == b.model.opt.gravity[2] == fresh.opt.gravity[2] != 0.0
    assert (a.timestep, b.timestep, robot.scene_model.opt.timestep) == (0.0005, 0.001, fresh.opt.timestep)


def test_scene_editor_adds_terrain_that_the_feet_touch() -> None:
    def add_stone(spec: mujoco.MjSpec) -> None:
        spec.worldbody.add_geom(
            name="stone", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.3, 0.3, 0.05], pos=[3.0, 0.0, 0.05]
        )

    sim = RobotSim("digit_like", scene_editor=add_stone)
    assert mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_GEOM, "stone") >= 0
    qpos = sim.qpos
    qpos[0] += 3.0  # stand on the stone, 0.1 m up
    qpos[2] += 0.1
    sim.set_state(qpos)
    sim.step(np.zeros(sim.nu), 4)
    assert sim.contact_state() == (True, True)


def test_bad_model_and_parameters_give_clear_errors(tmp_path: Path) -> None:
    with pytest.raises(ModelFileError, match="not found"):
        RobotSim(tmp_path / "missing.xml")
    bad = tmp_path / "bad.xml"
    bad.write_text("<mujoco><worldbody><geom type='sphere'/></worldbody>")
    with pytest.raises(ModelFileError, match="bad.xml"):
        RobotSim(bad)
    with pytest.raises(ParameterError, match="timestep"):
        RobotSim("digit_like", timestep=0.0)
    with pytest.raises(InvalidInputError, match="keyframe"):
        RobotSim("digit_like").reset("crouch")


def test_step_validates_motor_commands(sim: RobotSim) -> None:
    with pytest.raises(ValueError, match=r"shape \(20,\)"):
        sim.step(np.zeros(19))
    with pytest.raises(ValueError, match="finite"):
        sim.step(np.r_[np.zeros(19), np.nan])
    with pytest.raises(ValueError, match="positive integer"):
        sim.step(np.zeros(20), 0)
    t0 = sim.time
    sim.step(np.zeros(20), 3)
    assert sim.time == pytest.approx(t0 + 3 * sim.timestep)


# ------------------------------------------------------------------------------------------------
# contacts, pushes, falls
# ------------------------------------------------------------------------------------------------
def test_standing_under_pd_the_feet_carry_the_weight(sim: RobotSim) -> None:
    ok = sim.run(1.0, _standing_controller(sim), steps_per_control=5, progress=False)
    assert ok and sim.time == pytest.approx(1.0)
    fl, fr = sim.normal_forces()
    weight = sim.description.total_mass * G
    assert fl + fr == pytest.approx(weight, rel=0.01)
    assert fl == pytest.approx(fr, rel=0.1)
    (cl, cr) = sim.contact_forces()
    np.testing.assert_allclose(cl + cr, [0.0, 0.0, weight], atol=0.01 * weight)


def test_push_changes_momentum_by_force_times_duration_in_its_window_only() -> None:
    sim = RobotSim("digit_like")
    sim.model.opt.gravity[:] = 0.0
    qpos = sim.qpos
    qpos[2] += 0.5  # in the air, no contact
    sim.set_state(qpos)
    force = np.array([30.0, -20.0, 10.0])
    push = sim.add_push(force, t_start=0.01, duration=0.05)
    assert isinstance(push, Push) and push.body == "torso" and sim.pushes == (push,)
    assert push.force == (30.0, -20.0, 10.0) and push.t_end == 0.01 + 0.05 and push.step is None
    v0 = sim.com_velocity()
    sim.step(np.zeros(20), 10)  # up to t = 0.005: before the window
    np.testing.assert_allclose(sim.com_velocity(), v0, atol=1e-9)
    assert not np.any(sim.data.xfrc_applied)
    sim.step(np.zeros(20), 60)  # t = 0.035: inside
    np.testing.assert_allclose(sim.data.xfrc_applied[sim.model.body("torso").id, :3], force)
    np.testing.assert_allclose(sim.push_force(), force)
    sim.step(np.zeros(20), 200)  # t = 0.135: after
    assert not np.any(sim.data.xfrc_applied)
    dv = sim.com_velocity() - v0
    # (to 1e-4: the implicit damping integration perturbs momentum at the 1e-6 level)
    np.testing.assert_allclose(dv, force * 0.05 / sim.description.total_mass, rtol=1e-4)


def test_push_validation() -> None:
    sim = RobotSim("digit_like")
    with pytest.raises(InvalidInputError):
        sim.add_push([1.0, 2.0], 0.0, 0.1)
    with pytest.raises(InvalidInputError):
        sim.add_push([1.0, 2.0, 3.0], 0.0, -0.1)
    with pytest.raises(InvalidInputError, match="body"):
        sim.add_push([1.0, 2.0, 3.0], 0.0, 0.1, body="tail")


def test_without_torques_the_robot_falls_and_it_is_detected(sim: RobotSim) -> None:
    ok = sim.run(3.0, controller=None, progress=False)
    assert not ok and sim.fallen() and sim.time < 3.0
    assert "above the lower sole" in sim.fall_reason() or "tilted" in sim.fall_reason()


def test_tilt_criterion() -> None:
    sim = RobotSim("digit_like", fall=FallCriterion(max_tilt=0.5))
    qpos = sim.qpos
    angle = 0.6  # about the y axis
    qpos[3:7] = [np.cos(angle / 2), 0.0, np.sin(angle / 2), 0.0]
    qpos[2] += 0.5
    sim.set_state(qpos)
    assert "tilted" in sim.fall_reason()
    with pytest.raises(ParameterError):
        FallCriterion(min_height=-1.0)


# ------------------------------------------------------------------------------------------------
# rates, logs
# ------------------------------------------------------------------------------------------------
def test_rates_and_the_old_push_and_state_map_names_still_work_with_a_warning() -> None:
    from lipmpcc.robots.state_map import mujoco_to_pinocchio
    from lipmpcc.sim import robot_sim

    with pytest.warns(DeprecationWarning, match="Rates"):
        Rates = robot_sim.Rates
    r = Rates()
    assert (r.sim_hz, r.wbc_hz, r.sim_steps_per_wbc) == (2000.0, 400.0, 5)
    assert r.timestep == pytest.approx(0.0005)
    assert Rates(wbc_hz=2000.0).sim_steps_per_wbc == 1
    assert Rates(wbc_hz=400.0, planner_hz=25.0).wbc_ticks_per_plan == 16
    with pytest.raises(ParameterError, match="divisor"):
        Rates(wbc_hz=300.0)
    with pytest.raises(ParameterError, match="at most"):
        Rates(wbc_hz=4000.0)
    with pytest.warns(DeprecationWarning, match=r"lipmpcc\.push\.Push"):
        assert robot_sim.Push is Push
    with pytest.warns(DeprecationWarning, match="state_map"):
        assert robot_sim.mujoco_to_pinocchio is mujoco_to_pinocchio
    from lipmpcc.sim import types

    for name in ("Measurement", "FramePose", "FallCriterion", "SimLog"):
        with pytest.warns(DeprecationWarning, match=rf"robot_sim\.{name} moved to lipmpcc\.sim\.types"):
            assert getattr(robot_sim, name) is getattr(types, name)
    with pytest.raises(AttributeError):
        robot_sim.no_such_name


def test_log_records_every_n_steps_and_saves(tmp_path: Path) -> None:
    sim = RobotSim("digit_like", log_every=10)
    sim.add_push([5.0, 0.0, 0.0], 0.0, 0.02)
    sim.step(np.zeros(20), 100)
    arrays = sim.log.arrays()
    assert len(sim.log) == 10
    np.testing.assert_allclose(arrays["t"], np.arange(1, 11) * 10 * sim.timestep)
    assert arrays["qpos"].shape == (10, sim.model.nq) and arrays["contact"].shape == (10, 2)
    np.testing.assert_allclose(arrays["push"][:3, 0], 5.0)  # t = 0.005, 0.010, 0.015
    assert np.all(arrays["push"][4:] == 0.0)  # t >= 0.025
    path = sim.log.save(tmp_path / "log.npz")
    with np.load(path) as z:
        np.testing.assert_array_equal(z["qpos"], arrays["qpos"])
    sim.reset()
    assert len(sim.log) == 0 and sim.pushes == ()




# ------------------------------------------------------------------------------------------------
# the reference Digit v3 (bring-your-own-Digit input)
# ------------------------------------------------------------------------------------------------
def test_reference_digit_v3_loads_standing(shared_digit_xml: Path) -> None:
    sim = RobotSim(load_robot(shared_digit_xml))
    assert sim.model.nq == 61 and sim.nu == 20
    assert mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_GEOM, "lipmpcc_floor") < 0  # it has its own floor
    sim.step(np.zeros(20), 20)  # from its settled standing pose; under zero torques the legs fold after ~35 steps
    assert sim.contact_state() == (True, True)
    q, v = sim.pinocchio_state()
    assert q.shape == (61,) and v.shape == (54,)
    assert not sim.fallen()
    np.testing.assert_allclose(sim.torque_to_ctrl(np.full(20, 80.0))[0], 1.0)  # hip roll gear 80


def test_measure_equals_the_individual_accessors() -> None:
    sim = RobotSim("digit_like")
    sim.add_push([40.0, -10.0, 0.0], t_start=0.002, duration=0.01)
    sim.step(np.zeros(20), 37)  # sinking under zero torques: feet in contact, state moving
    m = sim.measure()
    q, v = sim.pinocchio_state()
    np.testing.assert_array_equal(m.q, q)
    np.testing.assert_array_equal(m.v, v)
    np.testing.assert_array_equal(m.com, sim.com())
    np.testing.assert_array_equal(m.com_vel, sim.com_velocity())
    torso = sim.torso_pose()
    np.testing.assert_array_equal(m.torso.position, torso.position)
    np.testing.assert_array_equal(m.torso.rotation, torso.rotation)
    for got, want in zip(m.feet, sim.foot_poses()):
        np.testing.assert_array_equal(got.position, want.position)
        np.testing.assert_array_equal(got.rotation, want.rotation)
    assert m.contact == sim.contact_state() == (True, True)
    assert m.normal_force == sim.normal_forces()
    assert m.time == sim.time
    # fresh arrays: stepping on does not change a measurement already taken
    com = m.com.copy()
    sim.step(np.zeros(20), 10)
    np.testing.assert_array_equal(m.com, com)


@pytest.mark.parametrize("compiled", [True, False])
def test_measure_hands_the_state_to_on_state_before_the_forward_pass(monkeypatch: pytest.MonkeyPatch, compiled: bool) -> None:
    """measure(on_state=f) calls f(q, v) once, with the measurement's own q and v, before the
    forward pass (the simulator's derived fields are still those of the previous state); the
    measurement is the one without on_state, and a diverged state raises before f is called."""
    if compiled and _tick.TICK is None:
        pytest.skip("lipmpcc._mjtick is not built (or not usable with this MuJoCo)")
    make = (lambda: RobotSim("digit_like")) if compiled else (lambda: python_path_sim(monkeypatch, "digit_like"))
    a, b = make(), make()
    assert a.compiled_tick == compiled
    for s in (a, b):
        s.add_push([40.0, -10.0, 0.0], t_start=0.002, duration=0.01)
        s.measure()
        s.step(np.zeros(20), 37)
    calls = []
    stale_xpos = a.data.xpos.copy()
    ma = a.measure(on_state=lambda q, v: calls.append((q, v, a.data.xpos.copy())))
    mb = b.measure()
    assert measurement_bytes(ma) == measurement_bytes(mb)
    assert len(calls) == 1 and calls[0][0] is ma.q and calls[0][1] is ma.v
    np.testing.assert_array_equal(calls[0][2], stale_xpos)  # before the forward pass
    a.data.qvel[3] = np.nan
    with pytest.raises(StateError):
        a.measure(on_state=lambda q, v: calls.append(q))
    assert len(calls) == 1


def test_one_step_call_equals_single_steps_with_a_push_starting_and_ending_inside_it() -> None:
    a, b = RobotSim("digit_like"), RobotSim("digit_like")
    for sim in (a, b):
        sim.add_push([30.0, 20.0, 0.0], t_start=0.0012, duration=0.0011)  # starts and ends mid-call
    a.step(np.zeros(20), 10)
    for _ in range(10):
        b.step(np.zeros(20), 1)
    np.testing.assert_array_equal(a.qpos, b.qpos)
    np.testing.assert_array_equal(a.qvel, b.qvel)
    assert a.time == b.time


def test_stepping_after_a_measurement_matches_mj_step_bit_for_bit() -> None:
    """measure() computes the state's derived fields as mj_step1 + the acceleration stages, and the next
    step() then runs only mj_step2 for its first substep: the trajectory is MuJoCo's own, to the bit,
    also with a push acting and when qpos is edited by hand in between (then a full mj_step runs)."""
    a, b = RobotSim("digit_like"), RobotSim("digit_like")
    for s in (a, b):
        s.reset("stand")
        s.add_push(np.array([30.0, -10.0, 0.0]), 0.004, 0.003)
    m, d = b.model, b.data
    rng = np.random.default_rng(0)
    for k in range(12):
        ctrl = rng.uniform(-0.2, 0.2, a.nu) * a.model.actuator_ctrlrange[:, 1]
        a.measure()  # primes the split step
        if k == 7:  # a hand edit after the measurement must not reuse the stale stages
            a.data.qpos[7] += 1e-3
            d.qpos[7] += 1e-3
        a.step(ctrl, 5)
        d.ctrl[:] = ctrl
        for _ in range(5):
            b._apply_pushes()
            mujoco.mj_step(m, d)
        assert np.array_equal(a.data.qpos, d.qpos) and np.array_equal(a.data.qvel, d.qvel)
    assert a.data.time == d.time


# ------------------------------------------------------------------------------------------------
# bad arguments on both paths of the tick (compiled lipmpcc._mjtick and Python)
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("compiled", [True, False])
def test_step_names_the_bad_argument_on_both_paths(monkeypatch: pytest.MonkeyPatch, compiled: bool) -> None:

    if compiled and _tick.TICK is None:
        pytest.skip("lipmpcc._mjtick is not built (or not usable with this MuJoCo)")
    sim = RobotSim("digit_like") if compiled else python_path_sim(monkeypatch, "digit_like")
    assert sim.compiled_tick == compiled
    q0 = sim.data.qpos.copy()
    with pytest.raises(InvalidInputError, match=r"(?s)^ctrl = .*shape \(20,\)"):
        sim.step(np.zeros((20, 1)))
    with pytest.raises(InvalidInputError, match=r"(?s)^ctrl = .*a real vector"):
        sim.step(np.array(["a"] * 20))
    with pytest.raises(InvalidInputError, match=r"(?s)^ctrl = .*non-finite entries at \[3\]"):
        sim.step(np.r_[np.zeros(3), np.inf, np.zeros(16)], 5)
    with pytest.raises(InvalidInputError, match=r"(?s)^ctrl = .*finite"):  # ctrl is checked before n
        sim.step(np.full(20, np.nan), 0)
    with pytest.raises(InvalidInputError, match=r"^n = "):
        sim.step(np.zeros(20), 1.5)
    assert sim.data.qpos.tobytes() == q0.tobytes() and sim.time == 0.0  # nothing was stepped
    sim.step(np.zeros(20, dtype=np.float32), 2)  # converted
    sim.step(np.zeros(40)[::2], 2)  # a strided view
    assert sim.time == pytest.approx(4 * sim.timestep)
    if compiled:  # the binding itself names its arguments
        with pytest.raises(ValueError, match="^ctrl: expected"):
            sim._tick.step(np.zeros(19), 1)
        with pytest.raises(ValueError, match="^n: expected"):
            sim._tick.step(np.zeros(20), 0)


@pytest.mark.parametrize("compiled", [True, False])
def test_divergence_is_told_after_mujoco_resets_itself(monkeypatch: pytest.MonkeyPatch, compiled: bool,
                                                      tmp_path: Path) -> None:
    """A 1e9 N push makes MuJoCo's acceleration blow up: MuJoCo warns (mjWARN_BADQACC), resets the state
    and the time to 0 and goes on. ``divergence()`` tells it on both paths of the tick, until ``reset``."""
    if compiled and _tick.TICK is None:
        pytest.skip("lipmpcc._mjtick is not built (or not usable with this MuJoCo)")
    monkeypatch.chdir(tmp_path)  # MuJoCo writes its warning to MUJOCO_LOG.TXT in the working directory
    sim = RobotSim("digit_like") if compiled else python_path_sim(monkeypatch, "digit_like")
    assert sim.divergence() is None and sim.warning_messages() == []
    sim.add_push([1e9, 0.0, 0.0], t_start=0.01, duration=0.1)
    sim.measure()
    for _ in range(10):
        sim.step(np.zeros(20), 5)
    assert sim.divergence() == "bad acceleration"
    assert sim.time < 0.01  # MuJoCo started again from 0
    sim.reset()
    assert sim.divergence() is None


def test_divergence_without_mujocos_reset_is_a_non_finite_state(sim: RobotSim) -> None:
    sim.data.qvel[0] = np.inf
    assert sim.divergence() == "non-finite state"


def test_other_mujoco_warnings_are_one_line_each_with_their_count(sim: RobotSim) -> None:
    sim.data.warning[int(mujoco.mjtWarning.mjWARN_CONTACTFULL)].number = 3
    sim.data.warning[int(mujoco.mjtWarning.mjWARN_BADCTRL)].number = 1
    msgs = sim.warning_messages()
    assert msgs == [
        "MuJoCo: the contact buffer was full and contacts were dropped (mjWARN_CONTACTFULL) (3 times)",
        "MuJoCo: non-finite or huge motor commands were set to zero (mjWARN_BADCTRL) (1 time)",
    ]
    assert sim.divergence() is None  # warnings, not a divergence
    sim.reset()
    assert sim.warning_messages() == []


def test_run_stops_where_the_simulation_diverged(sim: RobotSim, monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.chdir(tmp_path)  # MuJoCo's MUJOCO_LOG.TXT
    sim.add_push([1e9, 0.0, 0.0], t_start=0.05, duration=0.1)
    assert sim.run(0.2, steps_per_control=5, progress=False, stop_on_fall=False) is False
    assert sim.divergence() == "bad acceleration" and sim.time < 0.05


def test_self_contact_is_not_a_fall_but_ground_contact_is(shared_g1) -> None:
    """G1's legs crossed (hip links touching): no fall by default, a fall with ``self_contact``; a hip
    link in the ground is a fall naming the body and the ground. The fall height is the layout's."""
    import mujoco

    for self_contact in (False, True):
        sim = RobotSim(shared_g1, fall=FallCriterion(self_contact=self_contact))
        assert sim.fall_criterion.min_height == pytest.approx(shared_g1.fall_height)
        q, m = sim.qpos, sim.model
        for name, angle in (("left_hip_roll_joint", -0.5), ("right_hip_roll_joint", 0.5)):
            q[m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)]] = angle
        q[2] += 0.3  # feet in the air
        sim.set_state(q)
        detail = sim.fall_detail()
        if self_contact:
            assert detail["kind"] == "contact" and "hip" in detail["body"] and "hip" in detail["contact"]
        else:
            assert detail is None and not sim.fallen()
        q[2] -= 0.7
        sim.set_state(q)
        detail = sim.fall_detail()
        assert detail["kind"] == "contact" and "floor" in detail["contact"] and detail["body"] in detail["reason"]


def test_default_fall_height_is_relative_to_the_standing_pose() -> None:
    sim = RobotSim(load_robot("digit_like", fall_height=None))
    (pl, _), (pr, _) = sim.foot_poses()
    standing = float(sim.torso_pose().position[2] - min(pl[2], pr[2]))
    assert sim.fall_criterion.min_height == pytest.approx(0.55 * standing)
    assert RobotSim("digit_like").fall_criterion.min_height == 0.55  # its layout's


@pytest.mark.parametrize("compiled", [True, False])
def test_touched_is_a_contact_at_any_substep_since_the_last_measurement(monkeypatch: pytest.MonkeyPatch,
                                                                        compiled: bool) -> None:
    """``Measurement.peak_normal_force`` over a 5-substep tick is the largest vertical foot force of the
    states the tick passed through (as measured one substep at a time), so a foot that touches and
    bounces off between two ticks is ``touched`` though not in ``contact`` at the tick; a reset forgets it."""
    if compiled and _tick.TICK is None:
        pytest.skip("lipmpcc._mjtick is not built")
    a = RobotSim("digit_like") if compiled else python_path_sim(monkeypatch, "digit_like")
    b = RobotSim("digit_like")
    for s in (a, b):  # the robot dropped from 2 cm, limp: the feet bounce
        q = s.qpos.copy()
        q[2] += 0.02
        s.set_state(q)
    a.measure()
    b.measure()
    zero = np.zeros(a.nu)
    seen_between = False
    for _ in range(80):
        forces = []
        a.step(zero, 5)
        for _ in range(5):
            b.step(zero, 1)
            forces.append(b.measure().normal_force)
        m = a.measure()
        assert m.normal_force == forces[-1]
        assert m.peak_normal_force == (max(f[0] for f in forces), max(f[1] for f in forces))
        assert m.touched == tuple(p > a.contact_threshold for p in m.peak_normal_force)
        seen_between |= any(t and not c for t, c in zip(m.touched, m.contact))
    assert seen_between  # the drop has a contact that a tick's own state misses
    a.reset()
    m = a.measure()
    assert m.peak_normal_force == m.normal_force
