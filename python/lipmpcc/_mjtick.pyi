"""Type stubs of ``lipmpcc._mjtick``, the private C++ control tick of :class:`lipmpcc.sim.robot_sim.RobotSim`.

Written from ``cpp/sim/bindings/module.cpp``. It works on raw MuJoCo pointers
(``MjModel._address``, ``MjData._address``): use it only through ``RobotSim``, which keeps the
model, data and buffer alive and checks :data:`mujoco_version` against the running MuJoCo.
"""

import numpy as np
import numpy.typing as npt

_Array = npt.NDArray[np.float64]

#: ``mjVERSION_HEADER`` of the headers the module was compiled against
mujoco_version: int

def linked_mujoco_version() -> int:
    """``mj_version()`` of the libmujoco this module is linked to."""

def layout(nq: int, nv: int) -> dict[str, int | tuple[int, int]]:
    """Offsets of the measurement buffer: ``time``, ``q``, ``v``, ``com``, ``com_vel``,
    ``torso_pos``, ``torso_rot``, ``other``, ``size`` (ints) and ``foot_pos``, ``foot_rot``,
    ``force``, ``peak`` ((left, right) pairs; ``peak``: the largest vertical force on each foot [N] over the
    substep states since the previous measurement, this one included)."""

def rotate_transposed(w: float, x: float, y: float, z: float, v: npt.ArrayLike, fma_rotation: bool) -> _Array:
    """``R(w, x, y, z)ᵀ v`` (3,) as the state map computes it (with or without fused multiply-adds)."""

class TickConfig:
    torso: int
    sole_site: tuple[int, int]
    geom_side: list[int]
    geom_robot: list[int]
    perm: list[int]
    free_quat: list[tuple[int, int]]
    split: bool
    fma_rotation: bool
    def __init__(self) -> None: ...

class Tick:
    def __init__(self, model: int, data: int, config: TickConfig, buffer: _Array) -> None: ...
    def prime(self) -> None: ...
    def take_primed(self) -> bool: ...
    @property
    def primed(self) -> bool: ...
    def add_push(self, body: int, fx: float, fy: float, fz: float, t_start: float, t_end: float) -> None: ...
    def clear_pushes(self) -> None: ...
    def forget_contacts(self) -> None:
        """Forget the contact peaks (a reset or a new state)."""
    def step(self, ctrl: npt.ArrayLike, n: int) -> bool:
        """Hold ctrl for n steps (the feet's vertical contact forces read after each into the peaks); False
        (nothing done) when ctrl is not finite."""
    def state(self) -> int:
        """Pinocchio q and v into the buffer: 0, or 1 non-finite state / 2 zero quaternion."""
    def measure(self, stale: bool, mapped: bool = False) -> int:
        """Measurement into the buffer (mapped: state() returned 0 for this state): 0, or 1
        non-finite state / 2 zero quaternion (nothing done)."""
    def contacts(self) -> bool:
        """Per-foot contact forces into the buffer; True on a non-foot contact."""
