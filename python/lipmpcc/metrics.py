"""Scalar metrics shared by every study (timings, errors, RMSE)."""

from __future__ import annotations

import math
from typing import Iterable

import numpy as np

__all__ = [
    "Z95",
    "wilson_interval",
    "timing_stats_ms",
    "rms",
    "max_abs",
]


def timing_stats_ms(times_s: Iterable[float]) -> dict[str, float]:
    """Median, 90th percentile and max of a list of durations.

    Args:
        times_s: durations [s].

    Returns:
        ``{"median": ..., "p90": ..., "max": ..., "n": ...}`` in [ms]; NaN when empty.
    """
    t = np.asarray(list(times_s), dtype=float) * 1e3
    if t.size == 0:
        return {"median": float("nan"), "p90": float("nan"), "max": float("nan"), "n": 0}
    return {
        "median": float(np.median(t)),
        "p90": float(np.percentile(t, 90)),
        "max": float(np.max(t)),
        "n": int(t.size),
    }


def rms(x: Iterable[float]) -> float:
    """Root mean square; NaN when empty."""
    a = np.asarray(list(x), dtype=float)
    return float(np.sqrt(np.mean(a**2))) if a.size else float("nan")


def max_abs(x: Iterable[float]) -> float:
    """Largest absolute value; NaN when empty."""
    a = np.asarray(list(x), dtype=float)
    return float(np.max(np.abs(a))) if a.size else float("nan")


Z95 = 1.959963984540054  # the normal quantile of a two-sided 95 % interval


def wilson_interval(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a proportion ``k``/``n`` (NaN, NaN when ``n`` is 0)."""
    if n <= 0:
        return (math.nan, math.nan)
    p = k / n
    d = 1.0 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))
