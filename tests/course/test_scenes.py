"""The seeded random scenes of issue 31's benchmark (lipmpcc.course.scenes)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lipmpcc.course.scenes import (
    OBSTACLE_KINDS,
    Scene,
    SceneRun,
    SceneSpec,
    benchmark_report,
    judge,
    make_scene,
    reached_end,
    success_table,
    write_scene,
)
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.obstacles import obstacles_from_json
from lipmpcc.paths import load_path_csv


def test_same_seed_same_scene_other_seed_other_scene() -> None:
    a, b, c = make_scene(3), make_scene(3), make_scene(4)
    assert np.array_equal(a.waypoints, b.waypoints) and a.obstacles == b.obstacles and a.kinds == b.kinds
    assert not np.array_equal(a.waypoints, c.waypoints)


@pytest.mark.parametrize("seed", range(12))
def test_scenes_are_valid(seed: int) -> None:
    spec = SceneSpec()
    sc = make_scene(seed, spec)
    assert sc.length == pytest.approx(spec.length, rel=1e-3)
    assert np.allclose(sc.waypoints[0], 0.0) and sc.waypoints[1, 1] == 0.0  # starts at the origin heading +x
    assert spec.n_obstacles[0] <= len(sc.obstacles) <= spec.n_obstacles[1]
    assert set(sc.kinds) <= set(OBSTACLE_KINDS)
    for item, kind in zip(sc.obstacles, sc.kinds):
        assert spec.radius[0] <= item["radius"] <= spec.radius[1]
        if kind == "ahead":
            assert spec.ahead_speed[0] <= item["speed"] <= spec.ahead_speed[1]
        elif kind == "oncoming":
            assert spec.oncoming_speed[0] <= -item["speed"] <= spec.oncoming_speed[1]
        else:
            q = np.array(item["position"])
            assert np.linalg.norm(q) >= spec.clear_start  # not on the robot at the start
            speed = np.linalg.norm(item["velocity"])
            if kind == "static":
                assert speed == 0.0
                d = np.min(np.linalg.norm(sc.path.sample(2000) - q, axis=1))
                assert d <= spec.static_offset + 0.02
            else:
                assert spec.crossing_speed[0] - 2e-3 <= speed <= spec.crossing_speed[1] + 2e-3


def test_kinds_of_many_seeds_cover_all_four() -> None:
    kinds = {k for s in range(20) for k in make_scene(s).kinds}
    assert kinds == set(OBSTACLE_KINDS)


def test_written_files_read_back_in_the_cli_formats(tmp_path) -> None:
    sc = make_scene(1)
    csv, js = write_scene(sc, tmp_path)
    path = load_path_csv(csv)
    assert path.length == pytest.approx(sc.length, rel=1e-6)
    obs = obstacles_from_json(js, path)
    assert len(obs) == len(sc.obstacles)
    assert json.loads("\n".join(l for l in js.read_text().splitlines() if not l.startswith("#"))) == sc.obstacles


def test_bad_inputs_are_one_line_errors() -> None:
    with pytest.raises(InvalidInputError, match="seed"):
        make_scene(-1)
    with pytest.raises(InvalidInputError, match="kinds"):
        SceneSpec(kinds=("flying",))
    with pytest.raises(InvalidInputError, match="length"):
        SceneSpec(length=3.0)


def _scene() -> Scene:
    return make_scene(0, SceneSpec(kinds=("ahead",), n_obstacles=(1, 1)))


def test_judge_success_trailing_stall_and_contact() -> None:
    sc = _scene()
    L = sc.length
    assert judge({"stopped_reason": "end of path", "progress_m": L - 0.1, "min_clearance_m": 0.1}, sc) == (True, "ok")
    ob = sc.obstacles[0]
    t_end = 50.0
    s_ob = ob["s0"] + ob["speed"] * t_end
    assert judge({"progress_m": s_ob - 1.0, "duration_s": t_end, "min_clearance_m": 0.1}, sc) == (True, "trailing")
    ok, why = judge({"progress_m": 0.5, "duration_s": t_end, "min_clearance_m": 0.1}, sc)
    assert not ok and why.startswith("stalled")
    ok, why = judge({"stopped_reason": "end of path", "progress_m": L, "min_clearance_m": -0.01}, sc)
    assert not ok and why.startswith("collided")
    # the outcome fields, where the run has them, are trusted
    assert not reached_end({"reached_end": False, "stopped_reason": "end of path"}, L)
    assert judge({"reached_end": False, "outcome": "trailing", "progress_m": 1.0}, sc) == (True, "trailing")
    # a failure says what and where, in the run's own words where it has them
    ok, why = judge({"reached_end": False, "outcome": "incomplete", "progress_m": 17.5}, sc)
    assert not ok and why == f"incomplete at 17.50 m of {L:.2f} m"
    ok, why = judge({"reached_end": False, "outcome": "stalled", "progress_m": 2.0,
                     "stall": {"binding": {"kind": "obstacle"}}}, sc)
    assert not ok and why == f"stalled at 2.00 m of {L:.2f} m (binding: obstacle)"
    ok, why = judge({"fell": True, "fall_time_s": 78.5, "reached_end": True, "progress_m": L}, sc)
    assert not ok and why == f"fell at 78.5 s, {L:.2f} m of {L:.2f} m after reaching the end"


def test_success_table_counts_each_kind_and_all() -> None:
    runs = [SceneRun(0, "lip", "fixed T", "follow-path", ["static", "crossing"], {}, True, "ok"),
            SceneRun(1, "lip", "fixed T", "follow-path", ["static"], {}, False, "stalled")]
    rows = {r["kind"]: r for r in success_table(runs)}
    assert rows["static"]["n"] == 2 and rows["static"]["ok"] == 1
    assert rows["crossing"]["n"] == 1 and rows["all"]["n"] == 2
    assert 0.0 <= rows["all"]["wilson_lo"] <= 0.5 <= rows["all"]["wilson_hi"] <= 1.0


def test_benchmark_report_lists_rates_failures_and_distributions() -> None:
    runs = [SceneRun(0, "lip", "timed", "overtake", ["crossing"], {"solve_ms": {"median": 5.0, "p90": 9.0},
                                                                    "min_clearance_m": 0.1}, True, "ok"),
            SceneRun(1, "lip", "timed", "overtake", ["static"], {"solve_ms": {"median": 7.0, "p90": 12.0},
                                                                 "min_clearance_m": 0.04}, False, "stalled at 2.00 m of 19.00 m")]
    text = benchmark_report(runs)
    assert "| lip | timed | overtake | all | 1 / 2 | 50 % |" in text
    assert "seed 1 (static), lip, timed, overtake: stalled at 2.00 m of 19.00 m" in text
    assert "solve median [ms] min 5" in text and "clearance [m] min 0.04" in text
