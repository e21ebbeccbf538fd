"""The flat per-tick reference (:class:`PackedWbcReference`): the controller gives the same output to the bit
as for the same values in a :class:`WbcReference`, in every support mode; fields are views of one buffer in
the C++ layout; bad writes raise."""

from __future__ import annotations

import numpy as np
import pytest

import lipmpcc._wbc as _wbc
from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.control.wbc_types import PACKED_REFERENCE_FIXED_SIZE, PackedWbcReference, WbcReference
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.robots import load_robot
from lipmpcc.rotations import yaw_rotation
from lipmpcc.sim.robot_sim import RobotSim

MODES = ((True, True), (True, False), (False, True))
ARRAY_FIELDS = ("com_pos", "com_vel", "com_acc", "torso_rot", "torso_angvel", "torso_angacc", "foot_pos", "foot_vel",
                "foot_acc", "foot_rot", "foot_angvel", "foot_angacc", "arm_posture")


def _random_reference(rng: np.random.Generator, wbc: WholeBodyController, q: np.ndarray,
                      contact: tuple[bool, bool]) -> WbcReference:
    """A reference near the state ``q`` with random offsets (every field set)."""
    ref = wbc.hold_reference(q, contact)
    ref.com_pos = ref.com_pos + rng.normal(0.0, 0.02, 3)
    ref.com_vel, ref.com_acc = rng.normal(0.0, 0.2, 3), rng.normal(0.0, 0.5, 3)
    ref.torso_rot = yaw_rotation(float(rng.normal(0.0, 0.1))) @ np.asarray(ref.torso_rot)
    ref.torso_angvel, ref.torso_angacc = rng.normal(0.0, 0.1, 3), rng.normal(0.0, 0.3, 3)
    ref.foot_pos = np.asarray(ref.foot_pos) + rng.normal(0.0, 0.02, (2, 3))
    ref.foot_vel, ref.foot_acc = rng.normal(0.0, 0.2, (2, 3)), rng.normal(0.0, 0.5, (2, 3))
    ref.foot_rot = np.stack([yaw_rotation(float(rng.normal(0.0, 0.1))) for _ in range(2)])
    ref.foot_angvel = np.column_stack([np.zeros((2, 2)), rng.normal(0.0, 0.2, 2)])
    ref.foot_angacc = np.column_stack([np.zeros((2, 2)), rng.normal(0.0, 0.5, 2)])
    ref.arm_posture = np.asarray(ref.arm_posture) + rng.normal(0.0, 0.05, len(ref.arm_posture))
    ref.max_normal_force = (float(rng.uniform(200.0, 800.0)), np.inf)
    return ref


def _packed_copy(ref: WbcReference) -> PackedWbcReference:
    packed = PackedWbcReference(ref.arm_posture)
    for name in ARRAY_FIELDS + ("max_normal_force", "contact"):
        setattr(packed, name, getattr(ref, name))
    return packed


def test_packed_layout_matches_the_compiled_controller() -> None:
    assert PACKED_REFERENCE_FIXED_SIZE == _wbc.PACKED_REFERENCE_FIXED_SIZE
    packed = PackedWbcReference(np.array([0.1, -0.2]))
    assert packed.buf.size == PACKED_REFERENCE_FIXED_SIZE + 2
    packed.com_vel[:] = [1.0, 2.0, 3.0]
    packed.torso_rot[0, 1] = 7.0
    packed.foot_rot[1, 2, 0] = 5.0
    packed.foot_angacc[0, 2] = -4.0
    buf = packed.packed(double_support=False)
    assert buf[3:6].tolist() == [1.0, 2.0, 3.0] and buf[9 + 1] == 7.0
    assert buf[24 + 24 + 9 + 6] == 5.0 and buf[24 + 23] == -4.0  # right foot rot row 2 col 0; left angacc z
    assert buf[-2:].tolist() == [0.1, -0.2] and buf[72:74].tolist() == [np.inf, np.inf]
    ds = packed.packed(double_support=True)  # the fixed block a WbcReference is packed with
    assert ds[24 + 24 + 9 + 6] == 0.0 and ds[24 + 24 + 17] == 1.0 and ds[24 + 23] == 0.0
    assert packed.foot_rot[1, 2, 0] == 5.0  # the feet block itself is kept


@pytest.mark.parametrize("contact", MODES)
def test_packed_reference_gives_the_same_output_to_the_bit(contact: tuple[bool, bool]) -> None:
    robot = load_robot("digit_like")
    wbc = WholeBodyController(robot)
    rng = np.random.default_rng(7)
    sim = RobotSim(robot)
    sim.reset(robot.standing_reset)
    m = sim.measure()
    for _ in range(3):
        v = m.v + rng.normal(0.0, 0.05, m.v.shape)
        ref = _random_reference(rng, wbc, m.q, contact)
        wbc.reset()
        a = wbc.solve(m.q, v, ref)
        wbc.reset()
        b = wbc.solve(m.q, v, _packed_copy(ref))
        assert a.status_code == b.status_code and a.used_fallback == b.used_fallback
        for name in ("tau", "qdd", "wrenches", "loop_forces"):
            assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name


def test_bad_writes_raise() -> None:
    packed = PackedWbcReference(np.zeros(2))
    with pytest.raises(InvalidInputError, match="com_pos"):
        packed.com_pos = np.zeros(4)
    with pytest.raises(InvalidInputError, match="contact"):
        packed.contact = (True,)
    with pytest.raises(InvalidInputError, match="nonsense"):
        packed.nonsense = 1.0
    with pytest.raises(InvalidInputError, match="arm_posture"):
        PackedWbcReference(np.zeros((2, 2)))
    wbc = WholeBodyController(load_robot("digit_like"))
    q = np.zeros(wbc.nq)
    q[wbc.base_quaternion_index + 3] = 1.0
    with pytest.raises(InvalidInputError, match="arm_posture"):
        wbc.solve(q, np.zeros(wbc.nv), PackedWbcReference(np.zeros(wbc.n_arm + 1)))
