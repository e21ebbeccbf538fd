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
    assert "| `lip-overtake-mpcc` | 3D-LIP | overtakes the obstacle; no collision;" in report
    assert "](lip-circle/circle.png)" in report and "## Paper A" in report and "## Paper B" not in report
    html = (tmp_path / "report.html").read_text()
    assert html.count('<img alt="lip-circle: circle" src="data:image/png;base64,') == 1  # embedded: works offline
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
    assert "| I L=0.55 W=+0.15 | alip-qp |" in report and "| fails | differs |" in report  # the paper's QP fails
    assert "enters the stones from ALIP-MPC's approach" in report
    assert "[reproduce] alip-stones-I_L0.55_W+0.15-alip-mpc: ok" in capsys.readouterr().out


def test_the_study_list():
    """52 studies, reduced models first: paper A on the LIP (4), paper B on the ALIP (9 Table II courses x 2
    planners, the push test x 3), then the same on digit_like (tagged "fullbody") with walk and stand."""
    from lipmpcc.reproduce import all_studies, full_body_studies
    from lipmpcc.studies import names

    studies = all_studies()
    ids = [s.name for s in studies]
    assert len(ids) == len(set(ids)) == 52
    assert ids[:4] == ["lip-circle", "lip-circle-push", "lip-overtake-cartesian", "lip-overtake-mpcc"]
    prefixes = [i.split("-")[0] for i in ids]
    assert prefixes == sorted(prefixes, key=["lip", "alip", "digit"].index)  # reduced models first
    assert prefixes.count("alip") == 21 and prefixes.count("digit") == 27
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
    # a criterion in named parts names the parts a run missed, with the measured value (the report's reason)
    cart = {s.name: s for s in rp.all_studies()}["digit-overtake-cartesian"]
    ran = {"fell": False, "fall_time_s": None, "overtook": False, "cartesian_error_max_m": 0.05, "min_clearance_m": 0.05,
           "collided": True, "min_body_clearance_m": -0.009}
    assert rp._check(cart, ran) is False and cart.criterion == cart.check.text
    assert rp._missed_parts(cart, ran) == ["no part of the body in the obstacle (min_body_clearance_m = -0.009)"]
    assert rp._missed_parts(cart, {**ran, "collided": False, "cartesian_error_max_m": 0.097}) == [
        "Cartesian error <= 0.06 m (cartesian_error_max_m = 0.097)"]
    assert rp._check(cart, {**ran, "collided": False}) is True and rp._missed_parts(study, {}) == []
    assert rp.missed({"studies": {"a": {"meets_criterion": True}, "b": {"meets_criterion": None},
                                  "c": {"meets_criterion": False}}}) == ["c"]


# ---- issue 14: exit codes, expected failures, atomic study folders, partial reports, interrupts -----------
import os  # noqa: E402
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import pytest  # noqa: E402
from .conftest import package_env, default_sigint

from lipmpcc.cli import EXIT_ERROR, EXIT_INTERRUPTED, EXIT_OK, EXIT_USAGE  # noqa: E402
from lipmpcc.studies import RunResult  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
GOOD_CIRCLE = {"contouring_error_max_m": 0.01, "contouring_error_rms_m": 0.01, "solver_failures": 0, "fell": False,
               "push_recovery_s": [0.5]}


def _fake_run(monkeypatch, behaviour):
    """Replace the studies reproduce runs: ``behaviour(call_index, options)`` returns a summary or raises."""
    from lipmpcc import reproduce as rp

    calls: list = []

    def run(opts):
        calls.append(opts)
        return RunResult(summary=behaviour(len(calls) - 1, opts))

    monkeypatch.setattr(rp, "run", run)
    return calls


def test_reproduce_exits_0_when_every_study_meets_its_expectation(tmp_path, monkeypatch, capsys):
    calls = _fake_run(monkeypatch, lambda i, o: dict(GOOD_CIRCLE))
    assert main(["reproduce", "--only", "lip-circle", "--out", str(tmp_path)]) == EXIT_OK
    res = json.loads((tmp_path / "results.json").read_text())
    assert res["status"] == "complete" and res["not_run"] == [] and len(calls) == 2
    assert [e["status"] for e in res["studies"].values()] == ["ok", "ok"]
    assert "PARTIAL" not in (tmp_path / "report.md").read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lip-circle", "lip-circle-push", "report.html", "report.md",
                                                          "results.json"]
    assert capsys.readouterr().out.endswith("2 studies, 0 missed or failed\n")


