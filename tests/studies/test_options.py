"""RunResult.save: summary.json (numpy values as JSON, non-finite as null) and the figures."""

from __future__ import annotations

import json

import matplotlib.pyplot as plt
import numpy as np

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
