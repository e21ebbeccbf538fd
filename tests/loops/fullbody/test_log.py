"""lipmpcc.loops.fullbody.log: the per-tick log (rows to arrays, DCM, swing error), the run's outcome
and summary fields, and the video frames."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from lipmpcc.conventions import LEFT, RIGHT
from lipmpcc.loops.fullbody.log import FrameRecorder, LoopLog, LoopResult, TickLogger, TouchDown
from lipmpcc.metrics import timing_stats_ms
from lipmpcc.rotations import yaw_rotation

from .handmade import measurement


def _logger() -> TickLogger:
    """Three ticks: double support, then right stance with the left foot swinging 0.05 m off its reference."""
    lg = TickLogger(omega=3.0)
    nan3 = np.full(3, np.nan)
    for k, (stance, swing_ref, phase) in enumerate(((2, nan3, np.nan), (1, np.array([0.0, 0.1, 0.05]), 0.1),
                                                   (1, np.array([0.0, 0.1, 0.0]), 0.2))):
        m = measurement(0.0025 * k)
        m = m._replace(com_vel=np.array([0.3, -0.6, 0.0]), torso=m.torso._replace(rotation=yaw_rotation(0.5)))
        lg.log(m.time, m, 0.4, np.array([0.0, 0.0, 0.9]), swing_ref, phase, stance, np.zeros(4), 1e-4, 0, k == 2)
    return lg


def test_rows_become_arrays_with_the_dcm_and_the_swing_error() -> None:
    log = _logger().to_log()
    assert isinstance(log, LoopLog) and log.t.shape == (3,) and log.com.shape == (3, 3) and log.tau.shape == (3, 4)
    np.testing.assert_allclose(log.dcm[0], [0.0 + 0.3 / 3.0, 0.0 - 0.6 / 3.0])
    assert log.base_height[0] == 0.0  # q[2] of the hand-made measurement
    np.testing.assert_allclose(log.torso_yaw, 0.5)
    np.testing.assert_array_equal(log.torso_yaw_ref, 0.4)
    assert np.all(log.torso_tilt == 0.0) and log.contact.dtype == bool and list(log.fallback) == [False, False, True]
    # the swing foot (left, under right stance) is at (0, 0.1, 0): errors 0.05 then 0; NaN in double support
    assert math.isnan(log.swing_err[0])
    np.testing.assert_allclose(log.swing_err[1:], [0.05, 0.0], atol=1e-15)


def test_derived_columns_equal_the_per_tick_formulas_to_the_bit() -> None:
    """The logger computes the DCM, the torso's heading and tilt and the base height in :meth:`to_log` from the
    stored rows: equal to the bit to the formulas evaluated per tick on Python floats (how the logger did it)."""
    from lipmpcc.loops.fullbody.angles import tilt_of, yaw_of
    from lipmpcc.rotations import quat_wxyz_to_rot

    rng = np.random.default_rng(5)
    omega = 3.2576
    lg = TickLogger(omega=omega)
    want = []
    for k in range(40):
        m = measurement(0.0025 * k, contact=(bool(k % 2), True))
        rot = quat_wxyz_to_rot(*(rng.normal(size=4) / 2.0).tolist())
        q = rng.normal(size=7)
        m = m._replace(q=q, com=rng.normal(size=3), com_vel=rng.normal(size=3), torso=m.torso._replace(rotation=rot))
        lg.log(m.time, m, 0.1 * k, rng.normal(size=3), rng.normal(size=3), 0.01 * k, k % 3, rng.normal(size=4),
               1e-4, 0, False)
        (cx, cy, _), (vx, vy, _) = m.com.tolist(), m.com_vel.tolist()
        want.append(((cx + vx / omega, cy + vy / omega), float(q[2]), yaw_of(rot), tilt_of(rot)))
    log = lg.to_log()
    assert np.array_equal(log.dcm, np.array([w[0] for w in want]))
    assert np.array_equal(log.base_height, np.array([w[1] for w in want]))
    assert np.array_equal(log.torso_yaw, np.array([w[2] for w in want]))
    assert np.array_equal(log.torso_tilt, np.array([w[3] for w in want]))
    assert log.contact.dtype == bool and log.contact.shape == (40, 2) and log.stance.shape == (40,)


def test_an_empty_log_has_empty_arrays() -> None:
    log = TickLogger(omega=3.0).to_log()
    assert log.t.size == 0 and log.swing_err.size == 0


def _result(log: LoopLog, touchdowns: list[TouchDown]) -> LoopResult:
    ms = timing_stats_ms([1e-4, 2e-4])
    return LoopResult(log=log, touchdowns=touchdowns, fell=False, fall_time=math.nan, sim_time=0.005, wall_time=0.01,
                      real_time_factor=0.5, wbc_ms=ms, planner_ms=ms, qp_failures=0, wbc_rate_hz=400.0,
                      sim_rate_hz=2000.0, planner_rate_hz=10.0, omega=3.0, com_height=0.9)


def test_the_outcome_and_its_summary_fields() -> None:
    log = _logger().to_log()
    log.com[:, :2] = [[0.0, 0.0], [0.3, 0.4], [0.0, 0.0]]  # out 0.5 m and back
    tds = [TouchDown(0.3, LEFT, np.zeros(3), np.zeros(2), 0.0, 0.0, True, 0.3),
           TouchDown(0.6, RIGHT, np.zeros(3), np.zeros(2), 0.0, 0.0, False, 0.3)]
    res = _result(log, tds)
    assert res.n_steps == 2 and res.distance_walked == pytest.approx(1.0) and res.displacement == pytest.approx(0.0)
    assert res.min_base_height == 0.0
    s = res.summary()
    assert s["fell"] is False and s["fall_time_s"] is None and s["steps"] == 2 and s["touchdowns_by_contact"] == 1
    assert set(s["wbc_ms"]) == {"median", "p90", "max"} and s["rates_hz"] == {"sim": 2000.0, "wbc": 400.0, "planner": 10.0}
    assert s["distance_walked_m"] == pytest.approx(1.0) and s["com_height_m"] == 0.9
    empty = _result(TickLogger(3.0).to_log(), [])  # a run that stopped before its first tick
    assert math.isnan(empty.min_base_height) and empty.distance_walked == 0.0 and empty.displacement == 0.0
    assert empty.summary()["distance_walked_m"] == 0.0


def test_frames_are_kept_at_the_video_rate() -> None:
    rec = FrameRecorder(t0=0.0, fps=10.0)
    sim = SimpleNamespace(qpos=np.zeros(3))
    for k in range(0, 41):  # 0 .. 0.2 s every 5 ms
        sim.qpos[0] = k
        rec.record(0.005 * k, sim)
    assert rec.times == pytest.approx([0.0, 0.1, 0.2]) and [q[0] for q in rec.qpos] == [0, 20, 40]
    assert rec.qpos[0] is not rec.qpos[1]  # copies, not the simulator's array