def test_the_point_foot_push_test_is_an_expected_failure_and_a_missed_study_exits_1(tmp_path, monkeypatch, capsys):
    from lipmpcc.reproduce import expected_failures, missed

    _fake_run(monkeypatch, lambda i, o: {"fell": True, "fall_step": 11, "solver_failures": 0})
    assert main(["reproduce", "--only", "alip-push-alip-mpc", "--out", str(tmp_path)]) == EXIT_ERROR
    res = json.loads((tmp_path / "results.json").read_text())
    point, foot = res["studies"]["alip-push-alip-mpc"], res["studies"]["alip-push-alip-mpc-foot"]
    assert point["meets_criterion"] is False and point["status"] == "expected failure"
    assert "point-foot ALIP" in point["expected_failure"]
    assert foot["meets_criterion"] is False and foot["status"] == "MISSED" and "expected_failure" not in foot
    assert missed(res) == ["alip-push-alip-mpc-foot"] and expected_failures(res) == ["alip-push-alip-mpc"]
    report = (tmp_path / "report.md").read_text()
    rows = {ln.split("|")[1].strip(): [c.strip() for c in ln.split("|")[2:-1]] for ln in report.splitlines()
            if ln.startswith("| `alip-push")}
    assert rows["`alip-push-alip-mpc`"][3:5] == ["survives", "expected-fail: fell"] and "point foot" in rows["`alip-push-alip-mpc`"][-1]
    assert rows["`alip-push-alip-mpc-foot`"][3:5] == ["survives", "differs: fell"]
    assert "**exits 1**: 1 study misses its criterion" in report and "- `alip-push-alip-mpc-foot` (differs: fell)" in report
    out = capsys.readouterr().out
    assert "[reproduce] alip-push-alip-mpc: expected failure" in out
    assert "1 missed or failed: alip-push-alip-mpc-foot; 1 expected failure: alip-push-alip-mpc" in out


def test_reproduce_exits_1_when_every_study_fails_and_each_leaves_failed_json(tmp_path, monkeypatch, capsys):
    def broken(i, o):
        raise ValueError("Unrecognized backend string 'bogus'")

    (tmp_path / "lip-circle").mkdir()
    (tmp_path / "lip-circle" / "summary.json").write_text('{"fell": false}')  # an earlier success
    _fake_run(monkeypatch, broken)
    assert main(["reproduce", "--only", "lip-", "--out", str(tmp_path)]) == EXIT_ERROR
    res = json.loads((tmp_path / "results.json").read_text())
    assert res["status"] == "complete" and [e["status"] for e in res["studies"].values()] == ["error"] * 4
    assert [p.name for p in (tmp_path / "lip-circle").iterdir()] == ["failed.json"]  # not the old summary
    assert capsys.readouterr().out.endswith("4 studies, 4 missed or failed: lip-circle, lip-circle-push, "
                                            "lip-overtake-cartesian, lip-overtake-mpcc\n")


def test_an_interrupt_leaves_a_report_marked_partial_not_an_old_complete_one(tmp_path, monkeypatch, capsys):
    (tmp_path / "report.md").write_text("# lipmpcc reproduction report\n(an old, complete one)\n")
    (tmp_path / "report.html").write_text("<html>an old, complete one</html>")
    (tmp_path / "results.json").write_text('{"status": "complete"}')
    seen_report: list = []
    seen_html: list = []

    def behaviour(i, o):
        seen_report.append((tmp_path / "report.md").read_text() if (tmp_path / "report.md").exists() else None)
        seen_html.append((tmp_path / "report.html").exists())
        if i == 1:
            raise KeyboardInterrupt
        return dict(GOOD_CIRCLE)

    _fake_run(monkeypatch, behaviour)
    assert main(["reproduce", "--only", "lip-", "--out", str(tmp_path)]) == EXIT_INTERRUPTED
    captured = capsys.readouterr()
    assert captured.err == "lipmpcc: interrupted\n" and "Traceback" not in captured.out
    assert seen_report[0] is None and seen_html[0] is False  # the stale report went before the first study
    assert "PARTIAL REPORT (still running or stopped)" in seen_report[1]  # rewritten after each study
    report = (tmp_path / "report.md").read_text()
    assert "**PARTIAL REPORT (interrupted)**: 1 of 4 studies ran." in report
    assert "Not run: lip-circle-push, lip-overtake-cartesian, lip-overtake-mpcc." in report
    assert "PARTIAL REPORT (interrupted)" in (tmp_path / "report.html").read_text()
    res = json.loads((tmp_path / "results.json").read_text())
    assert res["status"] == "interrupted" and list(res["studies"]) == ["lip-circle"]
    assert not (tmp_path / "lip-circle-push").exists()  # the interrupted study left nothing
    assert not any(p.name.startswith(".") or p.name.endswith(".lock") for p in tmp_path.iterdir())
    assert not (tmp_path.parent / f"{tmp_path.name}.lock").exists()


