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
    assert main(["run", "stone-field", "--robot", "lip", "--out", str(tmp_path / "x")]) == 1  # not the LIP


def test_paper_b_pushes_on_the_field_move_the_feet_and_doubled_they_fell_it() -> None:
    from lipmpcc.planners.alip_mpc import AlipMpcParams
    from lipmpcc.planners.stone_field import StoneFieldParams
    from lipmpcc.studies.stone_field import FIELD_PUSH_STEPS, field_pushes

    pushes = field_pushes(1.0)
    assert [p.step - 5 for p in pushes] == list(FIELD_PUSH_STEPS) and pushes[0].force == (150.0, 0.0)
    foot = StoneFieldParams(mpc=AlipMpcParams.paper(cop_range=(0.06, 0.025)))
    fld = make_stone_field(0)
    calm, pushed = run_field(fld, params=foot), run_field(fld, params=foot, pushes=pushes)
    assert calm.outcome == pushed.outcome == "completed"
    assert np.max(np.abs(calm.log.footholds[:10] - pushed.log.footholds[:10])) > 0.01  # the planner answered
    assert run_field(fld, params=foot, pushes=field_pushes(2.0)).outcome == "fell"
    with pytest.raises(InvalidInputError, match="push_scale"):
        field_pushes(-1.0)
    with pytest.raises(InvalidInputError, match="pushes"):
        run_field(fld, pushes=[(150.0, 0.0)])  # type: ignore[list-item]


def test_the_sweep_spec_loads_and_a_case_runs_with_its_pushes() -> None:
    from lipmpcc.sweep.spec import load_spec
    from lipmpcc.sweep.worker import run_case, worker_env

    spec = load_spec("stone_field")
    assert spec.study == "stone-field" and len(spec.cases()) == 20 * 3 * 3 * 4
    case = next(c for c in spec.cases() if c["params"]["push_scale"] == 1.0 and c["planner_name"] == "greedy-stone")
    res = run_case(case, worker_env(False))
    s = res["summary"]
    assert res["status"] == "done" and s["planner"] == "greedy-stone" and s["outcome"] in FIELD_OUTCOMES
    assert s["push_set"] == "paper-b" and len(s["pushes"]) == 4 and s["pedestrian_speed"] == pytest.approx(0.3)


def test_lipmpcc_run_stone_field_takes_a_planner_and_paper_b_pushes_only(tmp_path) -> None:
    from lipmpcc.cli import main

    assert main(["run", "stone-field", "--push-set", "paper-a", "--out", str(tmp_path / "a")]) == 2
    assert main(["run", "stone-field", "--planner", "alip-qp", "--out", str(tmp_path / "b")]) == 1
