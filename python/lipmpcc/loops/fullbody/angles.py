"""Angles the full-body loop reads off rotation matrices (world frame, z up)."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["yaw_of", "tilt_of"]


def yaw_of(rotation: np.ndarray) -> float:
    """Heading [rad] of a frame: the angle of its x axis about the world z axis."""
    return math.atan2(rotation[1, 0], rotation[0, 0])


def tilt_of(rotation: np.ndarray) -> float:
    """Angle [rad] between a frame's z axis and the vertical."""
    return math.acos(max(-1.0, min(1.0, float(rotation[2, 2]))))
