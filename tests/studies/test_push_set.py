"""``lipmpcc run circle-push --push-set paper-b``: paper B's four pushes on the circle from the CLI and in sweeps."""

from __future__ import annotations

import json

import pytest

from lipmpcc.cli import EXIT_USAGE, main
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.studies import RunOptions, estimate_run_size
from lipmpcc.studies.run_size import PAPER_B_PUSH_RUNS
from lipmpcc.sweep.spec import parse_spec
from lipmpcc.sweep.worker import case_options, case_pushes


@pytest.fixture(scope="module")
def paper_b_run(tmp_path_factory):
    """The LIP's timed MPCC (T in [0.3, 0.5] s, re-planned at 25 Hz) under paper B's four pushes, fast mode."""
    mp = pytest.MonkeyPatch()
    mp.setenv("LIPMPCC_FAST", "1")
    out = tmp_path_factory.mktemp("pb") / "run"
    try:
        code = main(["run", "circle-push", "--push-set", "paper-b", "--step-duration-range", "0.3", "0.5",
                     "--replan-hz", "25", "--out", str(out)])
    finally:
        mp.undo()
    return code, out, json.loads((out / "summary.json").read_text())


def test_paper_b_pushes_from_the_cli_survived_with_the_durations_of_fig7(paper_b_run) -> None:
    code, out, s = paper_b_run
    assert code == 0 and s["push_set"] == "paper-b" and s["survived"] is True and s["fell"] is False
    assert s["reference_fell"] is False and s["pushes"] == 4
    rows = {r["push"]: r for r in s["paper_b_pushes"]}
    assert list(rows) == ["forward", "backward", "left", "right"]
    for r in rows.values():
        assert r["phase_s"] == pytest.approx(0.1, abs=1e-3) and abs(r["heading_error_deg"]) < 1.0
    fwd, back = rows["forward"], rows["backward"]
    assert fwd["pushed_s"] < fwd["reference_s"][1] - 0.03  # paper B Fig. 7: shorter after the forward push
    assert back["pushed_s"] > back["reference_s"][1] + 0.005  # and longer after the backward one
    assert (out / "push_durations.png").stat().st_size > 10_000 and (out / "circle-push.png").is_file()


def test_paper_a_pushes_stay_the_default_and_are_named(tmp_path) -> None:
    assert main(["run", "circle-push", "--steps", "8", "--out", str(tmp_path / "a")]) == 0
    s = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert s["push_set"] == "paper-a" and "paper_b_pushes" not in s


@pytest.mark.parametrize("argv, named", [
    (["--push-set", "paper-b", "--seed", "3"], "--seed does not apply to scenario 'circle-push' with --push-set paper-b"),
    (["--push-set", "paper-b", "--steps", "12"], "--steps = 12: expected at least"),
    (["--push-set", "paper-c"], "--push-set"),
])
def test_bad_uses_are_one_line_and_exit_2(argv, named, tmp_path, capsys) -> None:
    with pytest.raises(SystemExit) as e:  # argparse's choices end the parse
        code = main(["run", "circle-push", *argv, "--out", str(tmp_path / "x")])
        raise SystemExit(code)
    err = capsys.readouterr().err.strip().splitlines()
    assert e.value.code == EXIT_USAGE and named in err[-1]
    assert not (tmp_path / "x" / "summary.json").exists()


def test_push_set_elsewhere_is_refused_naming_it() -> None:
    from lipmpcc.studies import OptionNotApplicableError, check_options

    with pytest.raises(OptionNotApplicableError, match="--push-set does not apply to scenario 'overtake'"):
        check_options(RunOptions("overtake", push_set="paper-b"))
    with pytest.raises(InvalidInputError, match="paper-a or paper-b"):
        RunOptions("circle-push", push_set="paper-z")


def test_the_run_size_counts_the_runs_that_place_the_pushes() -> None:
    for robot in ("lip", "digit_like"):
        a = estimate_run_size(RunOptions("circle-push", robot=robot))
        b = estimate_run_size(RunOptions("circle-push", robot=robot, push_set="paper-b"))
        assert b.wall_s == pytest.approx(PAPER_B_PUSH_RUNS * a.wall_s) and b.amount == a.amount


SWEEP = {"study": "circle-push", "robot": "lip", "planners": ["mpcc"], "options": {"steps": 60},
         "axes": {"push_set": {"values": ["paper-a", "paper-b"]}, "push_scale": {"values": [1.0, 2.0]}}}


def test_a_sweep_varies_the_push_set_and_scales_paper_b_s_impulse() -> None:
    cases = parse_spec(SWEEP).cases()
    assert sorted({c["options"]["push_set"] for c in cases}) == ["paper-a", "paper-b"]
    b2 = next(c for c in cases if c["options"]["push_set"] == "paper-b" and c["params"]["push_scale"] == 2.0)
    assert case_options(b2).push_set == "paper-b" and case_options(b2).extra["push_scale"] == 2.0
    assert case_pushes(b2)[1]["impulse_Ns"] == pytest.approx(2.0 * 150.0 * 0.1)  # paper B's largest push, scaled


def test_a_sweep_of_paper_b_s_pushes_and_a_push_of_its_own_is_refused() -> None:
    raw = {**SWEEP, "options": {"steps": 60, "push_set": "paper-b"}, "axes": {"force": {"values": [100.0]}}}
    with pytest.raises(InvalidInputError, match="axes.force"):
        parse_spec(raw)


def test_a_robot_that_falls_before_a_pushed_footstep_gets_the_pushes_before_it(monkeypatch) -> None:
    """Paper B's pushes at 3x on fixed T (fast mode): the forward push fells the LIP before the backward push's
    footstep, so the run reports a fall with the one push applied (not an error about footsteps not reached)."""
    from lipmpcc import studies

    monkeypatch.setenv("LIPMPCC_FAST", "1")
    s = studies.run(RunOptions("circle-push", push_set="paper-b", extra={"push_scale": 3.0})).summary
    assert s["fell"] is True and s["survived"] is False and s["outcome"] == "fell"
    assert s["pushes"] == 1 and [r["push"] for r in s["paper_b_pushes"]] == ["forward"]
