"""lipmpcc.studies.stone_metrics: paper B's metrics, once for both robots — the ALIP loop's log scored by
loop_metrics, the stones reached (full-body runs, recorded in that log, are scored the same way in
tests/studies/test_stepping_stones.py)."""

from __future__ import annotations

from lipmpcc.studies.stepping_stones import run_case
from lipmpcc.studies.stone_metrics import stones_reached
from lipmpcc.terrain import N_APPROACH, make_profile


def test_the_stones_reached_are_the_touch_downs_on_stones() -> None:
    log, m = run_case("alip-mpc", make_profile("I", None, 0.4, 0.15).head(5))
    assert not m["fell"] and log.n_steps == N_APPROACH + 5
    assert stones_reached(log) == 5 == sum(bool(log.sequence.is_stone[int(i)]) for i in log.step_index)
