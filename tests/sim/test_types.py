"""lipmpcc.sim.types: frame poses, measurements, the fall criterion and the simulator log."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from lipmpcc.exceptions import ParameterError
from lipmpcc.sim.types import FallCriterion, FramePose, Measurement, SimLog


def test_poses_and_measurements_are_named_tuples() -> None:
    eye = np.eye(3)
    pose = FramePose(np.array([1.0, 2.0, 3.0]), eye)
    p, R = pose
    assert p is pose.position and R is pose.rotation
    m = Measurement(time=0.5, q=np.zeros(7), v=np.zeros(6), com=np.zeros(3), com_vel=np.zeros(3), torso=pose,
                    feet=(pose, pose), contact=(True, False), normal_force=(300.0, 0.0))
    assert m.contact == (True, False) and m.feet[1].position[2] == 3.0
    assert m._replace(time=1.0).time == 1.0 and m.time == 0.5


def test_fall_criterion_defaults_and_bounds() -> None:
    f = FallCriterion()
    assert (f.min_height, f.max_tilt, f.non_foot_contact, f.self_contact) == (None, 1.0, True, False)
    assert FallCriterion(min_height=0.4).min_height == 0.4
    assert FallCriterion(max_tilt=math.pi).max_tilt == math.pi
    for kw in ({"min_height": 0.0}, {"min_height": float("nan")}, {"max_tilt": 0.0}, {"max_tilt": 4.0}):
        with pytest.raises(ParameterError, match=next(iter(kw))):
            FallCriterion(**kw)


def test_log_stacks_its_samples_and_saves_them(tmp_path: Path) -> None:
    log = SimLog(every=5)
    assert len(log) == 0
    for k in range(3):
        log.t.append(0.01 * k)
        log.qpos.append(np.full(4, k, dtype=float))
        log.qvel.append(np.zeros(3))
        log.ctrl.append(np.zeros(2))
        log.com.append(np.array([0.0, 0.0, 0.9]))
        log.com_vel.append(np.zeros(3))
        log.contact.append((True, k != 1))
        log.normal_force.append((100.0, 50.0 * k))
        log.push.append(np.zeros(3))
    a = log.arrays()
    assert len(log) == 3 and set(a) == {"t", "qpos", "qvel", "ctrl", "com", "com_vel", "contact", "normal_force", "push"}
    assert a["qpos"].shape == (3, 4) and a["contact"].dtype == bool and a["contact"][1, 1] == False  # noqa: E712
    path = log.save(tmp_path / "deep" / "log.npz")
    with np.load(path) as z:
        np.testing.assert_array_equal(z["normal_force"], a["normal_force"])