def test_an_interrupt_turned_into_another_error_is_still_an_interrupt(tmp_path, monkeypatch, capsys):
    """A Ctrl-C that a library turns into another error (the full-body helper thread's
    'release unlocked lock') is not recorded as a study error."""

    def behaviour(i, o):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            raise RuntimeError("release unlocked lock")

    _fake_run(monkeypatch, behaviour)
    assert main(["reproduce", "--only", "lip-circle", "--out", str(tmp_path)]) == EXIT_INTERRUPTED
    res = json.loads((tmp_path / "results.json").read_text())
    assert res["status"] == "interrupted" and res["studies"] == {}


def test_reproduce_refuses_an_unusable_out_and_a_busy_one(tmp_path, monkeypatch, capsys):
    from lipmpcc.studies.outputs import OutputLock

    calls = _fake_run(monkeypatch, lambda i, o: dict(GOOD_CIRCLE))
    (tmp_path / "f").write_text("x")
    for out in ("", str(tmp_path / "f")):
        assert main(["reproduce", "--only", "lip-circle", "--out", out]) == EXIT_USAGE
        assert capsys.readouterr().err.startswith("lipmpcc: error: --out = ")
    with OutputLock(tmp_path / "r"):
        assert main(["reproduce", "--only", "lip-circle", "--out", str(tmp_path / "r")]) == EXIT_ERROR
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "another lipmpcc run" in err and calls == []


_SLOW_SECOND_STUDY = """
import sys, time
from lipmpcc import reproduce as rp
from lipmpcc.studies import RunResult
n = []
def run(opts):
    n.append(1)
    if len(n) == 2:
        time.sleep(60)
    return RunResult(summary={"contouring_error_max_m": 0.01, "solver_failures": 0, "push_recovery_s": []})
rp.run = run
from lipmpcc.cli import main
sys.exit(main(["reproduce", "--only", "lip-", "--out", sys.argv[1]]))
"""


def test_ctrl_c_stops_reproduce_with_one_line_and_a_partial_report(tmp_path):
    out = tmp_path / "r"
    env = package_env()
    p = subprocess.Popen([sys.executable, "-c", _SLOW_SECOND_STUDY, str(out)], preexec_fn=default_sigint, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env)
    try:
        t_end = time.time() + 60
        while time.time() < t_end and not (out / "results.json").exists():
            time.sleep(0.05)
        time.sleep(0.5)
        t0 = time.time()
        p.send_signal(signal.SIGINT)
        stdout, stderr = p.communicate(timeout=30)
        dt = time.time() - t0
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == EXIT_INTERRUPTED and stderr == "lipmpcc: interrupted\n" and dt < 3.0
    res = json.loads((out / "results.json").read_text())
    assert res["status"] == "interrupted" and list(res["studies"]) == ["lip-circle"]
    assert res["not_run"] == ["lip-circle-push", "lip-overtake-cartesian", "lip-overtake-mpcc"]
    assert "PARTIAL REPORT (interrupted)" in (out / "report.md").read_text()


def test_an_empty_only_is_refused_not_read_as_every_study() -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.reproduce import select_studies

    for only in ("", "  "):
        with pytest.raises(InvalidInputError, match="--only"):
            select_studies(only)
    assert len(select_studies(None)) > 40


# ---- issue 25: lipmpcc reproduce --robot MODEL.xml -------------------------------------------------------
def _model(tmp_path: Path, name: str = "My Robot_v3.xml") -> Path:
    p = tmp_path / "models" / name
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text("<mujoco/>")
    return p


def test_robot_option_adds_every_full_body_study_on_the_model_under_its_prefix(tmp_path):
    from lipmpcc.reproduce import all_studies, full_body_studies, model_prefix, select_studies

    model = str(_model(tmp_path))
    assert model_prefix(model) == "my-robot-v3" and model_prefix("digit_like") == "digit"
    assert model_prefix(str(tmp_path / "digit.xml")) == "digit-model"  # never the digit_like studies' names
    base, extra = full_body_studies(), full_body_studies(model)
    assert len(extra) == len(base) == 27
    for b, e in zip(base, extra):
        assert e.name == "my-robot-v3" + b.name[len("digit"):] and e.options == {**b.options, "robot": model}
        assert e.placement()["variant"] == b.name == b.placement()["variant"] and "fullbody" in e.tags
        assert "digit_like" not in e.title and (b.check is None) == (e.check is None)
    names = [s.name for s in all_studies(model)]
    assert len(names) == len(set(names)) == 79 and names[:52] == [s.name for s in all_studies()]
    assert [s.name for s in select_studies("my-robot-v3-stones-II-", model)] == [
        "my-robot-v3-stones-II-alip-mpc", "my-robot-v3-stones-II-alip-qp"]
    assert [s.name for s in select_studies("lip-circle", model)] == ["lip-circle", "lip-circle-push"]
    assert [s.name for s in select_studies("digit-stones-II-alip-mpc", model)] == [  # both models' profile II
        "digit-stones-II-alip-mpc", "my-robot-v3-stones-II-alip-mpc"]


