"""Solutions of notebook 10b (the deep dive of paper B on the full-body robot: pushes and the ankle)."""

from __future__ import annotations

import math

import numpy as np


def cop_dcm_shift(d, sigma, lam, t):
    """Change (2,) [m] of the next initial DCM z¹ that a CoP held at d (2,) [m] from t [s] into the step makes (σ = e^{λT})."""
    d = np.asarray(d, dtype=float)
    return d * (1.0 - sigma * math.exp(-lam * t))  # z¹(d) − z¹(0) = −σ e^{−λt} d + d
