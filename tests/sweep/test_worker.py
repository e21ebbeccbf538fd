"""lipmpcc.sweep.worker: a case rebuilt from its plain dict and run through lipmpcc.studies.run."""

from __future__ import annotations

import math

import pytest

from lipmpcc.conventions import GRAVITY
from lipmpcc.sweep.spec import parse_spec
from lipmpcc.sweep.worker import (
    DEFAULT_PUSH_DURATION,
    case_options,
    case_pushes,
    default_push_step,
    run_case,
    worker_env,
)


def one_case(axes, study="circle-push", robot="lip", planner="mpcc", options=None):
    raw = {"study": study, "robot": robot, "planners": [planner], "options": options or {"steps": 12}, "axes": axes}
    return parse_spec(raw).cases()[0]


def test_impulse_and_direction_give_the_force() -> None:
    case = one_case({"impulse": {"unit": "N*s", "value": 6}, "direction": {"unit": "deg", "value": 90}})
    (push,), info = case_pushes(case)
    f = 6.0 / DEFAULT_PUSH_DURATION
    assert push.force == pytest.approx((0.0, f), abs=1e-9)
    assert push.step == default_push_step("circle-push") and info["impulse_Ns"] == pytest.approx(6.0)


def test_onset_as_a_fraction_of_the_lip_step_and_a_weight_fraction() -> None:
    case = one_case({"weight_fraction": {"value": 0.1}, "onset": {"unit": "fraction", "value": 0.5},
                     "push_step": {"value": 3}, "duration": {"value": 0.2}})
    (push,), info = case_pushes(case)
    assert push.t_start == pytest.approx(0.5 * 0.4) and push.step == 3 and push.duration == pytest.approx(0.2)
    assert info["force_N"] == pytest.approx(0.1 * 48.0 * GRAVITY)


def test_push_time_is_an_absolute_push_and_push_scale_keeps_the_study_pushes() -> None:
    (push,), _ = case_pushes(one_case({"force": {"value": 30}, "push_time": {"value": 2.5}}))
    assert push.step is None and push.t_start == 2.5
    case = one_case({"push_scale": {"value": 2.0}})
    pushes, info = case_pushes(case)
    assert pushes is None and info["impulse_Ns"] == pytest.approx(2.0 * 50.0 * 0.1)
    assert case_options(case).extra == {"push_scale": 2.0}


def test_case_options_are_the_run_options_of_lipmpcc_run() -> None:
    case = one_case({"seed": {"value": 4}, "push_scale": {"value": 1.0}})
    opts = case_options(case, with_pushes=False)
    assert (opts.scenario, opts.planner, opts.robot, opts.seed, opts.steps) == ("circle-push", "mpcc", "lip", 4, 12)


def test_a_case_runs_through_the_study_and_reports_its_push() -> None:
    case = one_case({"impulse": {"value": 4.0}, "push_step": {"value": 5}})
    res = run_case(case, worker_env(False))
    assert res["status"] == "done" and res["error"] is None
    assert res["summary"]["pushes"] == 1 and res["summary"]["steps"] == 12
    assert res["push"]["impulse_Ns"] == pytest.approx(4.0) and res["wall_s"] > 0


def test_a_big_push_fells_the_lip_and_a_case_that_raises_is_an_error() -> None:
    case = one_case({"impulse": {"value": 60.0}, "push_step": {"value": 5}})
    assert run_case(case)["summary"]["fell"] is True
    case = dict(case, planner_name="alip-qp")  # not a planner of circle-push: the study raises
    res = run_case(case)
    assert res["status"] == "error" and "alip-qp" in res["error"] and "\n" not in res["error"]


def test_worker_env_sets_one_blas_thread_and_the_helper_threads() -> None:
    env = worker_env(helper_threads=False)
    assert env["OMP_NUM_THREADS"] == "1" and env["OPENBLAS_NUM_THREADS"] == "1"
    assert env["LIPMPCC_LOOP_THREAD"] == "0" and env["LIPMPCC_WBC_THREAD"] == "0"
    assert "LIPMPCC_LOOP_THREAD" not in worker_env(helper_threads=True)
    assert math.isfinite(DEFAULT_PUSH_DURATION)


