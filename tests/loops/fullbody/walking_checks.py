"""The walking runs' acceptance checks, shared by the digit_like and the Digit v3 tests
(:mod:`tests.loops.fullbody.test_loop`, :mod:`tests.loops.fullbody.test_loop_digit_v3`): the same criteria on any robot."""

from __future__ import annotations

import math

import numpy as np


def fit_circle(xy: np.ndarray) -> tuple[np.ndarray, float]:
    """Least-squares circle through points (n, 2): centre (2,) [m] and radius [m]."""
    A = np.c_[2 * xy, np.ones(len(xy))]
    sol, *_ = np.linalg.lstsq(A, (xy**2).sum(axis=1), rcond=None)
    centre = sol[:2]
    return centre, math.sqrt(sol[2] + centre @ centre)


def check_walked_10m_straight(res) -> None:
    """10 m at ≥ 0.5 m/s along +x, straight, upright, ≥ 40 steps landing where planned."""
    log = res.log
    assert not res.fell, f"fell at t = {res.fall_time:.2f} s"
    x = log.com[:, 0] - log.com[0, 0]
    assert x[-1] >= 10.0, f"walked {x[-1]:.2f} m"
    t10 = log.t[np.argmax(x >= 10.0)] - log.t[0]
    assert 10.0 / t10 >= 0.5, f"10 m in {t10:.1f} s"
    # straight: little lateral drift and heading change
    assert np.max(np.abs(log.com[:, 1] - log.com[0, 1])) < 0.3
    assert np.max(np.abs(np.unwrap(log.torso_yaw) - log.torso_yaw[0])) < 0.2
    assert res.min_base_height > log.base_height[0] - 0.1
    assert res.n_steps >= 40
    # footholds land where planned
    err = np.array([np.linalg.norm(td.pos[:2] - td.planned) for td in res.touchdowns])
    assert np.sqrt(np.mean(err**2)) < 0.02
    assert res.qp_failures <= 0.01 * len(log.t)


def check_full_circle(res, radius: float) -> None:
    """A full turn whose COM path after the start-up (3 s) fits a circle of ``radius`` ± 0.3 m."""
    log = res.log
    assert not res.fell, f"fell at t = {res.fall_time:.2f} s"
    yaw = np.unwrap(log.torso_yaw)
    assert yaw[-1] - yaw[0] >= 2 * math.pi, f"turned {yaw[-1] - yaw[0]:.2f} rad"
    xy = log.com[log.t - log.t[0] > 3.0, :2]
    centre, r = fit_circle(xy)
    assert abs(r - radius) < 0.3, f"radius {r:.2f} m"
    assert np.max(np.abs(np.linalg.norm(xy - centre, axis=1) - r)) < 0.3
    assert res.min_base_height > log.base_height[0] - 0.1


def check_steps_in_place(res, n: int) -> None:
    """``n`` alternating steps on the spot, heading kept, touch-downs detected from contact."""
    log = res.log
    assert not res.fell, f"fell at t = {res.fall_time:.2f} s"
    assert res.n_steps == n
    sides = [td.side for td in res.touchdowns]
    assert all(a != b for a, b in zip(sides, sides[1:]))  # alternating feet
    assert res.displacement < 0.3
    assert np.max(np.abs(np.unwrap(log.torso_yaw) - log.torso_yaw[0])) < 0.2
    assert sum(td.by_contact for td in res.touchdowns) >= 0.75 * n  # touch-down detected from contact
    assert res.min_base_height > log.base_height[0] - 0.1
