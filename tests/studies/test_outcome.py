"""lipmpcc.studies.outcome: one outcome per run, collided > fell > stopped_early > completed."""

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