def test_a_case_past_its_timeout_is_recorded_as_a_timeout() -> None:
    # the ALIP's 32 stones take seconds (the LIP's circle ends after 144 steps in 0.4 s, before the limit)
    warm = {"study": "stones", "robot": "alip", "planners": ["alip-mpc"], "options": {"steps": 3}}
    assert run_case(parse_spec(warm).cases()[0])["status"] == "done"  # the solver built: the run is in its solves
    alone = run_case(parse_spec({**warm, "options": {}}).cases()[0])
    assert alone["status"] == "done"
    limit = round(alone["wall_s"] / 4, 3)  # a quarter of the whole case, on any machine
    case = parse_spec({**warm, "options": {}, "timeout_s": limit}).cases()[0]
    assert case["timeout_s"] == limit
    res = run_case(case)
    assert res["status"] == "timeout" and res["summary"] is None, (res, alone["wall_s"])
    assert f"timeout_s = {limit:g} s" in res["error"] and limit <= res["wall_s"] < alone["wall_s"]


def test_a_timeout_that_the_code_swallows_is_raised_again_and_still_a_timeout() -> None:
    """A solver may catch the timeout in its own callback (CasADi turns an exception raised in its signal
    check into a failed solve): the case was then recorded "done" after running to its end. The timeout is
    raised again every RETIMEOUT_S until it escapes, and a body that swallowed it every time and ended, or
    raised another error from it, is a timeout all the same."""
    import time

    from lipmpcc.sweep.worker import CaseTimeout, deadline

    caught = []
    t0 = time.perf_counter()
    with pytest.raises(CaseTimeout):
        with deadline(0.05):
            for _ in range(2):
                try:
                    time.sleep(5.0)
                except CaseTimeout:  # swallowed, twice
                    caught.append(time.perf_counter() - t0)
            time.sleep(5.0)  # the third one escapes
    assert len(caught) == 2 and time.perf_counter() - t0 < 1.0
    with pytest.raises(CaseTimeout):
        with deadline(0.05):
            try:
                time.sleep(5.0)
            except CaseTimeout:
                pass  # swallowed, and the body ends before the next one
    with pytest.raises(CaseTimeout) as err:
        with deadline(0.05):
            try:
                time.sleep(5.0)
            except CaseTimeout as exc:
                raise RuntimeError("solver failed") from exc
    assert isinstance(err.value.__cause__, RuntimeError)


def test_the_deadline_is_not_taken_for_an_exception_and_is_lifted_after() -> None:
    import signal
    import time

    from lipmpcc.sweep.worker import CaseTimeout, deadline

    swallowed = False
    with pytest.raises(CaseTimeout):
        with deadline(0.05) as enforced:
            assert enforced
            try:  # a loop's own `except Exception` (a planner fallback, say) must not take it
                time.sleep(1.0)
            except Exception:  # noqa: BLE001
                swallowed = True
    assert not swallowed and signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
    with deadline(None) as enforced:  # no limit
        assert not enforced
    import threading

    seen = []
    t = threading.Thread(target=lambda: seen.append(deadline(1.0).__enter__()))
    t.start()
    t.join()
    assert seen == [False]  # not enforceable off the main thread (Dask's worker threads)


def test_a_case_within_its_timeout_runs_unchanged() -> None:
    base = {"study": "circle", "robot": "lip", "planners": ["mpcc"], "options": {"steps": 6}}
    plain, limited = parse_spec(base).cases()[0], parse_spec({**base, "timeout_s": 120}).cases()[0]
    assert "timeout_s" not in plain and plain["id"] != limited["id"]
    a, b = run_case(plain), run_case(limited)
    assert a["status"] == b["status"] == "done"
    assert a["summary"]["contouring_error_rms_m"] == b["summary"]["contouring_error_rms_m"]
