"""Control: the walking references and the whole-body controller that tracks them.

- :mod:`~lipmpcc.control.references`: COM, swing-foot and torso-heading references over a step
  (:class:`StepTrajectory`, :class:`LipComReference`, ...; the step phase is
  :class:`lipmpcc.models.phase.PhaseClock`);
- :mod:`~lipmpcc.control.wbc_types`: the controller's parameters, reference and output
  (:class:`WbcParams`, :class:`WbcReference`, :class:`WbcOutput`, ...);
- :mod:`~lipmpcc.control.wbc`: :class:`WholeBodyController`, the validating face of the C++ QP
  ``lipmpcc._wbc``.

The names below are imported on first use (the controller loads its compiled module then).
"""

from __future__ import annotations

from .._lazy import lazy_exports

__all__ = [
    "LipComReference",
    "Quintic",
    "SwingParams",
    "StepReference",
    "StepTrajectory",
    "TaskGains",
    "PostureGains",
    "WbcParams",
    "WbcReference",
    "PackedWbcReference",
    "WbcTaskErrors",
    "WbcOutput",
    "WholeBodyController",
]

_HOME = {
    **dict.fromkeys(("LipComReference", "Quintic", "SwingParams", "StepReference", "StepTrajectory"),
                    "references"),
    **dict.fromkeys(("TaskGains", "PostureGains", "WbcParams", "WbcReference", "PackedWbcReference", "WbcTaskErrors",
                     "WbcOutput"),
                    "wbc_types"),
    "WholeBodyController": "wbc",
}


__getattr__, __dir__ = lazy_exports(__name__, _HOME, globals())
