"""lipmpcc: bipedal footstep planning, reproduced.

Paper A: model predictive contouring control (MPCC) on the 3D-LIP.
Paper B: ALIP/DCM multi-step MPC with adaptive step duration on stepping stones.
"""

from __future__ import annotations

__version__ = "0.1.0"

from . import exceptions  # noqa: F401
from .config import fast_mode, set_fast_mode  # noqa: F401
