"""``lipmpcc run stones`` / ``lipmpcc run push`` through the CLI entry point."""

from __future__ import annotations

import json

import pytest

from lipmpcc.cli import main
from lipmpcc.terrain import paper_case_path

FIELDS = {
    "scenario", "planner", "robot", "fell", "fall_step", "steps_completed", "step_rmse_m", "stones_violated",
    "step_duration_min_s", "step_duration_max_s", "solve_ms", "solver_failures",
}


def run(tmp_path, *args):
    out = tmp_path / "out"
    code = main(["run", *args, "--out", str(out), "--replace"])  # each call replaces the last run whole
    summary = json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else None
    return code, summary, out


def test_stones_profile_I_with_alip_mpc(tmp_path):
    code, s, out = run(tmp_path, "stones", "--profile", "I", "--L", "0.55", "--W", "-0.15", "--steps", "10")
    assert code == 0
    assert FIELDS <= set(s)
    assert (s["scenario"], s["planner"], s["robot"]) == ("stones", "alip-mpc", "alip")
    assert s["fell"] is False and s["fall_step"] is None and s["steps_completed"] == 10
    assert 0.0 <= s["step_rmse_m"] <= 0.04 and s["stones_violated"] == 0 and s["solver_failures"] == 0
    assert 0.35 <= s["step_duration_min_s"] <= s["step_duration_max_s"] <= 0.65 + 1e-9
    assert set(s["solve_ms"]) >= {"median", "p90", "max"} and s["solve_ms"]["median"] > 0
    assert s["paper_rmse_m"] == 0.022 and s["L"] == 0.55 and s["W"] == -0.15
    assert (out / "footprints.png").exists() and (out / "durations_dcm.png").exists()


def test_stones_random_profile_with_alip_qp(tmp_path):
    code, s, _ = run(tmp_path, "stones", "--profile", "iv", "--seed", "2", "--planner", "alip-qp", "--steps", "8")
    assert code == 0
    assert s["planner"] == "alip-qp" and s["profile"] == "IV" and s["seed"] == 2 and s["solver"] == "proxqp"
    assert isinstance(s["fell"], bool) and s["n_stones"] == 8


def test_stones_from_a_file(tmp_path):
    path = paper_case_path("II", 3)
    code, s, _ = run(tmp_path, "stones", "--stones", str(path), "--steps", "6")
    assert code == 0 and s["stones_file"] == str(path) and s["profile"] is None and s["fell"] is False


def test_push_with_both_planners(tmp_path):
    code, s, out = run(tmp_path, "push", "--steps", "8")
    assert code == 0 and s["scenario"] == "push" and len(s["pushes"]) == 4
    assert s["pushes"][0] == {"stone": 5, "force_N": [150.0, 0.0], "window_s": [0.1, 0.2]}
    assert s["fell"] is False  # the forward push at stone 5 is absorbed
    assert s["step_duration_min_s"] < 0.45  # by a quicker step (paper B Fig. 7)
    assert (out / "push_response.png").exists()
    code, q, _ = run(tmp_path, "push", "--planner", "alip-qp", "--steps", "8")
    assert code == 0 and q["planner"] == "alip-qp" and isinstance(q["fell"], bool)


def test_push_with_a_foot_survives_every_push(tmp_path):
    """``--cop-range``: the ALIP-MPC plans the centre of pressure in a 0.12 x 0.05 m box; the point
    foot (the default on the ALIP model) falls at the backward push."""
    code, s, _ = run(tmp_path, "push", "--cop-range", "0.06", "0.025")
    assert code == 0 and s["model"]["cop_range_m"] == [0.06, 0.025]
    assert s["fell"] is False and s["steps_completed"] == s["n_stones"] >= 22 and s["solver_failures"] == 0
    code, p, _ = run(tmp_path, "push", "--cop-range", "0", "0", "--steps", "12")
    assert code == 0 and p["model"]["cop_range_m"] == [0.0, 0.0] and p["fell"] is True


