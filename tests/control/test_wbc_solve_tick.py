"""``WholeBodyController.solve_tick``, the full-body loop's per-tick call: the numbers of ``solve`` without
building the ``WbcOutput``.

- The same efforts, status, fallback flag and angular momentum to the bit as ``solve`` on the same ticks
  (both QP solvers, every support mode, a ``PackedWbcReference`` as the loop hands it), and the same
  effect on the controller (its last efforts, the fallback's starting point).
- The Python fallback (the C++ call raised) gives ``solve``'s fallback efforts.
- A closed-loop walk whose loop calls ``solve_tick`` logs what the same walk through ``solve`` logs, to the bit.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lipmpcc.control.reference_qp import ReferenceWbcQp
from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.control.wbc_types import PackedWbcReference, WbcParams
from lipmpcc.robots import load_robot

from .test_wbc_parity import MODES, random_reference, random_state


def _packed(ref, n_arm: int) -> PackedWbcReference:
    out = PackedWbcReference(np.zeros(n_arm))
    for name in ("com_pos", "com_vel", "com_acc", "torso_rot", "torso_angvel", "torso_angacc", "foot_pos",
                 "foot_vel", "foot_acc", "foot_rot", "foot_angvel", "foot_angacc", "arm_posture", "contact",
                 "max_normal_force"):
        setattr(out, name, getattr(ref, name))
    return out


@pytest.mark.parametrize("solver", ["daqp", "proxsuite"])
def test_solve_tick_equals_solve(solver: str) -> None:
    robot = load_robot("digit_like")
    params = dataclasses.replace(WbcParams.for_robot(robot), qp_solver=solver)
    full, lean = (WholeBodyController(robot, params, threaded=False) for _ in range(2))
    pmodel = ReferenceWbcQp(full.model.spec, params).model
    rng = np.random.default_rng(7)
    for mode, contact in MODES.items():
        q, v = random_state(pmodel, rng)
        ref = random_reference(full, q, contact, rng)
        for r in (ref, _packed(ref, full.n_arm)):
            out = full.solve(q, v, r)
            tau, status, fallback, angmom = lean.solve_tick(q, v, r)
            assert np.array_equal(tau, out.tau) and np.array_equal(angmom, out.errors.angular_momentum), mode
            assert (status, fallback) == (out.status_code, out.used_fallback)
            assert np.array_equal(lean._u_last, full._u_last)
    assert lean.qp_failures == full.qp_failures


def test_solve_tick_python_fallback(monkeypatch: pytest.MonkeyPatch) -> None:
    from .test_wbc import broken_solver_controller

    wbc, q, v, ref, good = broken_solver_controller(monkeypatch)
    tau, status, fallback, angmom = wbc.solve_tick(q, v, ref)
    assert fallback and status == wbc.solve(q, v, ref).status_code
    np.testing.assert_allclose(tau, good.tau - wbc.params.fallback_damping * wbc.actuation.T @ v)
    assert np.array_equal(angmom, np.zeros(3)) and wbc.qp_failures == 2


def test_loop_through_solve_tick_logs_what_solve_logs() -> None:
    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.planners.capture_point import CapturePointPlanner

    robot = load_robot("digit_like")
    logs = []
    for lean in (True, False):
        loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.6))
        if not lean:  # the loop's call through the full output, as before solve_tick
            wbc = loop.wbc

            def via_solve(q, v, ref, wbc=wbc):
                out = wbc.solve(q, v, ref)
                return out.tau, out.status_code, out.used_fallback, out.errors.angular_momentum

            wbc.solve_tick = via_solve
        res = loop.run(duration=1.3)
        assert not res.fell and res.touchdowns
        logs.append(res.log)
    for name in ("com", "com_vel", "tau", "left_foot", "right_foot", "swing_ref", "stance", "wbc_status"):
        assert np.array_equal(getattr(logs[0], name), getattr(logs[1], name), equal_nan=name == "swing_ref"), name


def test_solve_tick_names_a_bad_state_as_solve_does() -> None:
    """The loop's one-frame checks of solve_tick (float64 q and v, a PackedWbcReference) refuse what solve
    refuses, with the same error and name: a non-contiguous q, a v of the wrong size, a quaternion off norm 1,
    a NaN in v (from C++); float32 states take the general path and are refused there."""
    from lipmpcc.exceptions import StateError

    robot = load_robot("digit_like")
    wbc = WholeBodyController(robot, threaded=False)
    pmodel = ReferenceWbcQp(wbc.model.spec, wbc.params).model
    rng = np.random.default_rng(3)
    q, v = random_state(pmodel, rng)
    ref = _packed(random_reference(wbc, q, (True, True), rng), wbc.n_arm)
    q_strided = np.repeat(q, 2)[::2]
    q_off = q.copy()
    q_off[3:7] *= 1.01
    v_nan = v.copy()
    v_nan[5] = np.nan
    for bad_q, bad_v, name in ((q_strided, v, "q"), (q, v[:-1], "v"), (q_off, v, "q[3:7]"), (q, v_nan, "v"),
                               (q.astype(np.float32), v, "q")):
        messages = []
        for call in (wbc.solve, wbc.solve_tick):
            with pytest.raises(StateError) as err:
                call(bad_q, bad_v, ref)
            messages.append(str(err.value))
        assert messages[0] == messages[1] and name in messages[0], messages
    tau, status, fallback, _ = wbc.solve_tick(q, v, ref)  # and the good state still solves
    assert status == 0 and not fallback and np.all(np.isfinite(tau))


def test_a_loop_without_the_wbc_worker_skips_prepare_and_logs_the_same() -> None:
    """Without the WBC's worker thread the loop measures without handing the state to prepare (the solve
    computes the dynamics stage itself): prepare is never called, and a 1.3 s walk logs what the same walk
    with the worker logs, to the bit."""
    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.planners.capture_point import CapturePointPlanner

    robot = load_robot("digit_like")
    logs, prepared = [], []
    for threaded in (True, False):
        loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.6),
                            wbc=WholeBodyController(robot, threaded=threaded))
        calls = []
        prepare = loop.wbc.prepare
        loop.wbc.prepare = lambda q, v, prepare=prepare, calls=calls: (calls.append(1), prepare(q, v))[1]
        res = loop.run(duration=1.3)
        assert not res.fell and res.touchdowns
        logs.append(res.log)
        prepared.append(len(calls))
    assert prepared[0] == len(logs[0].t) and prepared[1] == 0
    for name in ("com", "com_vel", "tau", "left_foot", "right_foot", "swing_ref", "stance", "wbc_status"):
        assert np.array_equal(getattr(logs[0], name), getattr(logs[1], name), equal_nan=name == "swing_ref"), name
