"""``lipmpcc run stones|push --robot digit_like``: paper B on the full-body robot through the CLI."""

from __future__ import annotations

import json

import pytest

from lipmpcc.cli import main

pytestmark = pytest.mark.slow

REDUCED_FIELDS = {
    "scenario", "planner", "robot", "fell", "fall_step", "steps_completed", "step_rmse_m", "stones_violated",
    "step_duration_min_s", "step_duration_max_s", "solve_ms", "solver_failures",
}
FULL_BODY_FIELDS = {"wbc_ms", "qp_failures", "real_time_factor", "min_base_height_m", "distance_walked_m"}


def run(tmp_path, *args):
    out = tmp_path / "out"
    code = main(["run", *args, "--out", str(out)])
    summary = json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else None
    return code, summary, out


def test_stones_on_digit_like_writes_the_reduced_and_full_body_fields_and_a_video(tmp_path) -> None:
    code, s, out = run(tmp_path, "stones", "--robot", "digit_like", "--profile", "I", "--L", "0.2", "--W", "-0.15",
                       "--steps", "4", "--video")
    assert code == 0
    assert REDUCED_FIELDS | FULL_BODY_FIELDS <= set(s)
    assert (s["scenario"], s["planner"], s["robot"]) == ("stones", "alip-mpc", "digit_like")
    assert s["fell"] is False and s["fall_step"] is None and s["steps_completed"] == 4 and s["n_stones"] == 4
    assert 0.0 <= s["step_rmse_m"] <= 0.05 and s["stones_violated"] == 0 and s["solver_failures"] == 0
    assert s["paper_case"] == "I L=0.2 W=-0.15" and s["paper_rmse_m"] == 0.039
    assert 0 < s["wbc_ms"]["median"] <= s["wbc_ms"]["max"] and s["real_time_factor"] > 0
    assert s["qp_failures"] == 0 and s["min_base_height_m"] > 0.8 and s["distance_walked_m"] > 1.5
    assert s["model"]["z_c_m"] == pytest.approx(0.953, abs=0.01) and s["model"]["planner_rate_hz"] == 25.0
    assert (out / "footprints.png").exists() and (out / "durations_dcm.png").exists()
    videos = list(out.glob("stones.*"))
    assert len(videos) == 1 and videos[0].suffix in (".mp4", ".gif") and videos[0].stat().st_size > 10_000


def test_push_on_digit_like_with_alip_qp_applies_the_first_push(tmp_path) -> None:
    code, s, out = run(tmp_path, "push", "--robot", "digit_like", "--planner", "alip-qp", "--steps", "6")
    assert code == 0
    assert REDUCED_FIELDS | FULL_BODY_FIELDS <= set(s)
    assert s["scenario"] == "push" and s["planner"] == "alip-qp" and s["solver"] == "proxqp"
    assert s["pushes_applied"] == 1 and s["pushes"][0] == {"stone": 5, "force_N": [150.0, 0.0], "window_s": [0.1, 0.2]}
    assert isinstance(s["fell"], bool)
    assert (out / "push_response.png").exists()


@pytest.mark.parametrize(
    "args, word",
    [
        (["stones", "--robot", "digit_like", "--planner", "mpcc"], "--planner"),
        (["stones", "--robot", "digit_like", "--profile", "V"], "--profile"),
        (["stones", "--robot", "/no/such/robot.xml", "--steps", "2"], "robot.xml"),
        (["push", "--robot", "lip"], "--robot"),
    ],
)
def test_bad_full_body_options_exit_1_with_a_readable_line(tmp_path, capsys, args, word) -> None:
    code = main(["run", *args, "--out", str(tmp_path / "bad")])
    err = capsys.readouterr().err
    assert code == 1
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("lipmpcc: error:") and word in lines[0]
    assert "Traceback" not in err
