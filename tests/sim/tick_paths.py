"""The simulator on either path of its control tick (compiled ``lipmpcc._mjtick`` or Python), for the
bit-for-bit comparisons of test_robot_sim.py and test_tick.py."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.sim import _tick
from lipmpcc.sim.robot_sim import RobotSim
from lipmpcc.sim.types import Measurement


def python_path_sim(monkeypatch: pytest.MonkeyPatch, *args, **kw) -> RobotSim:
    """A RobotSim built with the compiled tick switched off (the Python path)."""
    with monkeypatch.context() as mp:
        mp.setattr(_tick, "TICK", None)
        sim = RobotSim(*args, **kw)
    assert not sim.compiled_tick
    return sim


def measurement_bytes(m: Measurement) -> bytes:
    """Every field of a measurement as bytes (for bit-for-bit comparisons)."""
    parts = [np.array([m.time]), m.q, m.v, m.com, m.com_vel, m.torso.position, m.torso.rotation,
             m.feet[0].position, m.feet[0].rotation, m.feet[1].position, m.feet[1].rotation,
             np.array(m.contact, dtype=float), np.array(m.normal_force), np.array(m.touched, dtype=float),
             np.array(m.peak_normal_force)]
    return b"".join(np.ascontiguousarray(p, dtype=float).tobytes() for p in parts)
