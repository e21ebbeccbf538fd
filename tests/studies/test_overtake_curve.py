"""Overtaking on a curved path (issue 18): the 0.8 m/s obstacle on the S-bend of data/paths/, on the LIP.

Fixed T = 0.4 s cannot pass it (its path speed is at most 0.3 m / 0.4 s = 0.75 m/s); with each step's duration
in [0.3, 0.5] s the MPCC passes it without contact, as on the straight line."""

from __future__ import annotations

import json

import pytest

from lipmpcc.cli import main
from lipmpcc.paths import load_path_csv
from lipmpcc.resources import data_path

PATH = data_path("paths") / "s_bend.csv"
OBSTACLE = data_path("paths") / "s_bend_obstacle.json"


def test_the_s_bend_is_35_m_with_two_60_degree_bends() -> None:
    p = load_path_csv(PATH)
    assert p.length == pytest.approx(35.0, abs=0.05)
    assert json.loads(OBSTACLE.read_text()) == [{"shape": "circle", "radius": 0.25, "s0": 1.0, "speed": 0.8}]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    out = {}
    for name, extra in (("fixed", []), ("timed", ["--step-duration-range", "0.3", "0.5"])):
        d = tmp_path_factory.mktemp(name) / "run"
        code = main(["run", "overtake", "--path", str(PATH), "--obstacles", str(OBSTACLE), "--steps", "70", *extra,
                     "--out", str(d)])
        out[name] = (code, json.loads((d / "summary.json").read_text()))
    return out


def test_fixed_t_trails_and_the_timed_mpcc_overtakes_without_contact(runs) -> None:
    code, fixed = runs["fixed"]
    assert code == 0 and not fixed["overtook"] and not fixed["collided"] and not fixed["fell"]
    code, timed = runs["timed"]
    assert code == 0 and timed["overtook"] and not timed["collided"] and not timed["fell"]
    assert timed["min_clearance_m"] > 0.02 and timed["solver_failures"] == 0
    assert timed["executed_durations_s"]["median"] < 0.35  # faster steps, not longer ones
    speed = {k: s["progress_m"] / s["duration_s"] for k, s in (("fixed", fixed), ("timed", timed))}
    assert speed["fixed"] <= 0.75 + 1e-6 and speed["timed"] > 0.8 + 0.1  # [m/s] along the path
