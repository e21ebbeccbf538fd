"""lipmpcc.studies.path_metrics: paper A's metrics, once for both robots — the LIP's summary fields are the loop's
with paper A's from paper_a_fields, the push recovery, overtook, and the progress along the path."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.push import Push
from lipmpcc.studies.path_metrics import (assess_run, lip_path_log, paper_a_fields, progress_trace, push_recovery_times,
                                          summarize_lip)


@pytest.fixture(scope="module")
def overtake():
    from lipmpcc.studies.path_following import simulate_lip

    return simulate_lip("overtake", n_steps=30)


def test_the_lip_summary_gives_paper_a_fields_as_the_loop_computes_them(overtake):
    from lipmpcc.loops.lip import summarize

    run = overtake
    s, loop = summarize_lip(run.lip_log, run.obstacles, 2.0), summarize(run.lip_log, run.obstacles, 2.0)
    assert s.keys() == loop.keys()
    for k in s:
        assert s[k] == loop[k] or (isinstance(s[k], float) and np.isnan(s[k]) and np.isnan(loop[k])), k
    assert s["min_clearance_m"] is not None and s["progress_m"] > 1.0


def test_paper_a_fields_judge_errors_after_the_settling_time(overtake):
    log = lip_path_log(overtake.lip_log)
    late = paper_a_fields(log, (), settle_time=float(log.t[-1]) + 1.0)
    assert np.isnan(late["contouring_error_max_m"]) or late["contouring_error_max_m"] == 0.0
    early = paper_a_fields(log, (), settle_time=0.0)
    assert early["contouring_error_max_m"] == pytest.approx(float(np.max(np.abs(log.e_contouring))))
    assert early["min_clearance_m"] is None and early["overtook"] is False  # no obstacles


def test_push_recovery_is_timed_from_the_push_end_the_loop_applied():
    from dataclasses import replace

    t = np.arange(10) * 0.4
    e = np.array([0.0, 0.0, 0.2, 0.1, 0.06, 0.01, 0.0, 0.0, 0.0, 0.0])
    push = Push.between((10.0, 0.0), 0.7, 0.8)
    log = replace(_log(t, e), pushes=(push,))
    assert push_recovery_times(log, 0.05, exact_end=True) == [pytest.approx(2.0 - 0.8)]
    late = replace(log, pushes=(Push((1.0, 0.0), 10.0),))
    assert push_recovery_times(late, 0.05) == []  # it ends after the run


def test_a_full_body_is_judged_up_to_the_exchange_that_reached_the_path_end():
    """A full body walks on in place at the path's end until its duration ends (the LIP loop stops there): its
    errors after that exchange are not paper A's path following (Digit v3's circle: 0.07 m before, 0.23 m after)."""
    from dataclasses import replace

    from lipmpcc.studies.path_metrics import _path_end_time

    t = np.arange(10) * 0.4
    e = np.array([0.5, 0.0, 0.02, -0.03, 0.01, 0.02, 0.2, -0.3, 0.1, 0.0])
    th_ref = np.array([0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0, 1.0, 1.0, np.nan])
    end = _path_end_time(t, th_ref, 1.0)
    assert end == pytest.approx(2.4)
    assert _path_end_time(t, th_ref, 1.5) is None
    log = replace(_log(t, e), path_end_t=end)
    assert paper_a_fields(log, (), settle_time=0.3)["contouring_error_max_m"] == pytest.approx(0.2)
    assert paper_a_fields(_log(t, e), (), settle_time=0.3)["contouring_error_max_m"] == pytest.approx(0.3)


def _log(t: np.ndarray, e: np.ndarray):
    from lipmpcc.plots.logs import PathFollowingLog

    z = np.zeros(len(t))
    return PathFollowingLog(t=t, e_contouring=e, e_lag=z, e_cartesian=z, footholds=np.zeros((len(t), 3)), sides=z,
                            step_offsets=np.zeros((len(t), 2)), v_avg_t=t, v_avg=z, v_max=0.1, tc=t,
                            com=np.zeros((len(t), 4)), obstacles=np.zeros((0, len(t), 2)), clearance=np.zeros(0))


def test_the_progress_along_the_path_reads_the_lip_run(overtake):
    trace = progress_trace(overtake, "length")
    assert len(trace.t) == len(overtake.lip_log.t) and np.all(np.diff(trace.progress) > -1e-9)
    assert trace.clearance.shape == (1, len(trace.t))
    assert assess_run(overtake, "overtake") is not None


def test_overtake_landmarks_of_a_synthetic_pass() -> None:
    """Step aside left (ē_c < 0), draw level at 6 s, cross back at 8 s and go 0.1 m beyond; and a run that never passes."""
    from types import SimpleNamespace

    from lipmpcc.studies.path_metrics import overtake_landmarks

    tc = np.linspace(0.0, 10.0, 1001)
    e_c = np.where(tc < 8.0, -0.5 * np.sin(np.pi * tc / 8.0), 0.1 * np.sin(np.pi * (tc - 8.0) / 2.0))
    ob = SimpleNamespace(s0=1.0, speed=0.5)  # an obstacle along the path: 1 m in, at 0.5 m/s
    lm = overtake_landmarks(SimpleNamespace(tc=tc, theta_c=1.0 * tc - 2.0, e_contouring_c=e_c), ob)
    assert lm.i_aside == 400 and lm.t_aside == pytest.approx(4.0) and lm.passed and lm.t_pass == pytest.approx(6.01, abs=0.02)
    assert lm.t_cross == pytest.approx(8.01, abs=0.02) and lm.e_back == pytest.approx(0.1) and lm.ahead[-1] == pytest.approx(2.0)
    slow = overtake_landmarks(SimpleNamespace(tc=tc, theta_c=0.4 * tc, e_contouring_c=-np.abs(e_c)), ob)
    assert not slow.passed and np.isnan(slow.t_pass) and slow.t_cross is None and slow.e_back <= 0