def test_extra_robot_reads_the_option_then_the_environment_and_refuses_a_bad_model(tmp_path, monkeypatch):
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.reproduce import ROBOT_ENV, extra_robot

    model = _model(tmp_path)
    monkeypatch.delenv(ROBOT_ENV, raising=False)
    assert extra_robot() is None  # as before: digit_like alone
    assert extra_robot(str(model)) == str(model.resolve())
    monkeypatch.setenv(ROBOT_ENV, str(model))
    assert extra_robot() == str(model.resolve())
    monkeypatch.setenv(ROBOT_ENV, "  ")
    assert extra_robot() is None
    for bad in (str(tmp_path / "absent.xml"), "digit_like", str(tmp_path)):
        with pytest.raises(InvalidInputError, match="--robot"):
            extra_robot(bad)
    monkeypatch.setenv(ROBOT_ENV, str(tmp_path / "absent.xml"))  # as the tests: no model, digit_like alone
    with pytest.warns(UserWarning, match="LIPMPCC_DIGIT_V3"):
        assert extra_robot() is None
    monkeypatch.setenv(ROBOT_ENV, str(tmp_path))  # a folder: not a model file
    with pytest.warns(UserWarning):
        assert extra_robot() is None
    monkeypatch.setenv(ROBOT_ENV, str(tmp_path / "models" / "My Robot_v3.xml"))
    with pytest.raises(InvalidInputError, match="--robot"):
        extra_robot("digit_like")  # the option first


def test_reproduce_robot_runs_the_model_and_reports_it_as_its_own_column(tmp_path, monkeypatch, capsys):
    from lipmpcc.reproduce import ROBOT_ENV

    monkeypatch.delenv(ROBOT_ENV, raising=False)
    model = _model(tmp_path, "digit-v3.xml")
    stones = {"fell": False, "fall_step": None, "steps_completed": 32, "step_rmse_m": 0.012, "stones_violated": 0,
              "step_duration_min_s": 0.4, "step_duration_max_s": 0.6, "solver_failures": 0, "relaxed_solves": 0,
              "real_time_factor": 0.5, "outcome": "completed"}

    def behaviour(i, opts):
        if opts.robot == "digit_like":
            return dict(stones)
        return {**stones, "fell": True, "fall_step": 12, "outcome": "fell", "solver_failures": 58, "relaxed_solves": 38}

    calls = _fake_run(monkeypatch, behaviour)
    monkeypatch.setattr("lipmpcc.reproduce._wbc_available", lambda: True)
    out = tmp_path / "out"
    code = main(["reproduce", "--only", "digit-v3-stones-IV-alip-mpc", "--robot", str(model), "--out", str(out)])
    assert code == EXIT_ERROR and [c.robot for c in calls] == [str(model.resolve())]  # the fall is a missed criterion
    assert "digit-v3-stones-IV-alip-mpc" in capsys.readouterr().out
    res = json.loads((out / "results.json").read_text())
    assert res["robots"] == ["digit_like", str(model.resolve())]
    e = res["studies"]["digit-v3-stones-IV-alip-mpc"]
    assert e["variant"] == "digit-stones-IV-alip-mpc" and e["solver_failures"] == 58 and e["relaxed_solves"] == 38
    calls.clear()
    code = main(["reproduce", "--only", "digit-stones-IV-alip-mpc", "--out", str(out)])  # without --robot: as before
    assert code == EXIT_OK and [c.robot for c in calls] == ["digit_like"]
    assert json.loads((out / "results.json").read_text())["robots"] == ["digit_like"]
    monkeypatch.setenv(ROBOT_ENV, str(model))
    calls.clear()
    code = main(["reproduce", "--only", "digit", "--out", str(out)])
    ran = {c.robot for c in calls}
    assert ran == {"digit_like", str(model.resolve())} and len(calls) == 54
    report = (out / "report.md").read_text()
    assert "## The full body on each model" in report
    assert "| study | paper | digit_like (MuJoCo) | digit-v3 (MuJoCo) |" in report
    assert ("| `digit-stones-IV-alip-mpc` | 0.024 m | RMSE 0.012 m (pass) | fell at stone 12 (differs: fell; 58 failed, "
            "38 relaxed) |") in report


def test_reproduce_refuses_a_missing_model_in_one_line(tmp_path, capsys):
    assert main(["reproduce", "--only", "lip-circle", "--robot", str(tmp_path / "no.xml"), "--out", str(tmp_path / "o")]) == EXIT_USAGE
    err = capsys.readouterr().err
    assert "--robot" in err and "MODEL.xml" in err and "Traceback" not in err and not (tmp_path / "o").exists()
