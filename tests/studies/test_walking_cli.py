"""``lipmpcc run walk`` / ``run stand`` (lipmpcc.studies.walking through the CLI): the full-body summary.json,
bad options, and the walk on the user's own Digit v3 file."""

from __future__ import annotations

import json
from pathlib import Path

import pytest


@pytest.mark.slow
def test_cli_walk_and_stand_write_full_body_summary(tmp_path) -> None:
    from lipmpcc.cli import main

    out = tmp_path / "walk"
    assert main(["run", "walk", "--robot", "digit_like", "--steps", "6", "--speed", "0.4", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"] == "walk" and s["planner"] == "capture-point" and s["robot"] == "digit_like"
    assert s["fell"] is False and s["steps"] == 6
    assert set(s["wbc_ms"]) == {"median", "p90", "max"}
    assert 0 < s["wbc_ms"]["median"] <= s["wbc_ms"]["p90"] <= s["wbc_ms"]["max"]
    assert isinstance(s["qp_failures"], int)
    assert s["real_time_factor"] > 0
    assert 0.5 < s["min_base_height_m"] < 1.2
    assert s["distance_walked_m"] > 0.3
    assert (out / "walk_top.png").stat().st_size > 0
    # the outcome fields (lipmpcc.studies.outcome), no obstacle: no clearance
    assert s["outcome"] == "completed" and s["collided"] is False and s["stopped_early"] is None
    assert s["min_clearance_m"] is None and s["min_body_clearance_m"] is None
    assert isinstance(s["relaxed_solves"], int) and isinstance(s["warnings"], list) and s["expected_outcome"] is None

    out = tmp_path / "stand"
    assert main(["run", "stand", "--robot", "digit_like", "--duration", "1.5", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"] == "stand" and s["fell"] is False
    for key in ("wbc_ms", "qp_failures", "real_time_factor", "min_base_height_m", "distance_walked_m"):
        assert key in s
    assert (out / "stand.png").stat().st_size > 0
    assert s["outcome"] == "completed" and s["collided"] is False and isinstance(s["warnings"], list)


@pytest.mark.slow
def test_cli_rejects_bad_options(tmp_path, capsys) -> None:
    from lipmpcc.cli import main

    assert main(["run", "walk", "--robot", "lip", "--out", str(tmp_path / "a")]) == 1
    assert "--robot" in capsys.readouterr().err
    assert main(["run", "walk", "--planner", "mpcc", "--out", str(tmp_path / "b")]) == 1
    assert "capture-point" in capsys.readouterr().err
    assert main(["run", "walk", "--speed", "7", "--steps", "2", "--out", str(tmp_path / "c")]) == 1
    assert "speed" in capsys.readouterr().err


@pytest.mark.slow
@pytest.mark.shared_model
def test_cli_walks_the_users_file(shared_digit_xml: Path, tmp_path: Path) -> None:
    """``lipmpcc run walk --robot PATH.xml`` on the unedited file."""
    from lipmpcc.cli import main

    out = tmp_path / "walk"
    args = ["run", "walk", "--robot", str(shared_digit_xml), "--steps", "6", "--speed", "0.4", "--out", str(out)]
    assert main(args) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["robot"] == "digit_v3" and s["fell"] is False and s["steps"] == 6
    assert s["qp_failures"] == 0 and s["distance_walked_m"] > 0.3
