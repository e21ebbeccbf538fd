"""The whole-body references of one tick, evaluated from the gait state.

:class:`WholeBodyReferences` reads the :class:`~lipmpcc.loops.fullbody.gait.Gait` (it never changes
it) and writes the loop's one :class:`~lipmpcc.control.wbc_types.PackedWbcReference` (the whole-body
reference as the flat buffer the C++ controller reads, no packing per tick), reused every tick:

- COM: the standing COM (``STAND``), the quintic shift (``SHIFT``) or the LIP about the stance foot
  (``DOUBLE``, ``SINGLE``), at constant height;
- torso: upright, at the gait's heading reference; in ``SINGLE`` the step's torso heading, rate and
  acceleration;
- swing foot (``SINGLE``): the step trajectory's position, velocity, acceleration and yaw;
- contacts: both feet, or the stance foot alone in ``SINGLE``; with ``load_ramp`` > 0 the normal force
  of the foot that touched down last is bounded by ``1.5 · weight · max(0.05, (t − t_td) / load_ramp)``
  until that ramp reaches 1.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...conventions import LEFT, RIGHT
from ...control.references import StepReference
from ...control.tick_references import compiled_tick_references
from ...rotations import yaw_rotation
from ...control.wbc_types import PackedWbcReference, WbcReference
from .gait import Gait, GaitMode

__all__ = ["TickReferences", "WholeBodyReferences", "fill_swing_reference"]

_NAN3 = np.full(3, np.nan)
_NO_LOAD_BOUND = (math.inf, math.inf)


class TickReferences(NamedTuple):
    """What one evaluation gives the loop besides the :class:`~lipmpcc.control.wbc_types.WbcReference` it wrote.

    Attributes:
        torso_yaw: the torso heading reference [rad] (the loop commits it to the gait).
        com: COM position reference (3,) [m].
        swing_pos: swing-foot position reference (3,) [m] (NaN in double support).
        phase: step phase τ [-] (NaN in double support).
    """

    torso_yaw: float
    com: np.ndarray
    swing_pos: np.ndarray
    phase: float


def fill_swing_reference(ref: WbcReference | PackedWbcReference, i: int, r: StepReference) -> None:
    """Write the swing foot's references ``r`` into row ``i`` (0 left, 1 right) of the per-foot
    fields of the (reused) whole-body reference ``ref`` (world frame).

    The foot turns about the vertical only: the angular velocity and acceleration rows get their
    z component [rad/s, rad/s²]; their x and y components are never written (they stay 0).
    """
    ref.foot_pos[i] = r.swing_pos
    ref.foot_vel[i] = r.swing_vel
    ref.foot_acc[i] = r.swing_acc
    ref.foot_rot[i] = yaw_rotation(r.swing_yaw)
    ref.foot_angvel[i, 2] = r.swing_yaw_rate
    ref.foot_angacc[i, 2] = r.swing_yaw_acc


class WholeBodyReferences:
    """Evaluates the references of a tick from ``gait`` into :attr:`ref` (see the module doc).

    Args:
        gait: the gait whose state is read.
        arm_posture: arm joint angles held throughout [rad].
        stand_com: the standing COM (2,) [m] (the reference in ``STAND``).
        com_height: constant COM height [m].
        weight: the robot's weight [N] (the scale of the load ramp).
        load_ramp: time over which a touching-down foot's normal-force bound ramps up [s] (0: none).
    """

    def __init__(self, gait: Gait, arm_posture: np.ndarray, stand_com: np.ndarray, com_height: float,
                 weight: float, load_ramp: float) -> None:
        self.gait = gait
        self.ref = PackedWbcReference(arm_posture)
        self.com_height = com_height
        self.weight = weight
        self.load_ramp = load_ramp
        self._stand_com = np.array([stand_com[0], stand_com[1], com_height])
        self._zero3 = np.zeros(3)
        # torso yaw rate and acceleration (0, 0, ψ̇) [rad/s], (0, 0, ψ̈) [rad/s²]: z rewritten each swing tick
        self._yaw_rates = (np.zeros(3), np.zeros(3))
        self._rot_yaw: float | None = None  # the heading of the cached rotation (compared by identity)
        self._rot = np.eye(3)
        self._compiled = compiled_tick_references()  # None: the Python path below in every mode

    def evaluate(self, t: float, yaw_ref: float) -> TickReferences:
        """The references at ``t`` [s], written into :attr:`ref`; ``yaw_ref``: the torso heading
        reference [rad] outside single support."""
        gait, ref, zero3 = self.gait, self.ref, self._zero3
        mode = gait.mode
        if self._compiled is not None and (mode is GaitMode.SINGLE or mode is GaitMode.DOUBLE):
            return self._evaluate_compiled(t, yaw_ref, mode is GaitMode.SINGLE)
        contacts = (True, True)
        swing_pos = _NAN3
        phase = math.nan
        if mode is GaitMode.STAND:
            com, com_vel, com_acc = self._stand_com, zero3, zero3
        elif mode is GaitMode.SHIFT:
            x, dx, ddx = gait.shift.evaluate(t)
            com = np.array([x[0], x[1], self.com_height])
            com_vel = np.array([dx[0], dx[1], 0.0])
            com_acc = np.array([ddx[0], ddx[1], 0.0])
        else:
            com, com_vel, com_acc = gait.lip.evaluate(t)
        if mode is GaitMode.SINGLE:
            r = gait.step.evaluate(t)
            swing = gait.swing
            contacts = (swing != LEFT, swing != RIGHT)
            phase = r.tau
            swing_pos = r.swing_pos
            fill_swing_reference(ref, gait.swing_index, r)
            yaw_ref = r.torso_yaw
            torso_angvel, torso_angacc = self._yaw_rates
            torso_angvel[2] = r.torso_yaw_rate
            torso_angacc[2] = r.torso_yaw_acc
        else:
            torso_angvel = torso_angacc = zero3
        if yaw_ref is not self._rot_yaw:
            self._rot = yaw_rotation(yaw_ref)
            self._rot_yaw = yaw_ref
        bound = self._normal_force_bound(t, mode) if self.load_ramp > 0.0 else _NO_LOAD_BOUND
        ref.write(contacts, com, com_vel, com_acc, self._rot, torso_angvel, torso_angacc, bound)
        return TickReferences(yaw_ref, com, swing_pos, phase)

    def _evaluate_compiled(self, t: float, yaw_ref: float, single: bool) -> TickReferences:
        """:meth:`evaluate` in ``DOUBLE`` or ``SINGLE`` (``single``) by one compiled call
        (:mod:`lipmpcc.control.tick_references`): the same numbers to the bit."""
        gait, ref = self.gait, self.ref
        step = gait.step.compiled_state() if single else None
        com, swing_pos, phase, yaw = self._compiled(t, gait.lip.compiled_state(), step, gait.swing_index, yaw_ref,
                                                    ref.buf, ref.feet)
        if single:
            swing = gait.swing
            contacts = (swing != LEFT, swing != RIGHT)
        else:
            contacts, swing_pos, yaw, phase = (True, True), _NAN3, yaw_ref, math.nan
        mode = GaitMode.SINGLE if single else GaitMode.DOUBLE
        ref.set_support(contacts, self._normal_force_bound(t, mode) if self.load_ramp > 0.0 else _NO_LOAD_BOUND)
        return TickReferences(yaw, com, swing_pos, phase)

    def _normal_force_bound(self, t: float, mode: GaitMode) -> tuple[float, float]:
        """(left, right) bound on the normal forces [N] with a load ramp (``load_ramp`` > 0): the
        ramp of the stance foot after a touch-down, else none."""
        gait = self.gait
        if mode is not GaitMode.STAND and gait.touchdowns:
            ramp = (t - gait.t_td) / self.load_ramp
            if ramp < 1.0:
                bound = max(0.05, ramp) * 1.5 * self.weight
                return (bound, math.inf) if gait.stance == LEFT else (math.inf, bound)
        return _NO_LOAD_BOUND
