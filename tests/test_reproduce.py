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


def test_the_study_list():
    """51 studies, reduced models first: paper A on the LIP (4), paper B on the ALIP (9 Table II courses x 2
    planners, the push test x 3), then the same on digit_like (tagged "fullbody") with walk and stand."""
    from lipmpcc.reproduce import all_studies, full_body_studies
    from lipmpcc.studies import names

    studies = all_studies()
    ids = [s.name for s in studies]
    assert len(ids) == len(set(ids)) == 51
    assert ids[:4] == ["lip-circle", "lip-circle-push", "lip-overtake-cartesian", "lip-overtake-mpcc"]
    prefixes = [i.split("-")[0] for i in ids]
    assert prefixes == sorted(prefixes, key=["lip", "alip", "digit"].index)  # reduced models first
    assert prefixes.count("alip") == 21 and prefixes.count("digit") == 26
    fb = full_body_studies()
    assert [s.name for s in studies if "fullbody" in s.tags] == [s.name for s in fb]
    assert all(s.options["robot"] == "digit_like" for s in fb)
    for s in studies:
        assert s.options["scenario"] in names() and s.keys and callable(s.paper)
        assert (s.check is None) == (s.criterion == "reported"), s.name
    by_name = {s.name: s for s in studies}
    assert by_name["alip-stones-II-alip-mpc"].options == {"scenario": "stones", "planner": "alip-mpc", "robot": "alip",
                                                          "profile": "II", "seed": 0}
    assert by_name["alip-push-alip-mpc-foot"].options["cop_range"] == (0.06, 0.025)
    assert by_name["lip-circle"].options == {"scenario": "circle", "planner": "mpcc", "robot": "lip"}


def test_criteria_and_missed_studies(tmp_path, monkeypatch, capsys):
    """A full-body study without the C++ controller is reported as skipped (not run); a criterion on a
    field the run did not produce is missed; missed() lists errors and missed criteria."""
    from lipmpcc import reproduce as rp

    monkeypatch.setattr(rp, "_wbc_available", lambda: False)
    res = rp.reproduce(tmp_path, only="digit-walk")
    assert list(res["studies"]) == ["digit-walk"] and "skipped" in res["studies"]["digit-walk"]["error"]
    assert rp.missed(res) == ["digit-walk"] and (tmp_path / "report.md").exists()
    study = {s.name: s for s in rp.all_studies()}["lip-circle"]
    assert rp._check(study, {}) is False  # KeyError: the criterion is not met
    assert rp.missed({"studies": {"a": {"meets_criterion": True}, "b": {"meets_criterion": None},
                                  "c": {"meets_criterion": False}}}) == ["c"]
