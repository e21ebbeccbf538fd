"""lipmpcc.loops.fullbody.angles: heading and tilt of a rotation matrix."""

from __future__ import annotations

import math

import pytest

from lipmpcc.loops.fullbody.angles import tilt_of, yaw_of
from lipmpcc.rotations import quat_wxyz_to_rot, yaw_rotation


@pytest.mark.parametrize("yaw", [0.0, 1.2, -3.0])
def test_yaw_of_a_yaw_rotation_and_no_tilt(yaw: float) -> None:
    R = yaw_rotation(yaw)
    assert yaw_of(R) == pytest.approx(yaw) and tilt_of(R) == 0.0


def test_tilt_is_the_angle_from_the_vertical_whatever_the_heading() -> None:
    pitch = quat_wxyz_to_rot(math.cos(0.2), 0.0, math.sin(0.2), 0.0)  # 0.4 rad about y
    assert tilt_of(pitch) == pytest.approx(0.4)
    assert tilt_of(yaw_rotation(2.0) @ pitch) == pytest.approx(0.4)
    assert yaw_of(yaw_rotation(2.0) @ pitch) == pytest.approx(2.0)
    upside_down = quat_wxyz_to_rot(0.0, 1.0, 0.0, 0.0)
    assert tilt_of(upside_down) == pytest.approx(math.pi)
    rounded = upside_down.copy()
    rounded[2, 2] = -1.0 - 1e-15  # round-off beyond [-1, 1] is clipped, not a math domain error
    assert tilt_of(rounded) == pytest.approx(math.pi)
