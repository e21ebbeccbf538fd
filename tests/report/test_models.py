"""The full-body studies with one column per model (lipmpcc reproduce --robot MODEL.xml), from fake entries."""

from __future__ import annotations

from lipmpcc.report.files import report_markdown
from lipmpcc.report.marks import judge
from lipmpcc.report.models import full_body_robots, model_cell, models_table

from . import synthetic

V3 = "/models/digit-v3/digit-v3.xml"


def _with_model() -> dict:
    """The synthetic results with digit-v3's push test (fell at stone 8) and its profile II (completed), and
    digit_like's profile II (fell at stone 20)."""
    res = synthetic.results()
    push = res["studies"]["digit-push-alip-mpc"]
    res["studies"]["digit-v3-push-alip-mpc"] = {
        **push, "title": "Paper B Fig. 7: push test, alip-mpc, digit-v3", "robot": V3, "variant": "digit-push-alip-mpc",
        "ours": {"fell": True, "fall_step": 8}, "outcome": "fell", "meets_criterion": False, "solver_failures": 45,
        "relaxed_solves": 3}
    res["studies"]["digit-stones-II-alip-mpc"] = {
        **res["studies"]["alip-stones-II-alip-mpc"], "title": "Paper B Table II, profile II, alip-mpc, digit_like",
        "robot": "digit_like", "figures": [], "ours": {"fell": True, "fall_step": 20}, "outcome": "fell",
        "meets_criterion": False}
    res["studies"]["digit-v3-stones-II-alip-mpc"] = {
        **res["studies"]["alip-stones-II-alip-mpc"], "title": "Paper B Table II, profile II, alip-mpc, digit-v3",
        "robot": V3, "variant": "digit-stones-II-alip-mpc", "figures": [],
        "ours": {"fell": False, "steps_completed": 32, "step_rmse_m": 0.014}}
    return res


def test_the_models_in_order_reduced_ones_left_out():
    res = _with_model()
    assert full_body_robots(res["studies"]) == ["digit_like", V3]
    assert full_body_robots(synthetic.results()["studies"]) == ["digit_like"]


def test_one_column_per_model_a_row_per_variant():
    res = _with_model()
    studies = res["studies"]
    marks = {n: judge(str(e.get("variant") or n), e) for n, e in studies.items()}
    assert models_table(synthetic.results()["studies"], marks) is None  # one model: nothing side by side
    t = models_table(studies, marks)
    assert t.header == ("study", "paper", "digit_like (MuJoCo)", "digit-v3 (MuJoCo)")
    rows = {r[0]: r for r in t.rows}
    assert rows["`digit-push-alip-mpc`"][1:] == ("survives", "completed (pass; 11 failed, 11 relaxed)",
                                                 "fell at stone 8 (differs: fell; 45 failed, 3 relaxed)")
    assert rows["`digit-stones-II-alip-mpc`"][1:] == ("0.023 m", "fell at stone 20 (differs: fell)", "RMSE 0.014 m (pass)")
    assert rows["`digit-walk`"][1:] == ("(not in the papers)", "completed (pass)", "–")
    assert [r[0] for r in t.rows] == ["`digit-push-alip-mpc`", "`digit-overtake-mpcc`", "`digit-walk`",
                                      "`digit-stones-II-alip-mpc`"]  # digit_like's names, in the entries' order
    err = {"error": "RuntimeError: boom", "status": "error", "robot": V3}
    assert model_cell(err, judge("x", err)) == "error: RuntimeError: boom"


def test_the_report_shows_the_model_beside_digit_like_and_the_papers():
    md = report_markdown(_with_model())
    assert "## The full body on each model" in md and "[The full body on each model](#" in md
    assert "| `digit-v3-push-alip-mpc` | digit-v3 (MuJoCo) | alip-mpc |" in md  # its row in Fig. 7's table
    assert "On the **digit-v3 (MuJoCo)**:" in md  # its own Table II
    table_ii = md[md.index("### Table II"):md.index("### Fig. 4")]
    assert "side by side" in table_ii and "| `digit-stones-II-alip-mpc` | 0.023 m | fell at stone 20 (differs: fell) | RMSE 0.014 m (pass) |" in table_ii
