"""lipmpcc.studies.outcome: one outcome per run, collided > fell > stopped_early > (path: completed at the end >
trailing > stalled > incomplete) > completed."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.studies.outcome import OUTCOMES, add_outcome, collided, outcome


@pytest.mark.parametrize(
    ("fell", "hit", "early", "expected"),
    [
        (False, False, None, "completed"),
        (False, False, "", "completed"),
        (False, False, "planner failed", "stopped_early"),
        (True, False, "planner failed", "fell"),
        (True, True, "planner failed", "collided"),
        (False, True, None, "collided"),
    ],
)
def test_precedence(fell, hit, early, expected):
    assert outcome(fell, hit, early) == expected
    assert expected in OUTCOMES


def test_collided_reads_the_whole_body_first():
    assert collided(-0.01) and not collided(0.0) and not collided(None) and not collided(float("nan"))
    assert not collided(-0.05, 0.02)  # the disks overlap, the robot's geometry does not
    assert collided(0.10, -0.001)  # an arm brushes the obstacle the disks clear
    assert collided(np.float64(-0.2), None)


def test_add_outcome_only_adds_fields_and_reads_the_loop_result():
    s = {"fell": False, "min_clearance_m": 0.3, "solver_failures": 2, "steps": 7}
    before = dict(s)
    res = SimpleNamespace(relaxed_solves=11, warnings=["MuJoCo: simulation unstable at t=0.52 s"])
    add_outcome(s, result=res, warnings=["one of ours"])
    assert {k: s[k] for k in before} == before
    assert s["relaxed_solves"] == 11 and s["warnings"] == ["MuJoCo: simulation unstable at t=0.52 s", "one of ours"]
    assert s["collided"] is False and s["outcome"] == "completed" and s["stopped_early"] is None
    assert s["min_body_clearance_m"] is None and s["expected_outcome"] is None


def test_add_outcome_defaults_without_a_loop_result():
    s = add_outcome({"fell": True}, stopped_early="planner failed", expected_outcome="fell")
    assert s["relaxed_solves"] == 0 and s["warnings"] == [] and s["min_clearance_m"] is None
    assert s["outcome"] == "fell" and s["stopped_early"] == "planner failed" and s["expected_outcome"] == "fell"
    s = add_outcome({"fell": False}, result=SimpleNamespace(stopped_early="MuJoCo diverged at t=0.13 s"))
    assert s["outcome"] == "stopped_early" and "diverged" in s["stopped_early"]
    assert math.isclose(add_outcome({"fell": False, "min_clearance_m": -0.1})["min_clearance_m"], -0.1)
    assert add_outcome({"fell": False, "min_clearance_m": -0.1})["outcome"] == "collided"


def test_bad_expected_outcome_is_refused():
    with pytest.raises(InvalidInputError, match="expected_outcome"):
        add_outcome({"fell": False}, expected_outcome="survived")


def test_run_outcome_of_a_written_summary_and_expected_baselines() -> None:
    from lipmpcc.studies.outcome import is_expected, run_outcome

    assert run_outcome({}) == "completed"  # an older summary: no outcome fields
    assert run_outcome({"fell": True, "collided": True}) == "collided"
    assert run_outcome({"outcome": "bogus", "stopped_early": "x"}) == "stopped_early"  # an invalid field is re-derived
    assert run_outcome({"outcome": "fell"}) == "fell"
    assert is_expected({"outcome": "fell", "expected_outcome": "fell"})
    assert not is_expected({"outcome": "completed", "expected_outcome": "fell"})  # a baseline that survived
    assert not is_expected({"outcome": "collided", "expected_outcome": "fell"})
    assert not is_expected({"outcome": "fell", "expected_outcome": None})


# ---- issue 31: the path outcomes, from synthetic progress traces -----------------------------------------
from lipmpcc.studies.outcome import (  # noqa: E402
    BINDING_CLEARANCE_M,
    STALL_TIME_S,
    SUCCESS_OUTCOMES,
    ProgressTrace,
    assess_progress,
    is_success,
    run_outcome,
)


def _trace(progress, L=10.0, goal="end", dt=0.4, clearance=None, along=None, speed=None, by_loop=False):
    p = np.asarray(progress, dtype=float)
    t = dt * np.arange(len(p))
    return ProgressTrace(t, p, np.column_stack([p, np.zeros_like(p)]), L, goal, clearance, along, speed, by_loop)


def _ended(trace, **kw):
    a = assess_progress(trace)
    return a, add_outcome({"fell": False, "min_clearance_m": None, **kw}, path=a)


def test_a_run_that_reaches_the_end_completed():
    a, s = _ended(_trace(np.linspace(0.0, 9.8, 60)))
    assert a.reached_end and s["outcome"] == "completed" and s["reached_end"] is True
    assert s["path_length_m"] == 10.0 and s["stall"] is None and s["goal"] == "end"
    # the LIP loop's own rule (its committed path parameter reached the end) also counts
    assert assess_progress(_trace(np.linspace(0.0, 9.0, 60), by_loop=True)).reached_end


def test_a_run_that_stops_progressing_stalled_with_where_and_the_binding_obstacle():
    p = np.r_[np.linspace(0.0, 2.0, 20), np.full(40, 2.0)]  # 8 s walking, then 16 s at 2 m
    clear = np.vstack([np.linspace(3.0, 3.0, 60), np.r_[np.linspace(1.0, 0.05, 20), np.full(40, 0.04)]])
    a, s = _ended(_trace(p, clearance=clear))
    assert s["outcome"] == "stalled" and not a.reached_end
    st = s["stall"]
    assert st["t_s"] == pytest.approx(0.4 * 19) and st["progress_m"] == pytest.approx(2.0)
    assert st["position"] == [pytest.approx(2.0), 0.0] and st["duration_s"] >= STALL_TIME_S
    assert st["binding"]["kind"] == "obstacle" and st["binding"]["obstacles"] == [1]
    assert st["binding"]["clearance_m"][0] <= BINDING_CLEARANCE_M and "obstacle 1" in st["binding"]["text"]


def test_walking_backwards_is_no_progress_and_says_how_far_back():
    p = np.r_[np.linspace(0.0, 1.6, 15), np.linspace(1.6, 0.0, 60)]  # then back off the start
    a, s = _ended(_trace(p, clearance=np.full((1, 75), 2.8)))
    assert s["outcome"] == "stalled" and s["stall"]["backwards_m"] == pytest.approx(1.6)
    assert s["stall"]["binding"]["kind"] == "planner" and s["stall"]["binding"]["obstacles"] == []
    assert s["stall"]["binding"]["nearest_obstacle"] == 0


def test_a_run_still_progressing_when_its_time_runs_out_is_incomplete_never_completed():
    a, s = _ended(_trace(np.linspace(0.0, 5.0, 60)))
    assert s["outcome"] == "incomplete" and not is_success(s) and s["stall"] is None
    # paper A's set-length studies (goal "length") run through: completed, though the path goes on
    a, s = _ended(_trace(np.linspace(0.0, 5.0, 60), goal="length"))
    assert s["outcome"] == "completed" and s["reached_end"] is False
    # ... but a set-length study that stalls says so
    a, s = _ended(_trace(np.r_[np.linspace(0.0, 1.0, 10), np.full(40, 1.0)], goal="length"))
    assert s["outcome"] == "stalled"


def test_a_run_held_behind_a_slower_obstacle_along_the_path_is_trailing():
    n = 60
    t = 0.4 * np.arange(n)
    along = np.vstack([1.5 + 0.15 * t, np.full(n, np.nan)])  # obstacle 0 along the path, 1 not
    p = np.maximum(0.0, along[0] - 1.1)  # held 1.1 m behind it
    a, s = _ended(_trace(p, along=along, speed=[0.15, np.nan], clearance=np.full((2, n), 0.5)))
    assert s["outcome"] == "trailing" and is_success(s)
    assert s["trailing_obstacle"] == 0 and s["trailing_gap_m"] == pytest.approx(1.1)
    # catching up on it (the gap closing fast) is not trailing
    p2 = np.r_[np.zeros(35), np.linspace(0.0, along[0, -1] - 1.0, n - 35)]  # 4 m in the last 10 s
    assert _ended(_trace(p2, along=along, speed=[0.15, np.nan]))[1]["outcome"] == "incomplete"
    # an obstacle that moves towards the robot is never trailed
    assert _ended(_trace(p, along=along, speed=[-0.15, np.nan]))[1]["outcome"] != "trailing"
    # one that has walked on past the path's end (it does not stop there) still holds the robot behind it
    past = np.vstack([6.9 + 0.15 * t, np.full(n, np.nan)])  # 0.4 m past the end of the 10 m path at the end
    held = past[0] - 1.1
    assert _ended(_trace(held, along=past, speed=[0.15, np.nan]))[1]["outcome"] == "trailing"


def test_the_severe_outcomes_come_first_and_a_short_run_is_not_judged_stalled():
    stalled = _trace(np.r_[np.linspace(0.0, 1.0, 10), np.full(40, 1.0)])
    assert _ended(stalled, fell=True)[1]["outcome"] == "fell"
    assert _ended(stalled, min_clearance_m=-0.1)[1]["outcome"] == "collided"
    assert add_outcome({"fell": False}, stopped_early="x", path=assess_progress(stalled))["outcome"] == "stopped_early"
    short = _trace(np.full(10, 0.5))  # 3.6 s without progress: shorter than STALL_TIME_S
    assert assess_progress(short).stall is None
    # the study's progress_m is kept, not overwritten
    s = add_outcome({"fell": False, "progress_m": 1.234}, path=assess_progress(stalled))
    assert s["progress_m"] == 1.234


def test_unknown_outcomes_are_never_a_success_and_bad_traces_are_refused():
    assert SUCCESS_OUTCOMES == ("completed", "trailing")
    assert run_outcome({"outcome": "teleported"}) == "teleported" and not is_success({"outcome": "teleported"})
    with pytest.raises(InvalidInputError, match="goal"):
        _trace([0.0, 1.0], goal="somewhere")
    with pytest.raises(InvalidInputError, match="as many"):
        ProgressTrace(np.zeros(3), np.zeros(2), np.zeros((3, 2)), 1.0)


def test_a_stall_far_from_obstacles_names_those_its_plans_ran_into_else_the_planner():
    p = np.r_[np.linspace(0.0, 2.0, 20), np.full(40, 2.0)]
    far = np.full((1, 60), 1.5)
    planned = np.r_[np.full(20, 1.0), np.full(40, 0.06)][None]
    trace = ProgressTrace(0.4 * np.arange(60), p, np.column_stack([p, 0 * p]), 10.0, "end", far, planned_clearance=planned)
    b = assess_progress(trace).stall["binding"]
    assert b["kind"] == "planned" and b["planned_obstacles"] == [0] and b["obstacles"] == []
    assert "barrier held the plan back" in b["text"]
    b = assess_progress(_trace(p, clearance=far)).stall["binding"]  # plans not known
    assert b["kind"] == "planner" and b["planned_obstacles"] == [] and b["nearest_clearance_m"] == 1.5


def test_a_stall_where_the_planner_held_the_robot_in_place_names_the_obstacles_held_for():
    p = np.r_[np.linspace(0.0, 0.3, 8), np.full(42, 0.3)]
    clear = np.full((3, 50), 0.1)
    held = np.zeros((3, 50))
    held[2, 30:] = 1.0  # the planner held the robot for obstacle 2 while it stalled
    trace = ProgressTrace(0.4 * np.arange(50), p, np.column_stack([p, np.zeros_like(p)]), 4.0, "end", clear,
                          held=held)
    a, s = _ended(trace)
    b = s["stall"]["binding"]
    assert s["outcome"] == "stalled" and b["kind"] == "held" and b["held_obstacles"] == [2]
    assert "no way out" in b["text"] and "obstacle 2" in b["text"]
    # without holds the same trace binds on the obstacles near the robot
    trace = ProgressTrace(0.4 * np.arange(50), p, np.column_stack([p, np.zeros_like(p)]), 4.0, "end", clear)
    b = _ended(trace)[1]["stall"]["binding"]
    assert b["kind"] == "obstacle" and b["held_obstacles"] == []
