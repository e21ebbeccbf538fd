"""The one MPCC driver (issue 24): both MPCC planners run on it, and its fallback chain does the same for each
formulation."""

import math

import numpy as np
import pytest

from lipmpcc.exceptions import NoFallbackPlanError
from lipmpcc.paths import LinePath
from lipmpcc.planners.mpcc import FixedStepFormulation, MpccParams, MpccPlanner
from lipmpcc.planners.mpcc_driver import MpccDriver, MpccFormulation


def _failing(monkeypatch, planner) -> None:
    fail = lambda *a, **k: (False, "forced failure", 3, math.nan, None, None)  # noqa: E731
    monkeypatch.setattr(planner, "_solve_sqp", fail)
    monkeypatch.setattr(planner, "_solve_ipopt", fail)


def test_the_fixed_step_planner_is_the_driver_over_its_formulation() -> None:
    pl = MpccPlanner(LinePath((0.0, 0.0), (5.0, 0.0)), MpccParams.circle())
    assert isinstance(pl, MpccDriver) and isinstance(pl.formulation, FixedStepFormulation)
    for name in ("build", "select", "reach", "guess", "parameters", "solve_sqp", "solve_ipopt", "with_progress",
                 "mean_progress", "progress_start", "result", "replay"):
        assert callable(getattr(pl.formulation, name)), name
    assert pl.formulation.label == "mpcc" and set(MpccFormulation.__annotations__) >= {"label", "mpcc"}


def test_the_first_failed_solve_has_no_fallback_and_later_ones_replay(monkeypatch) -> None:
    """No previous plan: NoFallbackPlanError naming the formulation; with one, the replayed plan, counted."""
    pl = MpccPlanner(LinePath((0.0, 0.0), (5.0, 0.0)), MpccParams.circle())
    with monkeypatch.context() as m:
        _failing(m, pl)
        with pytest.raises(NoFallbackPlanError, match="mpcc/sqp"):
            pl.solve(np.zeros(5), 1)
    assert pl.failures == 1 and pl.solves == 1
    first = pl.solve(np.zeros(5), 1)
    assert first.found and not first.used_fallback
    _failing(monkeypatch, pl)
    x = pl.params.model.step(np.zeros(5), first.u0)
    res = pl.solve(x, -1, t_now=pl.params.model.T)
    assert res.used_fallback and not res.found and pl.failures == 2 and pl.last is res
    # the replay is the previous plan shifted by one step, from the new state
    np.testing.assert_allclose(res.inputs[:-1], first.inputs[1:])
    assert res.stance_side == -first.stance_side and res.held_by == []


def test_the_timed_planner_is_the_same_driver_over_its_formulation(monkeypatch) -> None:
    """The timed MPCC runs on the same driver: its first failure names it, a later one replays its plan."""
    from lipmpcc.planners.mpcc_timed import TimedFormulation, TimedMpccParams, TimedMpccPlanner

    pl = TimedMpccPlanner(LinePath((0.0, 0.0), (5.0, 0.0)), TimedMpccParams(MpccParams.circle()))
    assert isinstance(pl, MpccDriver) and isinstance(pl.formulation, TimedFormulation)
    assert type(pl)._retry is MpccPlanner._retry and type(pl)._fallback is MpccPlanner._fallback
    with monkeypatch.context() as m:
        _failing(m, pl)
        with pytest.raises(NoFallbackPlanError, match="mpcc-timed/sqp"):
            pl.solve(np.zeros(5), 1)
    first = pl.solve(np.zeros(5), 1)
    assert first.found
    _failing(monkeypatch, pl)
    res = pl.solve(first.states[1], -1, t_now=float(first.durations[0]))
    assert res.used_fallback and pl.failures == 2
    np.testing.assert_allclose(res.durations[:-1], first.durations[1:])


def test_one_pair_of_builders_builds_both_formulations_and_the_old_names_warn() -> None:
    """``build_sqp``/``build_ipopt`` take either formulation's parameters; the timed pair is a deprecated alias."""
    import importlib

    from lipmpcc.planners import mpcc
    from lipmpcc.planners.mpcc_timed import TimedMpccParams, n_timed_params

    timed = importlib.import_module("lipmpcc.planners.mpcc_timed")
    path = LinePath((0.0, 0.0), (5.0, 0.0))
    prm = TimedMpccParams(MpccParams.circle(jit=False))
    opti = mpcc.build_ipopt(path, prm, 1)
    assert opti["vars"][2].shape[0] == n_timed_params(prm, 1)  # (X, Z, P): the timed problem's parameters
    assert len(mpcc.build_ipopt(path, prm.mpcc, 1)["vars"]) == 4  # (X, U, P, X0): the fixed-step one's
    for old, new in (("build_timed_sqp", "build_sqp"), ("build_timed_ipopt", "build_ipopt")):
        with pytest.warns(DeprecationWarning, match=f"mpcc_timed.{old} moved to lipmpcc.planners.mpcc.{new}"):
            assert getattr(timed, old) is getattr(mpcc, new)
    with pytest.warns(DeprecationWarning, match="sources.mpcc_timed.TimedMpccFootstepSource moved"):
        from lipmpcc.planners.sources.mpcc_timed import TimedMpccFootstepSource
    from lipmpcc.planners.sources import mpcc as sources

    assert TimedMpccFootstepSource is sources.TimedMpccFootstepSource
