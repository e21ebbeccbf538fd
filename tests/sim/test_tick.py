"""lipmpcc.sim._tick: the compiled control tick (lipmpcc._mjtick) against the simulator's Python path, bit for bit,
and the fall-back to Python when it is missing, disabled or built for another MuJoCo."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from lipmpcc.rotations import quat_wxyz_to_rot
from lipmpcc.sim import _tick
from lipmpcc.sim.robot_sim import RobotSim

from .tick_paths import measurement_bytes, python_path_sim


def test_compiled_tick_equals_the_python_path_bit_for_bit(monkeypatch: pytest.MonkeyPatch) -> None:
    """Measurements, contact forces, falls and the trajectory, with pushes that start and end inside
    control ticks (torso and a foot), hand edits of qpos between a measurement and the next step, and
    a SimLog (logged steps run in Python, on the compiled tick's primed stages)."""
    if _tick.TICK is None:
        pytest.skip("lipmpcc._mjtick is not built (or not usable with this MuJoCo)")
    for log_every in (None, 3):
        a = RobotSim("digit_like", log_every=log_every)
        b = python_path_sim(monkeypatch, "digit_like", log_every=log_every)
        assert a.compiled_tick
        for s in (a, b):
            s.add_push([30.0, -15.0, 5.0], 0.10123, 0.0507)
            s.add_push([-10.0, 0.0, 0.0], 0.12, 0.2, body=s.description.left_foot_body)
        rng = np.random.default_rng(3)
        _, hi = a.ctrl_range
        for k in range(120):
            ctrl = rng.uniform(-0.05, 0.05, a.nu) * hi
            ma, mb = a.measure(), b.measure()
            assert measurement_bytes(ma) == measurement_bytes(mb), k
            if k % 23 == 5:  # a hand edit after the measurement: a full mj_step must run
                for s in (a, b):
                    s.data.qpos[7] += 1e-4
            if k % 17 == 3:
                assert a.fallen() == b.fallen()
                for fa, fb in zip(a.contact_forces(), b.contact_forces()):
                    assert fa.tobytes() == fb.tobytes()
            a.step(ctrl, 5)
            b.step(ctrl, 5)
        assert a.data.qpos.tobytes() == b.data.qpos.tobytes() and a.data.qvel.tobytes() == b.data.qvel.tobytes()
        assert a.time == b.time and a.fallen() == b.fallen()
        if log_every:
            la, lb = a.log.arrays(), b.log.arrays()
            assert all(la[k].tobytes() == lb[k].tobytes() for k in la)
        a.reset("stand")
        b.reset("stand")
        assert not a.pushes and measurement_bytes(a.measure()) == measurement_bytes(b.measure())


def test_compiled_tick_falls_back_to_python_when_missing_or_built_for_another_mujoco(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import sys
    import types

    import lipmpcc

    # missing module: the import fails, the Python path runs
    monkeypatch.setitem(sys.modules, "lipmpcc._mjtick", None)
    monkeypatch.delattr(lipmpcc, "_mjtick", raising=False)
    assert _tick.load_tick_module() is None
    monkeypatch.undo()
    # disabled by the environment
    monkeypatch.setenv("LIPMPCC_PYTHON_TICK", "1")
    assert _tick.load_tick_module() is None
    monkeypatch.delenv("LIPMPCC_PYTHON_TICK")
    # built against another MuJoCo (headers or linked library)
    running = mujoco.mj_version()
    for header, linked in ((running + 1, running), (running, running - 1)):
        fake = types.SimpleNamespace(mujoco_version=header, linked_mujoco_version=lambda v=linked: v)
        assert _tick.check_tick_module(fake) is None
    # a rotation that differs from numpy's in the last bit is rejected too
    fake = types.SimpleNamespace(
        mujoco_version=running, linked_mujoco_version=lambda: running,
        rotate_transposed=lambda w, x, y, z, v, fma: np.nextafter(quat_wxyz_to_rot(w, x, y, z).T @ v, 1.0),
    )
    assert _tick.check_tick_module(fake) is None
    # without the module the simulator works on its Python path
    sim = python_path_sim(monkeypatch, "digit_like")
    sim.step(np.zeros(sim.nu), 5)
    assert sim.measure().time == pytest.approx(5 * sim.timestep)
