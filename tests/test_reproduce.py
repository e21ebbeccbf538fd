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
