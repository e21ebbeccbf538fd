"""Markdown tables of the stepping-stone studies, on one markdown-table function."""

from __future__ import annotations

from lipmpcc.report import md_table, sweep_markdown, table_markdown
from lipmpcc.report.tables import fmt


def test_md_table_has_a_rule_and_writes_empty_cells_as_one_space() -> None:
    assert md_table(["a", "b"], [["1", ""], ["", "x"]]) == "| a | b |\n|---|---|\n| 1 | |\n| | x |"


def test_a_bar_in_a_cell_does_not_split_it() -> None:
    assert md_table(["a"], [["x | y"]]).splitlines()[2] == r"| x \| y |"


def test_fmt_writes_floats_timings_and_lists_readably() -> None:
    assert fmt(0.0123456) == "0.01235" and fmt(float("nan")) == "nan"
    assert fmt({"median": 1.0, "p90": 2.0}) == "median 1 ms, p90 2 ms"
    assert fmt([0.031, 0.2]) == "[0.03, 0.20]" and fmt(3) == "3"


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
