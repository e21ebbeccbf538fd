"""lipmpcc.studies.run_size: absurd run lengths are refused up front with the estimated wall time and
the bound, unless --allow-long (issue 14)."""

from __future__ import annotations

import math

import pytest

from lipmpcc import config, studies
from lipmpcc.exceptions import InvalidInputError, RunTooLongError
from lipmpcc.studies import RunOptions
from lipmpcc.studies.applicability import FULL, REDUCED
from lipmpcc.studies.run_size import (
    FULL_S_PER_SIM_S,
    FULL_SETUP_S,
    MAX_WALL_S,
    REDUCED_S_PER_STEP,
    check_run_size,
    estimate_run_size,
    format_seconds,
)


@pytest.mark.parametrize("s, text", [(0.4, "0 s"), (42.0, "42 s"), (210.0, "3.5 min"), (7560.0, "2.1 h"),
                                     (4 * 86400.0, "4 days"), (3.156e9, "100 years"), (3.156e15, "1.0e+08 years"),
                                     (math.inf, "forever")])
def test_format_seconds(s: float, text: str) -> None:
    assert format_seconds(s) == text


@pytest.fixture(autouse=True)
def _full_mode():
    """The estimates below are of full runs, whatever LIPMPCC_FAST says."""
    with config.fast_mode_as(False):
        yield


def test_the_defaults_and_the_papers_runs_are_well_under_the_bound() -> None:
    for scenario in studies.names():
        size = estimate_run_size(RunOptions(scenario))
        assert 0 < size.wall_s < 120.0, (scenario, size)
        assert size.option == "" and size.value is None
    lip = estimate_run_size(RunOptions("circle"))
    assert (lip.kind, lip.unit, lip.amount) == (REDUCED, "steps", 120.0)  # paper A's 120 steps
    walk = estimate_run_size(RunOptions("walk"))
    assert (walk.kind, walk.unit, walk.amount) == (FULL, "simulated s", 20.0)
    assert walk.wall_s == pytest.approx(FULL_SETUP_S + 20.0 * FULL_S_PER_SIM_S)
    try:
        config.set_fast_mode(True)
        assert estimate_run_size(RunOptions("circle")).amount == 40.0
        assert estimate_run_size(RunOptions("circle", robot="digit_like")).amount == 10.0
    finally:
        config.set_fast_mode(None)


def test_the_length_comes_from_steps_or_duration() -> None:
    assert estimate_run_size(RunOptions("circle", robot="lip", steps=1000)).wall_s == pytest.approx(1000 * REDUCED_S_PER_STEP["circle"])
    both = estimate_run_size(RunOptions("walk", steps=10, duration=1e6))
    assert both.amount == pytest.approx(7.0) and both.option == "--duration"  # 10 steps end the run first
    assert estimate_run_size(RunOptions("stand", duration=100.0)).amount == 100.0
    assert estimate_run_size(RunOptions("overtake", robot="digit_like", planner="cartesian")).amount == 25.0
    stones = estimate_run_size(RunOptions("stones", robot="digit_like", steps=100))
    assert stones.unit == "simulated s" and stones.amount > 50.0


@pytest.mark.parametrize("opts, flag, words", [
    (RunOptions("walk", duration=1e9), "--duration", "15.8 years: 1e+09 simulated s"),
    (RunOptions("circle", robot="lip", steps=10**11), "--steps", "years: 1e+11 steps"),
    (RunOptions("circle", robot="lip", steps=10**6), "--steps", "13.9 h: 1e+06 steps"),
    (RunOptions("stand", duration=1e5), "--duration", "13.9 h"),
    (RunOptions("walk", steps=10**6), "--steps", "days"),
    (RunOptions("stones", robot="alip", steps=10**7), "--steps", "steps at ~0.06 s"),
])
def test_an_absurd_length_is_refused_with_the_estimate_and_the_bound(opts: RunOptions, flag: str, words: str) -> None:
    with pytest.raises(RunTooLongError) as e:
        check_run_size(opts)
    msg = str(e.value)
    assert isinstance(e.value, InvalidInputError) and e.value.name == flag
    assert msg.startswith(f"{flag} = ") and "expected a run of at most 1 h of wall time" in msg
    assert words in msg and msg.endswith("pass --allow-long to run it anyway)")
    assert e.value.wall_s > e.value.bound_s == MAX_WALL_S


def test_allow_long_and_a_higher_bound_let_it_run() -> None:
    opts = RunOptions("walk", duration=1e5)
    with pytest.raises(RunTooLongError):
        check_run_size(opts)
    assert check_run_size(RunOptions("walk", duration=1e5, allow_long=True)).amount == 1e5
    assert check_run_size(opts, max_wall_s=1e6).wall_s < 1e6


def test_studies_run_refuses_before_running(monkeypatch) -> None:
    ran = []
    monkeypatch.setattr(studies, "get", lambda name: ran.append)
    with pytest.raises(RunTooLongError, match="--steps = 100000000000"):
        studies.run(RunOptions("circle", robot="lip", steps=10**11))
    assert ran == []
    studies.run(RunOptions("circle", robot="lip", steps=10**11, allow_long=True))
    assert len(ran) == 1


def test_follow_path_is_sized_by_its_path(tmp_path) -> None:
    from lipmpcc.studies.path_scenarios import follow_path_duration, follow_path_steps
    from lipmpcc.studies.run_size import UNREADABLE_PATH_M

    wp = tmp_path / "wp.csv"
    wp.write_text("0,0\n40,0\n")  # 40 m
    lip = estimate_run_size(RunOptions("follow-path", path=str(wp)))
    assert (lip.kind, lip.unit, lip.amount) == (REDUCED, "steps", float(follow_path_steps(40.0)))
    full = estimate_run_size(RunOptions("follow-path", robot="digit_like", path=str(wp)))
    assert (full.kind, full.amount) == (FULL, follow_path_duration(40.0))
    assert estimate_run_size(RunOptions("follow-path", path=str(wp), steps=7)).amount == 7.0
    bad = estimate_run_size(RunOptions("follow-path", path=str(tmp_path / "missing.csv")))
    assert bad.amount == float(follow_path_steps(UNREADABLE_PATH_M))  # the study reports the file's error


def test_a_long_stone_file_is_counted_in_the_estimate(tmp_path) -> None:
    """``lipmpcc run stones --stones LONG.csv``: the file's stones, not the profile's, set the length (a
    1000-stone course is announced as the minutes it takes, not as a default course)."""
    from lipmpcc.studies import RunOptions, estimate_run_size
    from lipmpcc.studies.run_size import NOTICE_WALL_S

    rows = "\n".join(f"{1.4 + 0.3 * i:.2f},{0.14 if i % 2 else -0.14:.2f}" for i in range(1000))
    (tmp_path / "long.csv").write_text("x,y\n" + rows + "\n")
    size = estimate_run_size(RunOptions("stones", stones=str(tmp_path / "long.csv")))
    assert size.amount >= 1000 and size.wall_s > NOTICE_WALL_S
    assert estimate_run_size(RunOptions("stones")).amount < 100
