"""The compiled per-tick references (``_wbc.tick_references``) against the Python reference: bit-equal where
:func:`compiled_tick_references` enables them, on random steps with random re-targets and re-timings (not the
probe's), and a short full-body walk logged the same to the bit with and without them.

Where numpy's small matmul does not accumulate with FMAs in order (the loop then uses Python), the two differ
in the correction quintic's rounding only: its terms cancel, and summing them in the naive order instead moved
these cases by up to 1.1e-12 (absolute, on accelerations of order 1e2), hence the 1e-10 there."""

from __future__ import annotations

import numpy as np
import pytest

import lipmpcc._wbc as _wbc
from lipmpcc.control.references import LipComReference, StepTrajectory
from lipmpcc.control.tick_references import compiled_tick_references
from lipmpcc.rotations import yaw_rotation

pytestmark = pytest.mark.skipif(not hasattr(_wbc, "tick_references"), reason="_wbc built without tick_references")


def _random_case(rng: np.random.Generator) -> tuple[LipComReference, StepTrajectory, float]:
    lip = LipComReference(float(rng.uniform(0.5, 1.1)))
    lip.reset(float(rng.uniform(0, 1)), rng.normal(0, 0.2, 2), rng.normal(0, 0.5, 2), rng.normal(0, 0.2, 2))
    t0 = float(rng.uniform(0, 1))
    step = StepTrajectory(t0, t0 + float(rng.uniform(0.25, 0.5)), rng.normal(0, 0.3, 3), float(rng.normal(0, 1)),
                          rng.normal(0, 0.3, 3), float(rng.normal(0, 1)), float(rng.normal(0, 1)))
    for k in range(int(rng.integers(0, 4))):
        step.update(t0 + 0.05 * (k + 1), target_pos=rng.normal(0, 0.3, 3), target_yaw=float(rng.normal(0, 1)),
                    t_end=step.t_end + float(rng.normal(0, 0.03)))
    return lip, step, t0


def test_compiled_references_equal_the_python_ones() -> None:
    fn = _wbc.tick_references
    bitwise = compiled_tick_references() is not None
    rng = np.random.default_rng(2026)
    for _ in range(40):
        lip, step, t0 = _random_case(rng)
        packed, feet = np.zeros(24), np.zeros((2, 24))
        for t in (t0 + rng.uniform(-0.02, 0.6, 12)).tolist():
            side = int(rng.integers(0, 2))
            com, swing_pos, phase, yaw = fn(t, lip.compiled_state(), step.compiled_state(), side, 0.3, packed, feet)
            c, dc, ddc = lip.evaluate(t)
            r = step.evaluate(t)
            expected = np.concatenate([c, dc, ddc, yaw_rotation(r.torso_yaw).ravel(), [0, 0, r.torso_yaw_rate],
                                       [0, 0, r.torso_yaw_acc], r.swing_pos, r.swing_vel, r.swing_acc,
                                       yaw_rotation(r.swing_yaw).ravel(), [0, 0, r.swing_yaw_rate],
                                       [0, 0, r.swing_yaw_acc], c, r.swing_pos, [r.tau, r.torso_yaw]])
            got = np.concatenate([packed, feet[side], com, swing_pos, [phase, yaw]])
            if bitwise:
                assert got.tobytes() == expected.tobytes(), t
            else:  # another summation order in the correction quintic, whose terms cancel: up to ~1e-12 apart
                np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-10)
            assert not feet[1 - side].any()  # the other foot's row is never written
            feet[:] = 0.0


def test_double_support_and_bad_buffers() -> None:
    lip = LipComReference(0.9)
    lip.reset(0.0, np.array([0.1, 0.0]), np.array([0.3, 0.1]), np.zeros(2))
    packed, feet = np.full(30, 7.0), np.full((2, 24), 5.0)
    com, swing_pos, phase, yaw = _wbc.tick_references(0.2, lip.compiled_state(), None, 0, 0.4, packed, feet)
    assert swing_pos is None and np.isnan(phase) and yaw == 0.4
    assert packed[:9].tolist() == np.concatenate(lip.evaluate(0.2)).tolist()
    assert packed[9:18].tolist() == yaw_rotation(0.4).ravel().tolist() and not packed[18:24].any()
    assert (packed[24:] == 7.0).all() and (feet == 5.0).all()  # nothing else written
    with pytest.raises(ValueError, match="packed"):
        _wbc.tick_references(0.2, lip.compiled_state(), None, 0, 0.4, np.zeros(24, dtype=np.float32), feet)
    with pytest.raises(ValueError, match="lip"):
        _wbc.tick_references(0.2, np.zeros(8), None, 0, 0.4, packed, feet)


def test_walk_is_logged_the_same_with_and_without_them(monkeypatch: pytest.MonkeyPatch) -> None:
    if compiled_tick_references() is None:
        pytest.skip("compiled tick references not bit-equal on this machine (the loop uses Python)")
    from lipmpcc.loops.fullbody import FullBodyLoop, LoopParams
    from lipmpcc.loops.fullbody import references as loop_references
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.robots import load_robot

    loop = FullBodyLoop(load_robot("digit_like"), planner=CapturePointPlanner(speed=0.6),
                        params=LoopParams(helper_thread=False))
    compiled = loop.run(duration=1.0).log
    monkeypatch.setattr(loop_references, "compiled_tick_references", lambda: None)
    python = loop.run(duration=1.0).log
    assert np.isfinite(compiled.phase).any()  # single support was reached
    for name in ("com", "com_ref", "swing_ref", "phase", "tau", "torso_yaw_ref"):
        assert getattr(compiled, name).tobytes() == getattr(python, name).tobytes(), name


def test_switch_and_probe(monkeypatch: pytest.MonkeyPatch) -> None:
    from lipmpcc.control import tick_references as tr

    monkeypatch.setenv("LIPMPCC_TICK_REFERENCES", "0")
    tr.compiled_tick_references.cache_clear()
    try:
        assert tr.compiled_tick_references() is None
    finally:
        tr.compiled_tick_references.cache_clear()
    monkeypatch.delenv("LIPMPCC_TICK_REFERENCES")
    assert tr.reproduces_python(_wbc.tick_references) == (tr.compiled_tick_references() is not None)

    def off_by_one_ulp(*args):  # a compiled call one bit off is refused
        out = _wbc.tick_references(*args)
        return (np.nextafter(out[0], np.inf), *out[1:])

    assert not tr.reproduces_python(off_by_one_ulp)
