"""The full-body loop's per-tick references in C++ (``lipmpcc._wbc.tick_references``), bit-equal to the Python ones.

One compiled call per WBC tick evaluates the LIP COM reference (:meth:`LipComReference.evaluate
<lipmpcc.control.references.LipComReference.evaluate>`) and, in single support, the step trajectory
(:meth:`StepTrajectory.evaluate <lipmpcc.control.references.StepTrajectory.evaluate>`: swing foot and
torso heading, with its correction quintic), and writes them with their rotations into the flat
whole-body reference (:class:`~lipmpcc.control.wbc_types.PackedWbcReference`). The Python code stays the
readable reference; ``cpp/wbc/src/tick_references.cpp`` repeats it operation by operation.

Bit-equality rests on one property of the machine: numpy's small matrix product (the correction quintic,
``basis @ coefficients``) accumulating with fused multiply-adds in order, as OpenBLAS's kernels do on
x86-64 with FMA. :func:`compiled_tick_references` checks it once, on a probe trajectory evaluated both
ways, and returns None (the loop then uses the Python path) when the two differ by a bit, when
``lipmpcc._wbc`` is not built or when the environment variable ``LIPMPCC_TICK_REFERENCES`` is ``0``.
"""

from __future__ import annotations

import functools
import logging
import os
from typing import Callable

import numpy as np

from .references import LipComReference, StepTrajectory

__all__ = ["compiled_tick_references", "probe_times", "reproduces_python"]

_log = logging.getLogger(__name__)

#: ``tick_references(t, lip, step, swing_index, yaw_ref, packed, feet) -> (com, swing_pos, phase, torso_yaw)``
TickReferencesFn = Callable[..., tuple]


def probe_times() -> np.ndarray:
    """The probe's evaluation times [s]: before, across and after a re-timed, re-targeted step."""
    return np.concatenate([np.linspace(-0.01, 0.5, 97), [0.1, 0.23, 0.2999999, 0.3, 0.41, 0.45]])


def _probe_trajectory() -> tuple[LipComReference, StepTrajectory]:
    """A LIP segment and a step with two blended updates (a correction quintic in force)."""
    lip = LipComReference(0.93)
    lip.reset(0.013, np.array([0.11, -0.07]), np.array([0.53, 0.21]), np.array([0.02, -0.12]))
    step = StepTrajectory(0.0, 0.4, np.array([0.1, 0.2, 0.01]), 0.05, np.array([0.45, 0.18, 0.0]), 0.12, 0.03)
    step.update(0.1, target_pos=np.array([0.5, 0.15, 0.02]), target_yaw=0.2, t_end=0.42)
    step.update(0.23, target_pos=np.array([0.52, 0.16, 0.0]), t_end=0.39, torso_target_yaw=0.25)
    return lip, step


def reproduces_python(fn: TickReferencesFn) -> bool:
    """Whether ``fn`` gives the Python reference's numbers to the bit on the probe (COM, swing foot, heading)."""
    from ..rotations import yaw_rotation

    lip, step = _probe_trajectory()
    packed, feet = np.zeros(24), np.zeros((2, 24))
    for t in probe_times().tolist():
        com, swing_pos, phase, yaw = fn(t, lip.compiled_state(), step.compiled_state(), 1, 0.0, packed, feet)
        c, dc, ddc = lip.evaluate(t)
        r = step.evaluate(t)
        head = [c, dc, ddc, yaw_rotation(r.torso_yaw).ravel(), [0.0, 0.0, r.torso_yaw_rate], [0.0, 0.0, r.torso_yaw_acc]]
        row = [r.swing_pos, r.swing_vel, r.swing_acc, yaw_rotation(r.swing_yaw).ravel(), [0.0, 0.0, r.swing_yaw_rate],
               [0.0, 0.0, r.swing_yaw_acc]]
        expected = np.concatenate([*head, *row, c, r.swing_pos, [r.tau, r.torso_yaw]])
        got = np.concatenate([packed, feet[1], com, swing_pos, [phase, yaw]])
        if expected.tobytes() != got.tobytes():
            return False
    return True


@functools.cache
def compiled_tick_references() -> TickReferencesFn | None:
    """``lipmpcc._wbc.tick_references`` when it is built, not switched off (``LIPMPCC_TICK_REFERENCES=0``) and
    bit-equal to the Python reference on this machine (:func:`reproduces_python`); else None."""
    if os.environ.get("LIPMPCC_TICK_REFERENCES", "1") == "0":
        return None
    try:
        from .. import _wbc  # type: ignore[attr-defined]
    except ImportError:
        return None
    fn = getattr(_wbc, "tick_references", None)
    if fn is None:
        return None
    if not reproduces_python(fn):
        _log.info("the compiled tick references differ from the Python ones on this machine: using Python")
        return None
    return fn
