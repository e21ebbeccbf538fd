"""The stone-field study (issue 29): how a run is judged against the field, and the table's figures."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.stone_field import make_stone_field
from lipmpcc.studies.stone_field import FIELD_OUTCOMES, field_cases, field_course, field_table, run_field


def test_cases_alternate_without_and_with_a_pedestrian_in_the_issue_range() -> None:
    fields = field_cases([0, 1, 2, 3])
    assert [len(f.pedestrians) for f in fields] == [0, 1, 0, 1]
    for f in fields[1::2]:
        assert 0.3 <= float(np.hypot(*f.pedestrians[0].velocity)) <= 0.6


def test_course_is_the_approach_then_free_footholds() -> None:
    seq = field_course(make_stone_field(0), 5)
    assert len(seq) == 6 + 5 and not seq.is_stone.any() and np.all(np.isinf(seq.sizes[6:]))
    assert list(seq.sides[5:8]) == [1, -1, 1]  # the approach ends on the left foot: alternation holds


def test_table_reports_rates_with_wilson_intervals_and_plan_times() -> None:
    t = field_table([0, 2], choosers=("nominal",))
    (row,) = t.values()
    assert row["all"]["n"] == 2 and sum(row["outcomes"].values()) == 2
    lo, hi = row["all"]["wilson95"]
    assert 0.0 <= lo <= row["all"]["rate"] <= hi <= 1.0
    assert row["pedestrian"]["n"] == 0 and row["plan_ms"]["median"] > 0
    assert set(row["outcomes"]) == set(FIELD_OUTCOMES)


def test_a_run_off_the_stones_is_a_fall_not_a_success() -> None:
    run = run_field(make_stone_field(0), "greedy")  # fixed timing, nearest stone: it does not cross this field
    assert run.outcome in ("fell", "stalled") and not run.reached_end and run.reason


def test_bad_arguments() -> None:
    with pytest.raises(InvalidInputError, match="chooser"):
        run_field(make_stone_field(0), "best")
    with pytest.raises(InvalidInputError, match="stone_field"):
        run_field(None)  # type: ignore[arg-type]


def test_lipmpcc_run_stone_field_writes_the_outcome_fields(tmp_path) -> None:
    import json

    from lipmpcc.cli import main

    out = tmp_path / "field"
    code = main(["run", "stone-field", "--seed", "2", "--out", str(out)])
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"] == "stone-field" and s["outcome"] in FIELD_OUTCOMES
    assert code == (0 if s["outcome"] == "completed" else code) and (code == 0) == s["reached_end"]
    assert s["pedestrian_speed"] is None and s["collided"] is False and (out / "field.png").is_file()
    assert main(["run", "stone-field", "--robot", "digit_like", "--out", str(tmp_path / "x")]) == 1  # ALIP only
