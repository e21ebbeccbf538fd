"""The stone field on digit_like (issue 29): the ALIP study's planner, unchanged, behind paper B's full-body
footstep source, crosses a seeded field in MuJoCo with every measured sole on a stone (``lipmpcc run stone-field
--robot digit_like``)."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.planners.stone_field import StoneFieldPlanner
from lipmpcc.stone_field import make_stone_field
from lipmpcc.studies.stone_field_full_body import FieldSolver, _scene, field_on_robot
from lipmpcc.terrain import approach_footholds


def test_the_solver_counts_touch_downs_and_the_scene_holds_every_stone() -> None:
    fld = make_stone_field(2, length=1.5)
    moved = field_on_robot(fld, np.array([0.1, -0.02]))
    assert np.allclose(moved.centers - fld.centers, [0.1, -0.02]) and moved.n_stones == fld.n_stones
    seq = _scene(approach_footholds(), moved)
    assert int(seq.is_stone.sum()) == fld.n_stones and np.all(np.diff(seq.centers[6:, 0]) >= 0)
    solver = FieldSolver(StoneFieldPlanner(fld))
    sigma = solver.params.sigma_nom
    z = np.array([0.3 / (sigma - 1.0), -0.28 / (sigma + 1.0)])  # a periodic walk's initial DCM, right swing next
    entry = np.array([1.05, 0.14])
    res = solver.solve(entry + z, entry, +1, 0.0, [])
    assert res.success and fld.stone_at(res.next_foothold) is not None and solver._step == 0
    nxt = np.asarray(res.next_foothold)
    solver.solve(nxt + z * np.array([1.0, -1.0]), nxt, -1, 0.0, [])
    assert solver._step == 1 and len(solver.planner.choices) == 2

@pytest.mark.slow
def test_lipmpcc_run_stone_field_on_digit_like_writes_the_summary(tmp_path) -> None:
    import json

    from lipmpcc.cli import main

    out = tmp_path / "fb"
    code = main(["run", "stone-field", "--robot", "digit_like", "--seed", "2", "--out", str(out)])
    s = json.loads((out / "summary.json").read_text())
    # completed: every measured sole on a stone up to the goal, no fall (studies.stone_field.judge_log)
    assert code == 0 and s["outcome"] == "completed" and s["robot"] == "digit_like" and s["reached_end"]
    assert s["field_steps"] >= 8 and s["fell"] is False
    assert s["cop_range"] == [0.06, 0.025] and "qp_failures" in s and (out / "field.png").is_file()
    assert (out / "replay.npz").is_file()  # lipmpcc replay shows it
    assert main(["run", "stone-field", "--robot", "digit_like", "--planner", "stone-field-milp",
                 "--out", str(tmp_path / "x")]) == 1  # the MILP chooser: the ALIP only
