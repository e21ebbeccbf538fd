"""`lipmpcc reproduce`: report and results beside the paper's numbers."""

import json

from lipmpcc import config
from lipmpcc.cli import main


def test_reproduce_reduced_paper_a(tmp_path, capsys):
    try:
        assert main(["reproduce", "--fast", "--only", "lip-", "--out", str(tmp_path)]) == 0
    finally:
        config.set_fast_mode(None)
    res = json.loads((tmp_path / "results.json").read_text())
    assert res["fast"] is True
    names = set(res["studies"])
    assert {"lip-circle", "lip-circle-push", "lip-overtake-cartesian", "lip-overtake-mpcc"} <= names
    for e in res["studies"].values():
        assert e["meets_criterion"] is True, e
        assert e["paper"]
    report = (tmp_path / "report.md").read_text()
    assert "| lip-overtake-mpcc |" in report and "![lip-circle]" in report
    assert (tmp_path / "lip-circle" / "summary.json").exists()


def test_reproduce_takes_plain_arguments_and_reads_the_papers_numbers(tmp_path, capsys):
    from lipmpcc.reproduce import missed, reproduce

    try:
        res = reproduce(tmp_path, fast=True, only="alip-stones-I_L0.55_W+0.15")
    finally:
        config.set_fast_mode(None)
    assert list(res["studies"]) == ["alip-stones-I_L0.55_W+0.15-alip-mpc", "alip-stones-I_L0.55_W+0.15-alip-qp"]
    mpc, qp = res["studies"].values()
    assert mpc["paper"] == 0.028 and qp["paper"] == "fails"  # Table II, as data/reference/paper_results.json states it
    assert mpc["meets_criterion"] is True and qp["meets_criterion"] is None and missed(res) == []
    summary = json.loads((tmp_path / "alip-stones-I_L0.55_W+0.15-alip-qp" / "summary.json").read_text())
    assert summary["paper_case"] == "I L=0.55 W=+0.15" and summary["paper_rmse_m"] is None
    report = (tmp_path / "report.md").read_text()
    assert "| alip-stones-I_L0.55_W+0.15-alip-qp | reported | - |" in report
    assert "[reproduce] alip-stones-I_L0.55_W+0.15-alip-mpc: ok" in capsys.readouterr().out
