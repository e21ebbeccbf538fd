"""Angles and rotations every layer uses: wrapping, yaw rotations, quaternions.

- :func:`wrap_angle`, :func:`unwrap_near`: angles [rad] to (−π, π] and next to a reference;
- :func:`yaw_rotation`, :func:`yaw_of_rotation`: a pure yaw about the world z axis and back;
- :func:`quat_wxyz_to_rot`: MuJoCo's quaternion (w, x, y, z) as a rotation matrix.
"""

from __future__ import annotations

import math

import numpy as np

from .exceptions import StateError

__all__ = ["wrap_angle", "unwrap_near", "yaw_rotation", "yaw_of_rotation", "quat_wxyz_to_rot"]


def wrap_angle(a: float | np.ndarray) -> float | np.ndarray:
    """Wrap an angle to (−π, π] [rad] (elementwise for an array)."""
    if np.ndim(a):
        return (np.asarray(a, dtype=float) + np.pi) % (2.0 * np.pi) - np.pi
    return float((a + math.pi) % (2.0 * math.pi) - math.pi)


def unwrap_near(angle: float, reference: float) -> float:
    """``angle`` shifted by a multiple of 2π to lie within π of ``reference`` [rad]."""
    return reference + float(wrap_angle(angle - reference))


def yaw_rotation(yaw: float) -> np.ndarray:
    """Rotation matrix (3×3) of a pure yaw [rad] about the world z axis."""
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0]).reshape(3, 3)


def yaw_of_rotation(R: np.ndarray) -> float:
    """Heading [rad] of a rotation matrix (3×3): the angle of its x axis in the world xy plane."""
    return math.atan2(R[1, 0], R[0, 0])


def quat_wxyz_to_rot(qw: float, qx: float, qy: float, qz: float) -> np.ndarray:
    """Rotation matrix (3×3) of the quaternion (w, x, y, z), normalised first.

    Raises:
        StateError: a zero (or non-finite-norm) quaternion.
    """
    n = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    if not n > 0.0:
        raise StateError("quaternion", (qw, qx, qy, qz), "a non-zero quaternion")
    qw, qx, qy, qz = qw / n, qx / n, qy / n, qz / n
    return np.array(
        [
            1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw),
            2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw),
            2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy),
        ]
    ).reshape(3, 3)
