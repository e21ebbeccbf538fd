"""lipmpcc.rotations: angle wrapping, yaw rotations and MuJoCo's (w, x, y, z) quaternions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import StateError
from lipmpcc.rotations import quat_wxyz_to_rot, unwrap_near, wrap_angle, yaw_of_rotation, yaw_rotation


def test_wrap_angle_scalars_and_arrays() -> None:
    assert wrap_angle(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    assert wrap_angle(-0.25) == -0.25 and isinstance(wrap_angle(1.0), float)
    a = np.array([0.0, 2 * math.pi + 0.1, -2 * math.pi - 0.1, 7.0])
    np.testing.assert_allclose(wrap_angle(a), [0.0, 0.1, -0.1, 7.0 - 2 * math.pi], atol=1e-12)
    w = wrap_angle(np.linspace(-20, 20, 101))
    assert np.all((w >= -math.pi) & (w < math.pi))


def test_unwrap_near_moves_by_whole_turns() -> None:
    assert unwrap_near(0.1, 4 * math.pi) == pytest.approx(4 * math.pi + 0.1)
    assert unwrap_near(math.pi - 0.1, -math.pi) == pytest.approx(-math.pi - 0.1)
    assert abs(unwrap_near(5.0, 0.0) - 0.0) <= math.pi


@pytest.mark.parametrize("yaw", [0.0, 0.7, -2.5, math.pi / 2])
def test_yaw_rotation_round_trip(yaw: float) -> None:
    R = yaw_rotation(yaw)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(R) == pytest.approx(1.0) and R[2, 2] == 1.0
    np.testing.assert_allclose(R @ [1.0, 0.0, 0.0], [math.cos(yaw), math.sin(yaw), 0.0])
    assert yaw_of_rotation(R) == pytest.approx(yaw)


def test_quaternion_to_rotation() -> None:
    np.testing.assert_array_equal(quat_wxyz_to_rot(1.0, 0.0, 0.0, 0.0), np.eye(3))
    a = 0.8  # about z: the yaw rotation; scaling the quaternion changes nothing
    np.testing.assert_allclose(quat_wxyz_to_rot(3 * math.cos(a / 2), 0.0, 0.0, 3 * math.sin(a / 2)), yaw_rotation(a), atol=1e-15)
    R = quat_wxyz_to_rot(math.cos(0.3), math.sin(0.3), 0.0, 0.0)  # 0.6 rad about x
    np.testing.assert_allclose(R @ [0.0, 1.0, 0.0], [0.0, math.cos(0.6), math.sin(0.6)], atol=1e-15)
    with pytest.raises(StateError, match="quaternion"):
        quat_wxyz_to_rot(0.0, 0.0, 0.0, 0.0)
    with pytest.raises(StateError):
        quat_wxyz_to_rot(float("nan"), 0.0, 0.0, 1.0)
