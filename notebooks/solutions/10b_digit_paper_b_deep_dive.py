"""Solutions of notebook 10b (the deep dive of paper B on the full-body robot: pushes and the ankle)."""

from __future__ import annotations

import math

import numpy as np


def cop_to_cancel(dz, sigma, lam, t, box):
    """CoP d (2,) [m] held from t [s] to the step's end that moves the touch-down DCM by −dz (2,) [m], clipped to ±box (2,) [m]."""
    gain = sigma * math.exp(-lam * t) - 1.0  # z¹(d) − z¹(0) = −d (σ e^{−λt} − 1); > 0 before the step's end
    box = np.abs(np.asarray(box, dtype=float))
    return np.clip(np.asarray(dz, dtype=float) / gain, -box, box)
