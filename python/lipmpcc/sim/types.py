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

__all__ = ["FramePose", "Measurement", "FallCriterion", "SimLog", "FALL_HEIGHT_FRACTION"]

#: Default fall height as a fraction of the robot's standing torso height above the soles (the torso
#: origin; digit_like stands at 1.0 m and falls below 0.55 m).
FALL_HEIGHT_FRACTION = 0.55


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
        touched: (left, right) vertical force above ``contact_threshold`` at some simulation step
            since the previous measurement or now (a foot that touched between two control ticks,
            e.g. a toe whose contact flickers between the 2 kHz substeps); None: not measured (then
            ``contact``).
        peak_normal_force: (left, right) the largest vertical contact force [N] over those steps
            (None: not measured).
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
    touched: tuple[bool, bool] | None = None
    peak_normal_force: tuple[float, float] | None = None


@dataclass(frozen=True)
class FallCriterion:
    """When the robot counts as fallen (any condition).

    Attributes:
        min_height: torso origin height above the lower sole [m] below which the robot has fallen;
            None: the robot's own (its layout's ``fall_height``, else :data:`FALL_HEIGHT_FRACTION` of
            its standing torso height), resolved by the simulator (``RobotSim.fall_criterion``).
        max_tilt: largest angle between the torso z axis and the vertical [rad].
        non_foot_contact: a contact of a robot geom other than the feet with the ground or an
            obstacle (any geom that is not the robot's) counts as a fall.
        self_contact: also a contact between two robot geoms other than the feet (off by default:
            convex hulls of neighbouring links overlap in a normal gait).
    """

    min_height: float | None = None
    max_tilt: float = 1.0
    non_foot_contact: bool = True
    self_contact: bool = False

    def __post_init__(self) -> None:
        if self.min_height is not None and not (
            isinstance(self.min_height, (int, float)) and math.isfinite(self.min_height) and self.min_height > 0
        ):
            raise ParameterError("min_height", self.min_height, "a positive height [m] or None (the robot's own)")
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
