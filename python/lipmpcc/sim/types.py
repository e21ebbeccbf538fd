"""The simulator's values: frame poses, the measurement of one instant, the fall criterion, the log.

Positions [m], velocities [m/s], forces [N], angles [rad], times [s]; world frame unless noted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..exceptions import ParameterError

__all__ = ["FramePose", "Measurement", "FallCriterion", "SimLog"]


class FramePose(NamedTuple):
    """A frame in the world: ``position`` (3,) [m] and ``rotation`` (3, 3) (columns = frame axes)."""

    position: np.ndarray
    rotation: np.ndarray


class Measurement(NamedTuple):
    """The state a controller reads at one instant (world frame unless noted), from :meth:`~lipmpcc.sim.robot_sim.RobotSim.measure`.

    Attributes:
        time: simulated time [s].
        q, v: configuration and velocity in Pinocchio's convention (see
            :class:`~lipmpcc.robots.state_map.StateMap`).
        com: centre of mass (3,) [m]; com_vel: its velocity (3,) [m/s].
        torso: torso (floating base) frame.
        feet: (left, right) sole frames.
        contact: (left, right) vertical force above the simulator's ``contact_threshold``.
        normal_force: (left, right) vertical contact force [N].
    """

    time: float
    q: np.ndarray
    v: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray
    torso: FramePose
    feet: tuple[FramePose, FramePose]
    contact: tuple[bool, bool]
    normal_force: tuple[float, float]


@dataclass(frozen=True)
class FallCriterion:
    """When the robot counts as fallen (any condition).

    Attributes:
        min_height: torso origin height above the lower sole [m] below which the robot has fallen
            (standing: about 1.0 m for Digit).
        max_tilt: largest angle between the torso z axis and the vertical [rad].
        non_foot_contact: a contact of any robot geom other than the feet counts as a fall.
    """

    min_height: float = 0.55
    max_tilt: float = 1.0
    non_foot_contact: bool = True

    def __post_init__(self) -> None:
        if not (math.isfinite(self.min_height) and self.min_height > 0):
            raise ParameterError("min_height", self.min_height, "a positive height [m]")
        if not (math.isfinite(self.max_tilt) and 0 < self.max_tilt <= math.pi):
            raise ParameterError("max_tilt", self.max_tilt, "an angle in (0, pi] [rad]")


@dataclass
class SimLog:
    """Samples of a run (every ``every`` simulation steps), as lists; :meth:`arrays` stacks them.

    Fields per sample: ``t`` [s], ``qpos``, ``qvel``, ``ctrl``, ``com`` [m], ``com_vel`` [m/s],
    ``contact`` (left, right), ``normal_force`` (left, right) [N], ``push`` (3,) [N] on the torso.
    """

    every: int = 10
    t: list[float] = field(default_factory=list)
    qpos: list[np.ndarray] = field(default_factory=list)
    qvel: list[np.ndarray] = field(default_factory=list)
    ctrl: list[np.ndarray] = field(default_factory=list)
    com: list[np.ndarray] = field(default_factory=list)
    com_vel: list[np.ndarray] = field(default_factory=list)
    contact: list[tuple[bool, bool]] = field(default_factory=list)
    normal_force: list[tuple[float, float]] = field(default_factory=list)
    push: list[np.ndarray] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.t)

    def arrays(self) -> dict[str, np.ndarray]:
        """Every field as a NumPy array (first axis: sample)."""
        names = ("t", "qpos", "qvel", "ctrl", "com", "com_vel", "contact", "normal_force", "push")
        return {n: np.asarray(getattr(self, n)) for n in names}

    def save(self, path: str | Path) -> Path:
        """Write :meth:`arrays` to an ``.npz`` file."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez_compressed(path, **self.arrays())
        return path
