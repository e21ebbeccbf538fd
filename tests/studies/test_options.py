"""RunResult.save: summary.json (numpy values as JSON, non-finite as null) and the figures."""

from __future__ import annotations

import json

import matplotlib.pyplot as plt
import numpy as np
import pytest

from lipmpcc.studies import RunOptions, RunResult, get, names


def test_save_writes_the_summary_and_the_figures_and_closes_them(tmp_path) -> None:
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    res = RunResult(
        summary={"a": np.float64(1.5), "n": np.int64(3), "ok": np.bool_(True), "x": np.array([1.0, np.nan]),
                 "t": (1, 2), "inf": float("inf")},
        figures={"line": fig},
    )
    path = res.save(tmp_path / "out")
    assert path == tmp_path / "out" / "summary.json"
    assert json.loads(path.read_text()) == {"a": 1.5, "n": 3, "ok": True, "x": [1.0, None], "t": [1, 2], "inf": None}
    assert (tmp_path / "out" / "line.png").stat().st_size > 0
    assert not plt.fignum_exists(fig.number)


def test_registry_names_every_study() -> None:
    assert names() == ["circle", "circle-push", "overtake", "stones", "push", "walk", "stand"]
    assert get("stones").__module__ == "lipmpcc.studies.stepping_stones"
    assert RunOptions("walk").seed is None and RunOptions("walk").rng_seed == 0


def test_a_figure_that_cannot_be_written_leaves_no_new_summary(tmp_path, monkeypatch) -> None:
    """save writes the figures first and summary.json last, through a renamed file: a figure that fails
    leaves no summary.json (and no temporary file), and the figures are closed all the same."""
    fig, _ = plt.subplots()

    def broken(*args, **kwargs):
        raise OSError("No space left on device")

    monkeypatch.setattr(fig, "savefig", broken)
    with pytest.raises(OSError, match="No space left"):
        RunResult(summary={"fell": False}, figures={"f": fig}).save(tmp_path)
    assert list(tmp_path.iterdir()) == [] and not plt.fignum_exists(fig.number)


def test_run_outcome_reads_outcome_or_the_flags_in_their_precedence() -> None:
    from lipmpcc.studies import OUTCOMES, run_outcome

    assert set(OUTCOMES) == {"completed", "fell", "collided", "stopped_early"}
    assert run_outcome({}) == "completed"  # a summary without the fields: missing = False/None
    assert run_outcome({"fell": False, "collided": False, "stopped_early": None}) == "completed"
    assert run_outcome({"fell": True}) == "fell"
    assert run_outcome({"fell": np.bool_(True)}) == "fell"
    assert run_outcome({"stopped_early": "first solve failed"}) == "stopped_early"
    assert run_outcome({"fell": True, "stopped_early": "fell"}) == "fell"
    assert run_outcome({"collided": True, "fell": True, "stopped_early": "x"}) == "collided"
    assert run_outcome({"outcome": "collided"}) == "collided"  # the summary's own word first
    assert run_outcome({"outcome": "completed", "fell": True}) == "completed"
    assert run_outcome({"outcome": "exploded", "fell": True}) == "fell"  # not an outcome: the flags


@pytest.mark.parametrize("kw, message", [
    (dict(steps="3"), r"--steps = '3': expected an integer >= 1"),
    (dict(seed=-1), r"--seed = -1: expected an integer >= 0"),
    (dict(obstacle_speed="fast"), r"--obstacle-speed = 'fast': expected a finite number \[m/s\]"),
    (dict(duration=float("nan")), r"--duration = nan"),
    (dict(video=1), r"--video = 1: expected True or False"),
    (dict(cop_range=(0.1,)), r"--cop-range"),
    (dict(robot=5), r"--robot = 5: expected text"),
])
def test_run_options_name_an_option_of_the_wrong_type(kw, message) -> None:
    """The Python API refuses what the CLI's parser would (a study would fail deep inside otherwise)."""
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies import RunOptions

    with pytest.raises(InvalidInputError, match=message):
        RunOptions("circle", **kw)


def test_run_options_accept_numpy_numbers() -> None:
    from lipmpcc.studies import RunOptions

    o = RunOptions("circle", steps=np.int64(3), seed=np.int32(2), obstacle_speed=np.float32(0.5), cop_range=[0, 0])
    assert (o.steps, o.seed, o.obstacle_speed, o.cop_range) == (3, 2, 0.5, (0.0, 0.0))
    assert type(o.steps) is int and type(o.obstacle_speed) is float
