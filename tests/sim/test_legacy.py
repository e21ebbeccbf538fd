"""lipmpcc.sim._legacy.Rates: the deprecated loop rates (kept for one release), imported from their home
without a warning (the old path ``lipmpcc.sim.robot_sim.Rates`` warns: test_robot_sim.py)."""

from __future__ import annotations

import warnings

import pytest

from lipmpcc.exceptions import ParameterError


def test_rates_derive_steps_and_ticks() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        from lipmpcc.sim._legacy import Rates

    r = Rates(sim_hz=1000.0, wbc_hz=250.0, planner_hz=15.0)
    assert r.timestep == pytest.approx(1e-3) and r.sim_steps_per_wbc == 4
    assert r.wbc_ticks_per_plan == 17  # 250 / 15 rounded
    assert Rates(wbc_hz=400.0, planner_hz=400.0).wbc_ticks_per_plan == 1


@pytest.mark.parametrize("kw, name", [({"sim_hz": 0.0}, "sim_hz"), ({"planner_hz": float("inf")}, "planner_hz"),
                                      ({"wbc_hz": 300.0}, "wbc_hz"), ({"planner_hz": 500.0}, "planner_hz"),
                                      ({"sim_hz": True}, "sim_hz")])
def test_bad_rates_are_named(kw: dict, name: str) -> None:
    from lipmpcc.sim._legacy import Rates

    with pytest.raises(ParameterError, match=name):
        Rates(**kw)