@pytest.mark.parametrize(
    "args, word",
    [
        (["push", "--cop-range", "0.3", "0.02"], "--cop-range"),
        (["push", "--cop-range", "-0.01", "0.02"], "--cop-range"),
        (["stones", "--planner", "alip-qp", "--cop-range", "0.05", "0.02"], "--cop-range"),
        (["stones", "--profile", "V"], "--profile"),
        (["stones", "--planner", "mpcc"], "--planner"),
        (["stones", "--robot", "lip"], "--robot"),
        (["push", "--robot", "lip"], "--robot"),
        (["push", "--planner", "capture-point"], "--planner"),
        (["stones", "--L", "0.9"], "--L"),
        (["stones", "--W", "0.5"], "--W"),
        (["stones", "--stones", "/no/such/file.csv"], "stones file"),
        (["stones", "--steps", "40"], "--steps"),
        (["push", "--steps", "30"], "--steps"),
    ],
)
def test_bad_option_values_exit_1_with_a_readable_line(tmp_path, capsys, args, word):
    code = main(["run", *args, "--out", str(tmp_path / "bad")])
    err = capsys.readouterr().err
    assert code == 1
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("lipmpcc: error:") and word in lines[0]
    assert "Traceback" not in err


def test_bad_stone_file_content(tmp_path, capsys):
    f = tmp_path / "nan.csv"
    f.write_text("x,y\n1.45,nan\n")
    code = main(["run", "stones", "--stones", str(f), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 1 and "finite" in err and "nan.csv line 2" in err


def test_a_stone_file_is_walked_to_its_end(tmp_path):
    """More stones than the paper's 32 in a file, no --steps: every stone is walked (it stopped at the
    32nd without a word), and the summary says how many were reached of how many."""
    from lipmpcc.terrain import make_profile

    seq = make_profile("I", L=0.4, W=0.15, n=40)
    f = tmp_path / "forty.csv"
    f.write_text("x,y\n" + "\n".join(f"{x:.6f},{y:.6f}" for x, y in seq.centers))
    code, s, _ = run(tmp_path, "stones", "--stones", str(f))
    assert s["n_stones"] == 40 and s["stones_total"] == 40 and s["stones_available"] == 40
    assert s["stones_reached"] == 40 and s["fell"] is False and s["outcome"] == "completed" and code == 0
    code, s, _ = run(tmp_path / "few", "stones", "--stones", str(f), "--steps", "5")
    assert s["stones_total"] == 5 and s["stones_reached"] == 5 and s["stones_available"] == 40


def test_the_point_foot_push_test_is_an_expected_failure(tmp_path):
    """Paper B's push test with the ALIP-MPC on a point foot falls (it cannot survive the backward push):
    a known baseline, marked expected_outcome "fell"; with a foot it survives and has no such mark."""
    code, s, _ = run(tmp_path, "push")
    assert s["fell"] is True and s["outcome"] == "fell" and s["expected_outcome"] == "fell"
    assert s["stones_reached"] < s["stones_total"] and s["stopped_early"] is None
    code, s, _ = run(tmp_path / "foot", "push", "--cop-range", "0.06", "0.025")
    assert s["fell"] is False and s["outcome"] == "completed" and s["expected_outcome"] is None
    assert s["stones_reached"] == s["stones_total"] and s["collided"] is False and s["relaxed_solves"] == 0


def test_expected_outcomes_of_the_baselines():
    from lipmpcc.studies.stepping_stones import expected_outcome

    assert expected_outcome("push", "alip-mpc", (0.0, 0.0)) == "fell"
    assert expected_outcome("push", "alip-qp", (0.0, 0.0)) == "fell"
    assert expected_outcome("push", "alip-mpc", (0.06, 0.025)) is None
    assert expected_outcome("stones", "alip-mpc", (0.0, 0.0)) is None
