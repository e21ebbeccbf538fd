"""Markdown of the reproduction report and of the stepping-stone tables."""

from __future__ import annotations

import json

from lipmpcc.report import md_table, report_markdown, sweep_markdown, table_markdown, write_report


def test_md_table_has_a_rule_and_writes_empty_cells_as_one_space() -> None:
    assert md_table(["a", "b"], [["1", ""], ["", "x"]]) == "| a | b |\n|---|---|\n| 1 | |\n| | x |"


def test_report_lists_every_study_its_figures_and_errors(tmp_path) -> None:
    results = {
        "fast": True,
        "wall_s": 12.3,
        "studies": {
            "s1": {"title": "One", "ours": {"err": 0.012345, "solve_ms": {"median": 1.0, "p90": 2.0}}, "paper": 0.02,
                   "criterion": "err <= 0.05", "meets_criterion": True, "figures": ["s1/a.png"]},
            "s2": {"title": "Two", "error": "ValueError: boom"},
        },
    }
    md = report_markdown(results)
    assert "Fast mode: True. Total time: 12 s." in md
    assert "| s1 | err <= 0.05 | yes | - | err=0.01235; solve_ms=median 1 ms, p90 2 ms | 0.02 |" in md  # no outcome: older
    assert "| s2 | | error | | ValueError: boom | |" in md
    assert "### One\n\n![s1](s1/a.png)" in md
    assert write_report(results, tmp_path) == tmp_path / "report.md"
    assert json.loads((tmp_path / "results.json").read_text())["studies"]["s2"]["error"] == "ValueError: boom"


def test_report_shows_how_each_run_ended_and_its_warnings() -> None:
    """Outcomes cannot hide: a fall, a collision, solver failures and relaxed re-solves are in the table,
    a baseline's expected fall is marked, and the runs' warnings are listed."""
    base = {"title": "T", "ours": {}, "paper": None, "criterion": "c", "meets_criterion": True, "figures": []}
    results = {"fast": True, "wall_s": 1.0, "studies": {
        "a": {**base, "outcome": "completed", "solver_failures": 0, "relaxed_solves": 0, "warnings": []},
        "b": {**base, "outcome": "collided", "solver_failures": 3, "relaxed_solves": 0, "meets_criterion": False,
              "warnings": ["MuJoCo: simulation unstable at t=1.2 s"]},
        "c": {**base, "outcome": "fell", "expected_outcome": "fell", "relaxed_solves": 11, "warnings": []},
    }}
    md = report_markdown(results)
    assert "| a | c | yes | completed |" in md
    assert "| b | c | **no** | collided; 3 solver failures |" in md
    assert "| c | c | yes | fell (expected); 11 relaxed |" in md
    assert "- b: MuJoCo: simulation unstable at t=1.2 s" in md


def test_stone_tables() -> None:
    rows = [
        {"case": "II seed 0", "planner": "alip-mpc", "fell": False, "step_rmse_m": 0.0061, "paper_rmse_m": 0.023, "solver_failures": 0},
        {"case": "II seed 0", "planner": "alip-qp", "fell": True, "fall_step": 9, "paper_rmse_m": None, "solver_failures": 0},
    ]
    assert table_markdown(rows).splitlines()[2] == "| II seed 0 | 0.006 | 0.023 | falls at stone 9 | fails | 0 |"
    sweep = [{"push": "stone 5", "scale": 0.5, "planner": "alip-mpc", "fell": False, "fall_step": None},
             {"push": "stone 5", "scale": 0.5, "planner": "alip-qp", "fell": True, "fall_step": 6}]
    assert sweep_markdown(sweep).splitlines() == [
        "| push | scale | alip-mpc | alip-qp |", "|---|---|---|---|", "| stone 5 | 0.5 | survives | falls at stone 6 |",
    ]


def test_a_report_of_a_run_that_did_not_end_is_marked_partial(tmp_path) -> None:
    results = {
        "fast": False, "wall_s": 3.0, "status": "interrupted", "not_run": ["s2", "s3"],
        "studies": {"s1": {"title": "One", "ours": {"fell": True}, "paper": "survives", "criterion": "survives",
                           "meets_criterion": False, "expected_failure": "a point foot cannot", "figures": []}},
    }
    md = report_markdown(results)
    assert md.splitlines()[2] == "**PARTIAL REPORT (interrupted)**: 1 of 3 studies ran."
    assert "Not run: s2, s3." in md
    assert "| s1 | survives | no (expected failure) | - | fell=True | survives |" in md
    assert "- s1: a point foot cannot" in md
    results["status"] = "running"
    assert "**PARTIAL REPORT (still running or stopped)**" in report_markdown(results)
    results["status"] = "complete"
    results["not_run"] = []
    assert "PARTIAL" not in report_markdown(results)
    write_report(results, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report.md", "results.json"]  # no temporary file left
