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
