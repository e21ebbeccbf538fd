"""Issue 31's crossing pedestrian on ``digit_like`` (fixed T and timed), shortened to a 2.5 m path: the
pedestrian (r = 0.3 m, 0.55 m/s, as in the issue) crosses 1.4 m ahead of the start at 5 s, when the robot is
about to reach it; the robot gives way and then reaches the end, stands there and does not fall."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lipmpcc.cli import main

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("timed", [[], ["--step-duration-range", "0.3", "0.5"]], ids=["fixed-T", "timed"])
def test_digit_like_waits_for_the_crossing_pedestrian_and_reaches_the_end(tmp_path, timed) -> None:
    (tmp_path / "p.csv").write_text("x,y\n0,0\n2.5,0\n")
    (tmp_path / "o.json").write_text(json.dumps(
        [{"shape": "circle", "radius": 0.3, "position": [1.4, -2.75], "velocity": [0.0, 0.55]}]))
    out = tmp_path / "out"
    code = main(["run", "follow-path", "--robot", "digit_like", "--path", str(tmp_path / "p.csv"),
                 "--obstacles", str(tmp_path / "o.json"), "--duration", "15", "--out", str(out), *timed])
    s = json.loads((out / "summary.json").read_text())
    assert code == 0 and s["outcome"] == "completed" and s["reached_end"] is True and not s["fell"]
    assert s["progress_m"] >= 2.5 - 0.05
    # it met the pedestrian (the barrier acted: the whole body within 0.7 m of it) and kept clear of it
    assert 0.0 < s["min_body_clearance_m"] < 0.7
    # measured (loaded machine): fixed T at the end at 14.2 s, timed at 8.5 s; both 0.47-0.54 m clear
    assert s["path_end_time_s"] is not None and s["path_end_time_s"] < 15.0
    assert np.isfinite(s["solve_ms"]["median"]) and s["solver_failures"] == 0
