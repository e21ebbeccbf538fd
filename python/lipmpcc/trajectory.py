"""Deprecated: moved to :mod:`lipmpcc.control.references` in lipmpcc 0.2 (see CHANGELOG.md); removed in 0.3.

``PhaseClock`` → :mod:`lipmpcc.models.phase`; the angle helpers ``wrap_angle``, ``unwrap_near``, ``yaw_rotation`` → :mod:`lipmpcc.rotations`;
``lip_omega`` → :func:`lipmpcc.models.lip.omega`; ``lip_solution``, ``dcm`` →
:mod:`lipmpcc.models.lip`; ``GRAVITY`` → :mod:`lipmpcc.conventions`.
"""

from ._deprecated import forward

__getattr__, __dir__ = forward(__name__, "lipmpcc.control.references", renames={
    "PhaseClock": "lipmpcc.models.phase:PhaseClock",
    "wrap_angle": "lipmpcc.rotations:wrap_angle",
    "unwrap_near": "lipmpcc.rotations:unwrap_near",
    "yaw_rotation": "lipmpcc.rotations:yaw_rotation",
    "lip_omega": "lipmpcc.models.lip:omega",
    "lip_solution": "lipmpcc.models.lip:lip_solution",
    "dcm": "lipmpcc.models.lip:dcm",
    "GRAVITY": "lipmpcc.conventions:GRAVITY",
})
