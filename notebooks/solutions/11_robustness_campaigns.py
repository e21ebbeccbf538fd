"""Solutions of notebook 11 (robustness campaigns: reading and designing a sweep)."""

from __future__ import annotations

import math
import sqlite3


def wilson(k, n, z=1.959963984540054):
    """(low, high): the Wilson score interval of k successes in n cases (NaN, NaN when n is 0)."""
    if n <= 0:
        return (math.nan, math.nan)
    p = k / n
    d = 1.0 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z / d * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (max(0.0, c - h), min(1.0, c + h))


def cases_needed(p, half_width):
    """Smallest number of cases n whose 95 % Wilson interval at the rate p has a half-width <= half_width."""
    n = 1
    while True:
        lo, hi = wilson(p * n, n)
        if (hi - lo) / 2 <= half_width:
            return n
        n += 1


def largest_recoverable(db_path, planner, direction_deg):
    """Largest impulse [N s] at and below which every done case of (planner, direction [deg]) survived."""
    db = sqlite3.connect(db_path)
    try:
        rows = db.execute(
            "SELECT impulse_Ns, min(survived) FROM cases WHERE status = 'done' AND planner = ? "
            "AND abs(p_direction - ?) < 1e-9 GROUP BY round(impulse_Ns, 9) ORDER BY impulse_Ns",
            (planner, math.radians(direction_deg)),
        ).fetchall()
    finally:
        db.close()
    best = 0.0
    for impulse, all_survived in rows:
        if not all_survived:
            break
        best = impulse
    return best
