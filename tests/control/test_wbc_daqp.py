"""DAQP in the whole-body QP (``WbcParams(qp_solver="daqp")``, cpp/wbc/src/qp_solver_daqp.cpp).

- Parity: on the same QPs — random states and references in every support mode, each followed by a
  short smooth sequence of ticks so that DAQP warm-starts from the previous working set — DAQP's
  solution (q̈, wrenches, motor efforts) equals proxsuite's at a tight tolerance, and on the last tick of
  each sequence the numpy reference QP's (``ReferenceWbcQp``, cold), on digit_like and, when ../shared is
  present, on Digit v3 (closed loops eliminated, rigid springs; the reference with the loop forces as
  variables).
- The warm start works: along a smooth sequence DAQP needs fewer active-set changes per tick than
  from an empty working set.
- Closed loop: digit_like walks 2 s at 0.6 m/s under a push with DAQP without falling or a QP failure,
  and touches down when and where it does with proxsuite (to 0.1 mm; measured 3e-6 m).
- An infeasible QP (1e4 N of normal force asked of each foot of the small test biped) is reported as
  such and handled by the fallback, without raising; the iteration limit likewise.
- proxsuite is the default, ``$LIPMPCC_WBC_QP_SOLVER`` replaces it; a solver that is not one of the two
  is refused by name.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.control.wbc_types import QP_SOLVER_ENV, QP_SOLVERS, WbcParams
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.robots import load_robot

from ..conftest import SHARED_DIGIT
from lipmpcc.control.reference_qp import ReferenceWbcQp
from .test_wbc_parity import MODES, PARAMS, loop_state, random_reference, random_state

N_START = {"digit_like": 2, "digit_v3": 1}  # random starting points per mode (Digit v3: slower states)
N_TICKS = 6  # smooth ticks after each (warm starts)
DT = 0.0025  # [s] the 400 Hz WBC tick


def controllers(name: str, solver: str) -> tuple[WholeBodyController, ReferenceWbcQp]:
    params = dataclasses.replace(PARAMS, qp_solver=solver)
    if name == "digit_like":
        wbc = WholeBodyController(load_robot("digit_like"), params, threaded=False)
    else:
        if not SHARED_DIGIT.exists():
            pytest.skip(f"reference model not found at {SHARED_DIGIT}")
        wbc = WholeBodyController(load_robot(SHARED_DIGIT), params, threaded=False)
    return wbc, ReferenceWbcQp(wbc.model.spec, params)


@pytest.fixture(scope="module", params=["digit_like", "digit_v3"])
def pair(request):
    daqp, ref_qp = controllers(request.param, "daqp")
    prox, _ = controllers(request.param, "proxsuite")
    return request.param, daqp, prox, ref_qp


def sequence(name: str, wbc: WholeBodyController, ref_qp: ReferenceWbcQp, mode: str, seed: int):
    """(q, v, ref) of N_START random starts, each followed by N_TICKS ticks that move the state by
    v·dt and the reference by a small drift (what consecutive walking ticks look like)."""
    rng = np.random.default_rng(seed + 100 * list(MODES).index(mode))
    for _ in range(N_START[name]):
        q, v = loop_state(wbc, ref_qp, rng) if ref_qp.n_loop else random_state(ref_qp.model, rng)
        ref = random_reference(wbc, q, MODES[mode], rng)
        for k in range(N_TICKS + 1):
            yield k, q, v, ref
            if ref_qp.n_loop:  # stay on the loop manifold: the same state, a drifting reference
                ref.com_pos = ref.com_pos + np.array([0.001, 0.0005, 0.0])
            else:
                import pinocchio as pin

                q = pin.integrate(ref_qp.model, q, v * DT)
                ref.com_pos = ref.com_pos + ref.com_vel * DT
            ref.foot_pos = ref.foot_pos + ref.foot_vel * DT


@pytest.mark.parametrize("mode", list(MODES))
def test_daqp_solutions_equal_proxsuite(pair, mode: str) -> None:
    name, daqp, prox, ref_qp = pair
    daqp.reset()
    prox.reset()
    n = 0
    for k, q, v, ref in sequence(name, daqp, ref_qp, mode, seed=3):
        a = daqp.solve(q, v, ref)
        b = prox.solve(q, v, ref)
        assert b.status == "solved"  # the comparison is only meaningful on solved QPs
        assert a.status == "solved", a.status
        wants = [((b.qdd, b.wrenches, b.tau), "proxsuite")]
        if k == N_TICKS:  # the last, warm-started tick of a start: the numpy reference QP too (cold, 1e-10)
            sol = ref_qp.solve(q, v, ref)
            assert sol.found
            wants.append(((sol.qdd, sol.wrenches, sol.tau), "numpy reference"))
        for (qdd, wrenches, tau), who in wants:
            for got, want, what in ((a.qdd, qdd, "qdd"), (a.wrenches, wrenches, "wrenches"), (a.tau, tau, "tau")):
                scale = max(1.0, float(np.max(np.abs(want))))
                np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * scale, err_msg=f"{name} {mode} {what} {who}")
        n += 1
    assert n == N_START[name] * (N_TICKS + 1)
    assert daqp.qp_failures == 0


def test_warm_start_needs_fewer_active_set_changes() -> None:
    """Along smooth double-support sequences on digit_like, the warm-started solver changes its working
    set less often than a solver reset before every tick (both find the same solution)."""
    warm, ref_qp = controllers("digit_like", "daqp")
    cold, _ = controllers("digit_like", "daqp")
    it_warm, it_cold = [], []
    for k, q, v, ref in sequence("digit_like", warm, ref_qp, "double", seed=11):
        a = warm.solve(q, v, ref)
        cold.reset()
        b = cold.solve(q, v, ref)
        assert a.status == b.status == "solved"
        np.testing.assert_allclose(a.qdd, b.qdd, rtol=0, atol=1e-6 * max(1.0, float(np.max(np.abs(b.qdd)))))
        if k > 0:  # the first tick of a start is cold for both
            it_warm.append(a.iterations)
            it_cold.append(b.iterations)
    assert np.mean(it_warm) < 0.6 * np.mean(it_cold), (it_warm, it_cold)


@pytest.mark.parametrize("max_iter, status", [(50, "primal_infeasible"), (1, "max_iter_reached")])
def test_infeasible_qp_goes_to_the_fallback(max_iter: int, status: str) -> None:
    from .test_wbc import mini_description, standing_state

    wbc = WholeBodyController(mini_description(), WbcParams(qp_solver="daqp", min_normal_force=1e4, qp_max_iter=max_iter))
    q, v = standing_state(wbc)
    ref = wbc.hold_reference(q)
    for k in range(3):
        out = wbc.solve(q, v, ref)
        assert out.used_fallback and out.status == status
        assert np.all(np.isfinite(out.tau))
        assert wbc.qp_failures == k + 1


def test_qp_solver_is_validated(monkeypatch: pytest.MonkeyPatch) -> None:
    """proxsuite is the default; ``$LIPMPCC_WBC_QP_SOLVER`` replaces it (checked by name); a robot's
    ``wbc_overrides`` and an explicit argument win over both."""
    assert QP_SOLVERS == ("proxsuite", "daqp")
    monkeypatch.delenv(QP_SOLVER_ENV, raising=False)
    assert WbcParams().qp_solver == "proxsuite"
    monkeypatch.setenv(QP_SOLVER_ENV, " DAQP ")
    assert WbcParams().qp_solver == "daqp"
    assert WbcParams(qp_solver="proxsuite").qp_solver == "proxsuite"
    robot = dataclasses.replace(load_robot("digit_like"), wbc_overrides={"qp_solver": "proxsuite"})
    assert WbcParams.for_robot(robot).qp_solver == "proxsuite"
    monkeypatch.setenv(QP_SOLVER_ENV, "osqp")
    with pytest.raises(InvalidInputError, match=r"LIPMPCC_WBC_QP_SOLVER = 'osqp': expected one of 'proxsuite', 'daqp'"):
        WbcParams()
    monkeypatch.delenv(QP_SOLVER_ENV)
    assert WbcParams(qp_solver="proxsuite").qp_solver == "proxsuite"
    for bad in ("DAQP", "osqp", "", 1, None):
        with pytest.raises(InvalidInputError, match=r"qp_solver = .*: expected one of 'proxsuite', 'daqp'"):
            WbcParams(qp_solver=bad)


def test_closed_loop_walk_with_daqp() -> None:
    """2 s of walking at 0.6 m/s with a 40 N push on digit_like: no fall, no QP failure, and the
    touch-downs of the proxsuite run (the two QP solvers reach the same optimum to ~1e-8)."""
    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.push import Push

    robot = load_robot("digit_like")
    runs = {}
    for solver in ("daqp", "proxsuite"):
        params = dataclasses.replace(WbcParams.for_robot(robot), qp_solver=solver)
        loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.6), wbc_params=params)
        runs[solver] = res = loop.run(duration=2.0, pushes=[Push(t_start=1.0, force=(40.0, 20.0, 0.0), duration=0.1)])
        assert not res.fell and res.qp_failures == 0 and len(res.touchdowns) >= 3, solver
    a, b = runs["daqp"], runs["proxsuite"]
    assert [(td.t, td.side) for td in a.touchdowns] == [(td.t, td.side) for td in b.touchdowns]
    pa = np.array([td.pos for td in a.touchdowns])
    pb = np.array([td.pos for td in b.touchdowns])
    np.testing.assert_allclose(pa, pb, rtol=0, atol=1e-4)
